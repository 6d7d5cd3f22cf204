"""Hostile notebook outputs in the feedback HTML that instructors and students open (issue 42, item 7).

`make grade` on a small nbgrader course (Ex. 1, no ROS) with two students: alice hands in the answer
key; mallory the same plus a cell whose outputs are an HTML page of attacks (``<script>``,
``onerror=``, an iframe, ``javascript:`` links, a ``<meta>`` refresh), a JavaScript output, a PNG whose
``width`` metadata breaks out of nbconvert's unquoted attribute, Markdown with the same, and a Markdown
cell of her own holding a script, and an ``notes.html`` of her own beside the notebook. No page of the
feedback folder may hold an element or attribute that runs or loads anything; mallory keeps alice's
score, and both pages keep what a reader needs (the scores, tables, printed text, images).
"""

from __future__ import annotations

import json
import os
import shutil
import subprocess
from html.parser import HTMLParser
from pathlib import Path
from typing import Dict, List, Tuple

import pytest
from grading_helpers import REPO, SOLUTIONS, grader_env, nbgrader_course

from hri_teleop.grading.batch.feedback_html import CSP, sanitize_document, sanitize_feedback

ASSIGNMENT = "preparation"
NOTEBOOK = "ex01_fsr_and_arduino"
PNG = ("iVBORw0KGgoAAAANSUhEUgAAAAEAAAABCAYAAAAfFcSJAAAADUlEQVR42mP8z8BQDwAEhQGAhKmMIQAAAABJRU5ErkJggg==")
ATTACK_HTML = (
    "<script>document.title='PWNED-1'</script><img src=x onerror=\"document.title='PWNED-2'\">"
    "<iframe src=\"javascript:alert('PWNED-3')\"></iframe><a href=\"javascript:alert('PWNED-4')\">click</a>"
    "<svg onload=\"alert('PWNED-5')\"><script>alert('PWNED-6')</script></svg>"
    "<meta http-equiv=refresh content=\"0;url=javascript:alert('PWNED-7')\">"
    "<object data=\"javascript:alert('PWNED-8')\"></object><form action=\"https://evil.example/\"><input name=p>"
    "</form><a href=\"data:text/html,<script>alert('PWNED-9')</script>\">data</a>"
    "<table><tr><th>kept header</th></tr><tr><td>kept cell</td></tr></table>"
)
HOSTILE_CELL = (
    "from IPython.display import display, HTML, Markdown, Javascript\n"
    f"display(HTML({ATTACK_HTML!r}))\n"
    "display(Javascript(\"document.title='PWNED-10'\"))\n"
    "display({'image/png': " + repr(PNG) + "}, raw=True, "
    "metadata={'image/png': {'width': \"1 onerror=alert('PWNED-11') \"}})\n"
    "display(Markdown(\"[md](javascript:alert('PWNED-12')) <img src=x onerror=alert('PWNED-13')>\"))\n"
    "print('plain text <b>kept</b> & printed')\n"
)
MARKDOWN_CELL = "## my notes\n<script>alert('PWNED-14')</script><img src=x onerror=\"alert('PWNED-15')\">\n"
STUDENT_PAGE = "<html><head><script>alert('PWNED-16')</script></head><body onload=\"alert('PWNED-17')\">hi</body></html>"
#: Elements that run, load, frame or submit something.
ACTIVE_TAGS = {"script", "iframe", "frame", "object", "embed", "svg", "math", "form", "input", "button", "base",
               "link", "applet", "audio", "video", "source", "portal", "textarea", "select"}


