"""Put this folder first on a node's PYTHONPATH to stand in for SDL's pad (see pad_standin_joystick).

Only when HRI_PAD_STANDIN_SCRIPT names a pad script; otherwise Python starts as usual.
"""

import os

if os.environ.get("HRI_PAD_STANDIN_SCRIPT"):
    import pad_standin_joystick

    pad_standin_joystick.install()
