"""What a lab twin node counts, written atomically to a JSON file in the twin's folder.

The twin must look like the lab on the ROS graph, so its nodes say what reached them through
files, never topics: each node keeps its counts here and a writer thread replaces
``<folder>/<node>.json`` (write to a temporary file, then rename) soon after any change, and once
more when the node stops. The folder comes from the environment (:data:`TWIN_DIR_ENV`).
"""

from __future__ import annotations

import json
import os
import threading
from pathlib import Path
from typing import Any, Dict, Mapping, Optional

__all__ = ["TWIN_DIR_ENV", "FLUSH_PERIOD_S", "CountsFile", "write_json_atomic", "read_json", "counts_path"]

#: The environment variable that names the twin's folder for its node processes.
TWIN_DIR_ENV = "HRI_LAB_TWIN_DIR"
#: Changes are written at most this often (s): a node that counts 50 twists a second writes 20 files.
FLUSH_PERIOD_S = 0.05


def counts_path(folder: Path, node: str) -> Path:
    """Where node ``node`` (``franka_control``, ``/serial_node``, ...) keeps its counts."""
    return Path(folder) / f"{node.strip('/')}.json"


def write_json_atomic(path: Path, data: Mapping[str, Any]) -> None:
    """Replace ``path`` with ``data`` as JSON in one step: a reader sees the old file or the new one."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.{threading.get_ident()}.tmp")
    tmp.write_text(json.dumps(dict(data), sort_keys=True), encoding="utf-8")
    os.replace(tmp, path)


def read_json(path: Path) -> Dict[str, Any]:
    """A counts file's contents ({} while it does not exist yet)."""
    try:
        data = json.loads(Path(path).read_text(encoding="utf-8"))
    except FileNotFoundError:
        return {}
    return dict(data) if isinstance(data, dict) else {}


class CountsFile:
    """A node's counts: ``add``/``set`` them from any thread; a thread writes them after each change."""

    def __init__(self, path: Path, node: str, flush_period_s: float = FLUSH_PERIOD_S) -> None:
        self.path = Path(path)
        self._values: Dict[str, Any] = {"node": node, "pid": os.getpid()}
        self._lock = threading.Lock()
        self._changed = threading.Event()
        self._closed = threading.Event()
        self._period_s = flush_period_s
        self.flush()
        self._thread = threading.Thread(target=self._run, name=f"counts {node}", daemon=True)
        self._thread.start()

    @classmethod
    def from_env(cls, node: str) -> Optional["CountsFile"]:
        """The counts file in the twin's folder (None outside a twin: the node then counts nothing)."""
        folder = os.environ.get(TWIN_DIR_ENV, "").strip()
        return cls(counts_path(Path(folder), node), node) if folder else None

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

    def flush(self) -> None:
        with self._lock:
            values = dict(self._values)
        write_json_atomic(self.path, values)

    def _run(self) -> None:
        while not self._closed.is_set():
            self._changed.wait()
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