class _Elements(HTMLParser):
    """Every start tag as a browser's tokenizer sees it: (tag, attributes)."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.elements: List[Tuple[str, Dict[str, str]]] = []

    def handle_starttag(self, tag: str, attrs: List[Tuple[str, "str | None"]]) -> None:
        self.elements.append((tag, {k.lower(): (v or "") for k, v in attrs}))


def _elements(text: str) -> List[Tuple[str, Dict[str, str]]]:
    parser = _Elements()
    parser.feed(text)
    parser.close()
    return parser.elements


def active_parts(text: str) -> List[str]:
    """What in the page ``text`` could run a script or load something: empty for a safe page."""
    found = []
    for tag, attrs in _elements(text):
        if tag in ACTIVE_TAGS:
            found.append(f"<{tag}>")
        if tag == "meta" and attrs.get("http-equiv", "").lower() not in ("content-security-policy", ""):
            found.append(f"<meta http-equiv={attrs['http-equiv']}>")
        for name, value in attrs.items():
            if name.startswith("on"):
                found.append(f"<{tag} {name}=...>")
            url = "".join(value.split()).lower()
            if name in ("href", "src", "action", "data", "formaction", "xlink:href", "srcdoc") and (
                    url.startswith(("javascript:", "vbscript:")) or (url.startswith("data:")
                                                                    and not url.startswith("data:image/"))):
                found.append(f"<{tag} {name}={value[:40]}>")
    return found


def _csp(text: str) -> str:
    return next((a.get("content", "") for t, a in _elements(text) if t == "meta"
                 and a.get("http-equiv", "").lower() == "content-security-policy"), "")


# -- the rewrite itself, on pages as nbconvert writes them ----------------------------------------------

def test_an_attack_page_keeps_no_active_part_and_its_tables_text_and_images_stay():
    page = (f"<html><head><title>ex &lt;1&gt;</title><style>body{{color:red}}</style>"
            f"<script src='https://cdn.example/x.js'></script></head><body><div>{ATTACK_HTML}</div>"
            f"<pre>plain text &lt;b&gt;kept&lt;/b&gt;</pre><img src=\"data:image/png;base64,{PNG}\"\n"
            f"width=1 onerror=alert('PWNED-11') ><a href='#top'>top</a><a href='https://ros.org/'>ros</a></body></html>")
    assert active_parts(page)  # the detector sees the attacks in the raw page
    clean = sanitize_document(page)
    assert active_parts(clean) == [], clean
    assert "PWNED-1" not in clean and "PWNED-6" not in clean  # scripts gone with their content
    assert _csp(clean) == CSP and "script-src" not in CSP and "default-src 'none'" in CSP
    assert "<th>kept header</th>" in clean and "<td>kept cell</td>" in clean
    assert "plain text &lt;b&gt;kept&lt;/b&gt;" in clean
    assert f'src="data:image/png;base64,{PNG}"' in clean and 'width="1"' in clean
    assert 'href="#top"' in clean and 'href="https://ros.org/"' in clean
    assert "<title>ex &lt;1&gt;</title>" in clean and "body{color:red}" in clean


def test_a_link_or_a_fifo_named_like_a_page_is_removed_unread_and_a_page_is_a_new_file(tmp_path):
    folder = tmp_path / "feedback" / "mallory" / ASSIGNMENT
    folder.mkdir(parents=True)
    secret = tmp_path / "instructor.html"
    secret.write_text("<script>alert('instructor')</script>")
    (folder / "linked.html").symlink_to(secret)
    os.mkfifo(folder / "pipe.html")
    (folder / "page.html").write_text(STUDENT_PAGE)
    problems = dict(sanitize_feedback(folder))
    assert set(problems) == {"linked.html", "pipe.html"}
    assert sorted(p.name for p in folder.iterdir()) == ["page.html"]
    assert secret.read_text() == "<script>alert('instructor')</script>"  # never written through the link
    assert active_parts((folder / "page.html").read_text()) == []


# -- make grade on a course -----------------------------------------------------------------------------

def _with_cells(path: Path) -> None:
    """The notebook at ``path`` with the hostile code cell and Markdown cell appended."""
    import nbformat

    nb = nbformat.read(str(path), as_version=4)
    nb.cells.append(nbformat.v4.new_markdown_cell(MARKDOWN_CELL))
    nb.cells.append(nbformat.v4.new_code_cell(HOSTILE_CELL))
    nbformat.write(nb, str(path))


@pytest.fixture(scope="module")
def graded(tmp_path_factory) -> Path:
    """The course after `make grade` (alice: the answer key; mallory: the answer key and the attacks)."""
    from hri_teleop.grading.cases.templates import generate_answers

    root = nbgrader_course(tmp_path_factory.mktemp("hostile-output") / "course", ASSIGNMENT, [NOTEBOOK])
    for student in ("alice", "mallory"):
        folder = root / "submitted" / student / ASSIGNMENT
        folder.mkdir(parents=True)
        shutil.copy(root / "source" / ASSIGNMENT / f"{NOTEBOOK}.ipynb", folder)
        generate_answers(SOLUTIONS, folder / "hri_lab")
    _with_cells(root / "submitted" / "mallory" / ASSIGNMENT / f"{NOTEBOOK}.ipynb")
    (root / "submitted" / "mallory" / ASSIGNMENT / "notes.html").write_text(STUDENT_PAGE)
    out = root.parent / "grades"
    proc = subprocess.run(["make", "-s", "-o", "setup", "grade", f"DIR={root / 'submitted'}", f"OUT={out}", "JOBS=2",
                           "CHECKS=robot-params", "TIMEOUT=120"], cwd=REPO, capture_output=True, text=True,
                          env=grader_env(), timeout=900, stdin=subprocess.DEVNULL)
    print(proc.stdout[-4000:], proc.stderr[-4000:])
    assert proc.returncode == 0, proc.stdout[-3000:] + proc.stderr[-3000:]
    return root


def _pages(root: Path, student: str) -> Dict[str, str]:
    folder = root / "feedback" / student / ASSIGNMENT
    return {p.name: p.read_text(encoding="utf-8") for p in sorted(folder.rglob("*"))
            if p.suffix in (".html", ".htm") and p.is_file()}


def test_no_page_of_the_feedback_holds_a_script_a_handler_or_a_javascript_url(graded):
    pages = _pages(graded, "mallory")
    assert {f"{NOTEBOOK}.html", "notes.html"} <= set(pages), sorted(pages)  # nbgrader copies her notes.html
    for name, text in pages.items():
        assert active_parts(text) == [], f"{name}: {active_parts(text)}"
        assert _csp(text) == CSP, name
    notebook = pages[f"{NOTEBOOK}.html"]
    assert "kept cell" in notebook and "plain text &lt;b&gt;kept&lt;/b&gt; &amp; printed" in notebook
    assert f"data:image/png;base64,{PNG}" in notebook


def test_the_hostile_student_keeps_the_honest_score_and_the_honest_page_stays_readable(graded):
    rows = {r["student"]: r for r in _grades(graded)}
    assert rows["mallory"]["total"] == rows["alice"]["total"], rows
    honest = _pages(graded, "alice")[f"{NOTEBOOK}.html"]
    assert active_parts(honest) == []
    assert "Score:" in honest and "<pre" in honest and "<h1" in honest


def _grades(root: Path) -> List[Dict[str, str]]:
    import csv

    with open(root.parent / "grades" / "grades.csv", newline="") as fh:
        return list(csv.DictReader(fh))


def test_the_class_report_escapes_what_students_wrote(graded):
    report = (graded.parent / "grades" / "report.html").read_text()
    assert active_parts(report) == []
    summary = json.loads((graded.parent / "grades" / "summary.json").read_text())
    assert summary
