"""Feedback HTML that nothing a student wrote can script: each page rebuilt from an allow-list.

A fresh head (charset, a Content-Security-Policy that lets nothing run, frame or load, the title and
style sheets) and the old body through ammonia (nh3) with allowed tags, attributes and URL schemes.
nbconvert's own ``sanitize_html`` is not enough in nbgrader's feedback template (Markdown cells raw,
an unquoted ``width`` metadata); why, and what it costs: docs/grading-internals.md, "Output a
student wrote, in a browser".
"""

from __future__ import annotations

import html
import os
import re
import stat
import sys
from pathlib import Path
from typing import Dict, List, Optional, Sequence, Set, Tuple

from hri_teleop.grading.run.untrusted_files import UntrustedFileError, read_regular, walk_regular

__all__ = ["CSP", "ALLOWED_TAGS", "HTML_SUFFIXES", "FEEDBACK_CAP_BYTES", "MAX_TAGS", "sanitize_document", "sanitize_feedback", "main"]

#: The page may style itself and show data: images; nothing else loads or runs.
CSP = ("default-src 'none'; style-src 'unsafe-inline'; img-src data:; font-src data:; base-uri 'none'; "
       "form-action 'none'; frame-src 'none'")
ALLOWED_TAGS = frozenset({
    "a", "abbr", "b", "blockquote", "br", "caption", "cite", "code", "col", "colgroup", "dd", "del", "details",
    "dfn", "div", "dl", "dt", "em", "figcaption", "figure", "h1", "h2", "h3", "h4", "h5", "h6", "hr", "i", "img",
    "ins", "kbd", "li", "mark", "ol", "p", "pre", "q", "s", "samp", "small", "span", "strike", "strong", "sub",
    "summary", "sup", "table", "tbody", "td", "tfoot", "th", "thead", "tr", "tt", "u", "ul", "var",
})
_ANY_TAG_ATTRIBUTES = frozenset({"class", "id", "title", "lang", "dir", "align", "style"})
_TAG_ATTRIBUTES = {
    "a": frozenset({"href", "name"}),
    "img": frozenset({"src", "alt", "width", "height"}),
    "td": frozenset({"colspan", "rowspan", "valign"}), "th": frozenset({"colspan", "rowspan", "valign", "scope"}),
    "col": frozenset({"span"}), "colgroup": frozenset({"span"}),
    "ol": frozenset({"start", "type", "reversed"}), "li": frozenset({"value"}),
}
_DATA_IMAGE = re.compile(r"data:image/(png|jpeg|gif|webp|svg\+xml);base64,[A-Za-z0-9+/=\s]*\Z", re.IGNORECASE)
_HREF = re.compile(r"(https?:|mailto:|#|\./|[^:]*(/|\Z))", re.IGNORECASE)
_NUMBER = re.compile(r"\d{1,5}%?\Z")
#: Files the feedback folder may hold that a browser would run as a page.
HTML_SUFFIXES = (".html", ".htm", ".xhtml", ".shtml", ".svg", ".xml", ".mht", ".mhtml")
#: A feedback page larger than this (outputs and images included) is replaced by a note.
FEEDBACK_CAP_BYTES = 64 * 1024 ** 2
_BODY = re.compile(r"<body\b[^>]*>(.*)</body\s*>", re.IGNORECASE | re.DOTALL)
_BODY_START = re.compile(r"<body\b[^>]*>", re.IGNORECASE)
_TITLE = re.compile(r"<title\b[^>]*>(.*?)</title\s*>", re.IGNORECASE | re.DOTALL)
_PAGE_TAGS = re.compile(r"</?(html|head|body)\b[^>]*>", re.IGNORECASE)
#: A body with more tags than this is shown as escaped text (ammonia takes seconds per 50 000 nested tags;
#: a page of the course has a few hundred, a 60-row DataFrame about 1 000).
MAX_TAGS = 50_000
_STYLE = re.compile(r"<style\b[^>]*>(.*?)</style\s*>", re.IGNORECASE | re.DOTALL)


def _attribute_allowed(tag: str, name: str, value: str) -> bool:
    """The allow-list above, and only safe values for the URL and size attributes."""
    if name not in _ANY_TAG_ATTRIBUTES and name not in _TAG_ATTRIBUTES.get(tag, frozenset()):
        return False
    value = value.strip()
    if tag == "img" and name == "src":
        return bool(_DATA_IMAGE.match(value))
    if tag == "a" and name == "href":
        return bool(_HREF.match(value)) and not value.lower().startswith(("javascript:", "data:", "vbscript:"))
    if name in ("width", "height", "colspan", "rowspan", "span", "start", "value"):
        return bool(_NUMBER.match(value))
    return True


def _attribute_value(tag: str, name: str, value: str) -> Optional[str]:
    """nh3's attribute filter (after its allow-list): ``value``, or None to drop the attribute."""
    return value if _attribute_allowed(tag, name, value) else None


