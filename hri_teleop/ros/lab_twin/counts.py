"""What a lab twin node counts, written atomically to a JSON file in the twin's folder.

The twin must look like the lab on the ROS graph, so its nodes say what reached them through files,
never topics: ``<folder>/<node>.json``, replaced (temporary file, then rename) soon after any change
and once more when the node stops; the folder comes from :data:`TWIN_DIR_ENV`. A later process of
the same node takes the file over. The robot's user stop lives there too (:data:`ACTIVATION_FILE`).
"""

from __future__ import annotations

import fcntl
import json
import os
import threading
import time
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Dict, Iterator, Mapping, Optional

__all__ = ["TWIN_DIR_ENV", "TWIN_PACKAGE_ENV", "TWIN_BOARD_PORT_ENV", "FLUSH_PERIOD_S", "RECLAIM_PERIOD_S", "ACTIVATION_FILE", "CountsFile",
           "write_json_atomic", "owner_lock", "read_json", "counts_path", "read_activated", "write_activated"]

#: The environment variable that names the twin's folder for its node processes.
TWIN_DIR_ENV = "HRI_LAB_TWIN_DIR"
#: Set (to the package's name) by the executables of the twin's installed packages: a node started
#: by a launch records it as ``package`` in its counts.
TWIN_PACKAGE_ENV = "HRI_LAB_TWIN_PACKAGE"
#: Set by the twin's installed serial_node.py: the twin's board (its pty), opened instead of ``~port``.
TWIN_BOARD_PORT_ENV = "HRI_LAB_TWIN_BOARD_PORT"
#: Changes are written at most this often (s): a node that counts 50 twists a second writes 20 files.
FLUSH_PERIOD_S = 0.05
#: Without changes, how often a node checks that its file still holds its own counts (s).
RECLAIM_PERIOD_S = 1.0
#: The robot's user stop in the twin's folder: ``{"activated": true}`` (missing: activated).
ACTIVATION_FILE = "activation.json"


def counts_path(folder: Path, node: str) -> Path:
    """Where node ``node`` (``franka_control``, ``/serial_node``, ...) keeps its counts."""
    return Path(folder) / f"{node.strip('/')}.json"


def write_json_atomic(path: Path, data: Mapping[str, Any]) -> None:
    """Replace ``path`` with ``data`` as JSON in one step: a reader sees the old file or the new one."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{threading.get_ident()}.tmp")
    tmp.write_text(json.dumps(dict(data), sort_keys=True), encoding="utf-8")
    os.replace(tmp, path)


@contextmanager
def owner_lock(path: Path) -> Iterator[None]:
    """Hold the lock that makes "read the owner, then write" one step for ``path``.

    Every writer of a counts file (each thread of each process of the node) takes it, so an older
    process can never read its own counts, lose the processor, and then write over a newer one's.
    """
    lock_path = Path(path).with_name(f".{Path(path).name}.lock")
    with open(lock_path, "a", encoding="utf-8") as handle:
        fcntl.flock(handle, fcntl.LOCK_EX)
        try:
            yield
        finally:
            fcntl.flock(handle, fcntl.LOCK_UN)


def read_json(path: Path) -> Dict[str, Any]:
    """A counts file's contents ({} while it does not exist yet)."""
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        return {}
    return dict(data) if isinstance(data, dict) else {}


def read_activated(folder: Path) -> object:
    """The user stop's state in ``folder``: True (released, also when never set), False, or what a
    person wrote there instead of a bool (the caller keeps the arm still then)."""
    return read_json(Path(folder) / ACTIVATION_FILE).get("activated", True)


def write_activated(folder: Path, activated: bool) -> None:
    write_json_atomic(Path(folder) / ACTIVATION_FILE, {"activated": bool(activated)})


def _newer(theirs: Mapping[str, Any], ours: Mapping[str, Any]) -> bool:
    """Whether ``theirs`` comes from another process that started after ours."""
    started = theirs.get("started_ns")
    return (theirs.get("pid") != ours.get("pid") and isinstance(started, int)
            and started > int(ours.get("started_ns", 0)))


class CountsFile:
    """A node's counts: ``add``/``set`` them from any thread; a thread writes them after each change."""

    def __init__(self, path: Path, node: str, flush_period_s: float = FLUSH_PERIOD_S) -> None:
        self.path = Path(path)
        self._values: Dict[str, Any] = {"node": node, "pid": os.getpid(), "started_ns": time.time_ns()}
        self._lock = threading.Lock()
        self._changed = threading.Event()
        self._closed = threading.Event()
        self._superseded = False
        self._period_s = flush_period_s
        self.flush()
        self._thread = threading.Thread(target=self._run, name=f"counts {node}", daemon=True)
        self._thread.start()

    @classmethod
    def from_env(cls, node: str) -> Optional["CountsFile"]:
        """The counts file in the twin's folder (None outside a twin: the node then counts nothing);
        a node of the twin's installed packages records the package's name as ``package``."""
        folder = os.environ.get(TWIN_DIR_ENV, "").strip()
        if not folder:
            return None
        counts = cls(counts_path(Path(folder), node), node)
        package = os.environ.get(TWIN_PACKAGE_ENV, "").strip()
        if package:
            counts.set("package", package)
        return counts

    def add(self, key: str, amount: int = 1) -> None:
        with self._lock:
            self._values[key] = int(self._values.get(key, 0)) + amount
        self._changed.set()

    def set(self, key: str, value: Any) -> None:
        with self._lock:
            if self._values.get(key) == value:
                return
            self._values[key] = value
        self._changed.set()

    def add_to(self, key: str, item: str, amount: int = 1) -> None:
        """Count ``item`` in the mapping ``key`` (e.g. goals per action)."""
        with self._lock:
            table = dict(self._values.get(key, {}))
            table[item] = int(table.get(item, 0)) + amount
            self._values[key] = table
        self._changed.set()

    def get(self, key: str, default: Any = None) -> Any:
        with self._lock:
            return self._values.get(key, default)

    @property
    def superseded(self) -> bool:
        """True once a process of the same node that started later has written the file."""
        with self._lock:
            return self._superseded

    def flush(self) -> None:
        """Write the counts, unless a newer process of this node owns the file (then never again)."""
        with self._lock:
            values = dict(self._values)
            if self._superseded:
                return
        with owner_lock(self.path):
            try:
                current = read_json(self.path)
            except ValueError:  # not JSON: nobody's counts, ours replace it
                current = {}
            if _newer(current, values):
                with self._lock:
                    self._superseded = True
                return
            write_json_atomic(self.path, values)

    def _run(self) -> None:
        while not self._closed.is_set():
            if not self._changed.wait(RECLAIM_PERIOD_S):
                # Nothing changed: an older process's last write may still have crossed ours.
                try:
                    if read_json(self.path).get("pid") == os.getpid():
                        continue
                except ValueError:
                    pass
            self._changed.clear()
            self.flush()
            self._closed.wait(self._period_s)

    def close(self, **final: Any) -> None:
        """Write the last counts (and ``final`` values, e.g. ``stopped=True``) and stop the writer."""
        with self._lock:
            self._values.update(final)
        self._closed.set()
        self._changed.set()
        self._thread.join(timeout=2.0)
        self.flush()
