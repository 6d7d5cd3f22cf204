"""Replace a file the lab keeps (a calibrated launch file, a trial's sidecar) all at once.

Why: a crash, a full disk or Ctrl-C in the middle of a write must leave the old file or
the new one, never half of one -- a half-written launch file stops the lab, a half-written
sidecar loses a participant's trial. The text goes to a temporary file in the same folder
(same file system, so the rename is atomic), is flushed to disk, takes the old file's
permissions, and then replaces it.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import Union

__all__ = ["replace_text"]


def replace_text(path: Union[str, Path], text: str, new_mode: int = 0o644) -> None:
    """Write ``text`` (UTF-8) to ``path`` atomically; ``new_mode`` when the file did not exist.

    Raises OSError (the caller names the file and the fix in its own error); the
    temporary file never stays behind.
    """
    path = Path(path)
    handle, temp = tempfile.mkstemp(prefix="." + path.name + ".", suffix=".tmp", dir=str(path.parent))
    try:
        with os.fdopen(handle, "w", encoding="utf-8") as out:
            out.write(text)
            out.flush()
            os.fsync(out.fileno())
        os.chmod(temp, path.stat().st_mode & 0o7777 if path.exists() else new_mode)
        os.replace(temp, path)
    except BaseException:
        if os.path.exists(temp):
            os.unlink(temp)
        raise
