"""Check a gamepad and its layout: ``python -m hri_teleop.apps.pad_check [--layout auto]``.

Prints the pad's raw SDL indices next to the positional names the layout gives them, one
line per change, so a new controller or driver can be checked (and a layout file written)
in a minute. ``--rumble`` vibrates while a button is held; ``--list`` lists the layouts;
``--stale`` reports the longest run of identical readings with a stick held (stale_input_timeout).
"""

from __future__ import annotations

import argparse
import sys
import time
from typing import List, Optional

from hri_teleop.core.gamepad.layout import AUTO_LAYOUT, available_layouts, load_layout
from hri_teleop.core.gamepad.stale import StaleInputWatch
from hri_teleop.core.gamepad.state import AXES, GamepadError
from hri_teleop.hardware.real.pygame_pad import PygamePad


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="python -m hri_teleop.apps.pad_check", description=__doc__.splitlines()[0])
    parser.add_argument("--layout", default=AUTO_LAYOUT,
                        help="layout name or YAML path (default: auto, identified from the pad)")
    parser.add_argument("--index", type=int, default=0, help="joystick index (default: 0)")
    parser.add_argument("--rate", type=float, default=50.0, help="poll rate in Hz (default: 50)")
    parser.add_argument("--seconds", type=float, default=0.0, help="stop after this long (default: Ctrl-C)")
    parser.add_argument("--rumble", action="store_true", help="rumble while any mapped button is held")
    parser.add_argument("--list", action="store_true", help="list the shipped layouts and exit")
    parser.add_argument("--stale", action="store_true",
                        help="hold a stick still: report the longest run of identical readings (compare "
                             "stale_input_timeout in teleop.yaml)")
    parser.add_argument("--deadzone", type=float, default=0.1, help="with --stale: a stick beyond this is held")
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
    watch = StaleInputWatch(timeout_s=3600.0, deadzone=args.deadzone)  # only measures how long
    longest_s = 0.0
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
                if args.stale:
                    watch.update(state, time.monotonic())
                    run_s = watch.frozen_s(time.monotonic())
                    if run_s > longest_s:
                        if int(run_s * 10) > int(longest_s * 10):  # a line per 0.1 s more
                            line = "longest run of identical readings with a stick held: %.1f s" % run_s
                        longest_s = run_s
            if line != last:
                print(line, flush=True)
                last = line
            time.sleep(period)
    except KeyboardInterrupt:
        pass
    finally:
        pad.close()
    if args.stale:
        print("longest run of identical readings with a stick held: %.2f s" % longest_s)
    return 0


if __name__ == "__main__":
    sys.exit(main())