def _clean_body(body: str) -> str:
    """The body through ammonia (nh3: html5ever, the browsers' parsing, in linear time): allowed tags and
    attributes only, ``<script>`` and ``<style>`` gone with their content, other tags gone, their text kept."""
    import nh3  # noqa: PLC0415 - make grade's course mode only

    attributes: Dict[str, Set[str]] = {"*": set(_ANY_TAG_ATTRIBUTES)}
    attributes.update({tag: set(names) for tag, names in _TAG_ATTRIBUTES.items()})
    body = _PAGE_TAGS.sub("", body)
    if body.count("<") > MAX_TAGS:
        return (f"<p>This page held more than {MAX_TAGS} tags: the grader shows its HTML as text.</p>"
                f"<pre>{html.escape(body)}</pre>")
    return str(nh3.clean(body, tags=set(ALLOWED_TAGS),
                         clean_content_tags={"script", "style", "template", "noscript", "xmp", "noembed"},
                         attributes=attributes, attribute_filter=_attribute_value, strip_comments=True,
                         url_schemes={"http", "https", "mailto", "data"}))


def sanitize_document(text: str) -> str:
    """``text`` (an HTML page) rebuilt safe: a head of our own (charset, CSP, title, the head's style sheets
    that cannot leave their element) and the body through the allow-list. Parsing ``text`` wrongly can cost
    readability only: every part written out is escaped or cleaned."""
    match = _BODY.search(text)
    start = _BODY_START.search(text)
    head_text = text[:start.start()] if start else ""
    body = match.group(1) if match else (text[start.end():] if start else text)
    title = _TITLE.search(head_text)
    styles = [css for css in _STYLE.findall(head_text) if "</style" not in css.lower() and "<!--" not in css]
    head = ('<meta charset="utf-8">\n'
            f'<meta http-equiv="Content-Security-Policy" content="{html.escape(CSP)}">\n'
            f"<title>{html.escape(html.unescape(title.group(1).strip()) if title else 'feedback')}</title>\n"
            + "".join(f"<style>{css}</style>\n" for css in styles))
    return f"<!DOCTYPE html>\n<html>\n<head>\n{head}</head>\n<body>\n{_clean_body(body)}\n</body>\n</html>\n"


def _rewrite(path: Path, root: Path) -> str:
    """Rewrite one page under ``root`` in place (a new file, never through a link): "" or why it was replaced."""
    try:
        text = read_regular(path, FEEDBACK_CAP_BYTES, root=root).decode("utf-8", "replace")
        page, why = sanitize_document(text), ""
    except UntrustedFileError as exc:
        why = str(exc).replace(str(root), "").lstrip("/")
        page = ('<!DOCTYPE html><html><head><meta charset="utf-8">'
                f'<meta http-equiv="Content-Security-Policy" content="{html.escape(CSP)}"><title>feedback</title>'
                f"</head><body><p>This feedback page was not kept: {html.escape(why)}.</p></body></html>\n")
    tmp = path.with_name(f".{path.name}.sanitized")
    if tmp.is_symlink() or tmp.exists():
        tmp.unlink()
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW | os.O_CLOEXEC, 0o644)
    with os.fdopen(fd, "w", encoding="utf-8") as fh:
        fh.write(page)
    os.replace(tmp, path)  # replaces a link there too, never writes through it
    return why


def sanitize_feedback(folder: Path) -> List[Tuple[str, str]]:
    """Every page below ``folder`` (a student's feedback) rewritten by :func:`sanitize_document`; links and
    special files with a page's suffix removed. (relative path, what was wrong) of those not kept as they were."""
    problems: List[Tuple[str, str]] = []
    if not folder.is_dir() or folder.is_symlink():
        return problems
    for rel, kind in list(walk_regular(folder)):
        path = folder / rel
        if not rel.lower().endswith(HTML_SUFFIXES) or kind == "d":
            continue
        if kind != "f":  # a link or a FIFO named like a page: gone, not opened
            if not stat.S_ISDIR(os.lstat(path).st_mode):
                path.unlink()
            problems.append((rel, kind))
            continue
        why = _rewrite(path, folder)
        if why:
            problems.append((rel, why))
    return problems


def main(argv: Optional[Sequence[str]] = None) -> int:
    """``python -m hri_teleop.grading.batch.feedback_html FOLDER...``: clean every page below each folder
    (e.g. ``notebooks/feedback`` after ``nbgrader generate_feedback`` was run by hand)."""
    folders = [Path(a) for a in (sys.argv[1:] if argv is None else argv)]
    if not folders:
        print("usage: python -m hri_teleop.grading.batch.feedback_html FOLDER... (e.g. notebooks/feedback)")
        return 2
    for folder in folders:
        for rel, why in sanitize_feedback(folder):
            print(f"{folder / rel}: not kept ({why})")
        print(f"{folder}: every page cleaned")
    return 0


if __name__ == "__main__":
    sys.exit(main())
