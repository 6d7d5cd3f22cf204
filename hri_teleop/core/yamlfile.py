"""Read a YAML file that a person wrote: every problem becomes one line naming the file and the fix.

Why one function: the teleop config, the gamepad layouts and the pad scripts are all
edited by students, and the lab's rule for bad input is one line with the cause and the
fix, never a traceback.  Each module passes its own error class, so callers keep
catching ``ConfigError`` / ``GamepadError`` as before.
"""

from __future__ import annotations

from pathlib import Path
from typing import Type, Union

import yaml

__all__ = ["read_yaml"]


def read_yaml(
    path: Union[str, Path],
    error: Type[Exception],
    *,
    what: str = "file",
    missing_fix: str = "check the path",
) -> object:
    """The parsed content of the YAML file ``path`` (None for an empty file).

    Raises ``error`` with a one-line message that names the file as ``str(path)`` spells it:

    * missing: ``<what> not found: <path>; <missing_fix>``
    * a directory: ``<path> is a directory, not a YAML file; pass the file's path``
    * unreadable (permissions, not UTF-8): ``<path>: cannot read (<Error>: <detail>); check
      the file's permissions and encoding``
    * a syntax error: ``<path>:<line>: <problem>; fix the YAML syntax (...)``

    The shape of the content is not checked: each caller expects its own (a mapping, a
    list of steps) and says so in its own words.
    """
    source = str(path)
    try:
        text = Path(path).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise error(f"{what} not found: {source}; {missing_fix}") from None
    except IsADirectoryError:
        raise error(f"{source} is a directory, not a YAML file; pass the file's path") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise error(f"{source}: cannot read ({exc.__class__.__name__}: {exc}); "
                    "check the file's permissions and encoding") from None
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"{source}:{mark.line + 1}" if mark is not None else source
        problem = getattr(exc, "problem", None) or str(exc).splitlines()[0]
        raise error(f"{where}: {problem}; fix the YAML syntax (indent with spaces, `key: value`)") from None
