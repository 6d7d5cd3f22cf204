"""The meshcat server of one ArmView, ending with the process that started it (``python -I`` this file).

The view stops its server when it is closed or the kernel exits normally; a kernel that dies
without its exit hooks (killed, or ipykernel's ``os._exit`` once JupyterLab is gone) would leave it
serving. So a thread here watches the parent and ends the server when the parent is gone.
"""

from __future__ import annotations

import os
import sys
import threading
import time
import warnings

#: How often the parent is looked at (s).
PARENT_POLL_S = 0.5


def _end_with(parent: int) -> None:
    while os.getppid() == parent:
        time.sleep(PARENT_POLL_S)
    os._exit(0)  # the parent is gone: nobody can show this server any more


def main() -> None:
    threading.Thread(target=_end_with, args=(os.getppid(),), name="parent watch", daemon=True).start()
    with warnings.catch_warnings():  # meshcat's server imports a deprecated zmq.eventloop
        warnings.simplefilter("ignore", DeprecationWarning)
        from meshcat.servers.zmqserver import main as serve  # noqa: PLC0415 - after the watch is up
    sys.argv = sys.argv[:1]
    serve()


if __name__ == "__main__":
    main()
