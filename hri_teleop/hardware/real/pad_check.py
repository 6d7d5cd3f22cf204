"""Check a gamepad and its layout: ``python -m hri_teleop.hardware.real.pad_check [--layout auto]``.

Prints the pad's raw SDL indices next to the positional names the layout gives them, one
line per change, so a new controller or driver can be checked (and a layout file written)
in a minute. ``--rumble`` vibrates while a button is held; ``--list`` lists the layouts.
"""

from __future__ import annotations

import argparse
import sys
import time
from typing import List, Optional

from hri_teleop.core.gamepad.layout import AUTO_LAYOUT, available_layouts, load_layout
from hri_teleop.core.gamepad.state import AXES, GamepadError
from hri_teleop.hardware.real.pygame_pad import PygamePad


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m hri_teleop.hardware.real.pad_check", description=__doc__.splitlines()[0])
    parser.add_argument("--layout", default=AUTO_LAYOUT,
                        help="layout name or YAML path (default: auto, identified from the pad)")
    parser.add_argument("--index", type=int, default=0, help="joystick index (default: 0)")
    parser.add_argument("--rate", type=float, default=50.0, help="poll rate in Hz (default: 50)")
    parser.add_argument("--seconds", type=float, default=0.0, help="stop after this long (default: Ctrl-C)")
    parser.add_argument("--rumble", action="store_true", help="rumble while any mapped button is held")
    parser.add_argument("--list", action="store_true", help="list the shipped layouts and exit")
    return parser


def main(argv: Optional[List[str]] = None) -> int:
    args = _parser().parse_args(argv)
    try:
        if args.list:
            for name in available_layouts():
                print("%-24s %s" % (name, load_layout(name).description))
            return 0
        chosen = args.layout if args.layout.strip() == AUTO_LAYOUT else load_layout(args.layout)
        pad = PygamePad(chosen, args.index, check_layout=False, log=lambda m: print("warning: " + m))
    except GamepadError as exc:
        print("error: %s" % exc, file=sys.stderr)
        return 1
    layout = pad.layout
    print("pad %r, layout %r (%s; %s); move sticks and press buttons, Ctrl-C to stop"
          % (pad.name, layout.name, layout.description, pad.layout_reason))
    period = 1.0 / max(1.0, args.rate)
    end = time.monotonic() + args.seconds if args.seconds > 0 else None
    last = None
    try:
        while end is None or time.monotonic() < end:
            raw = pad.read_raw()
            if raw is None:
                line = "disconnected"
            else:
                axes, buttons = raw
                state = layout.state_from_raw(axes, buttons)
                held_raw = [i for i, b in enumerate(buttons) if b]
                held = ["%s(%s)" % (n, layout.label(n)) for n, b in state.buttons.items() if b]
                line = "raw axes [%s] raw buttons %s | %s | pressed: %s" % (
                    " ".join("%+.2f" % a for a in axes), held_raw,
                    " ".join("%s=%+.2f" % (n, state.axis(n)) for n in AXES),
                    " ".join(held) or "-")
                if args.rumble:
                    pad.rumble(1.0 if held else 0.0, 0.2)
            if line != last:
                print(line, flush=True)
                last = line
            time.sleep(period)
    except KeyboardInterrupt:
        pass
    finally:
        pad.close()
    return 0


if __name__ == "__main__":
    sys.exit(main())
