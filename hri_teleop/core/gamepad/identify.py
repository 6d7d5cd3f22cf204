"""Which shipped layout fits a pad, from its SDL GUID, name and counts of axes and buttons.

``layout: auto`` (the default) uses it so a student need not pick ``layout:=`` by hand. The
GUID carries the USB vendor/product and the kernel driver's version; its 0x8000 bit tells
Sony's gamepad-spec drivers from the generic HID driver, whose raw order differs. A pad it
does not know, or knows to read in an order no layout describes, gives no layout and a reason.
"""

from __future__ import annotations

import re
from typing import Dict, NamedTuple, Optional

from hri_teleop.core.gamepad.layout import AUTO_LAYOUT, available_layouts, load_layout

__all__ = ["AUTO_LAYOUT", "SdlGuid", "LayoutGuess", "parse_sdl_guid", "identify_layout", "BUS_NAMES"]

#: Bus types in an SDL GUID (Linux input.h BUS_*).
BUS_USB = 0x03
BUS_BLUETOOTH = 0x05
BUS_NAMES = {BUS_USB: "USB", BUS_BLUETOOTH: "Bluetooth"}

SONY = 0x054C
MICROSOFT = 0x045E
#: Product ids (USB and Bluetooth alike) of the pads the shipped layouts describe.
DUALSHOCK4: Dict[int, str] = {0x05C4: "DualShock 4", 0x09CC: "DualShock 4 (second model)",
                              0x0BA0: "DualShock 4 USB wireless adaptor"}
DUALSENSE: Dict[int, str] = {0x0CE6: "DualSense", 0x0DF2: "DualSense Edge"}
#: hid-sony (Linux >= 4.10) and hid-playstation set this bit of the device version to say the
#: buttons follow the kernel's gamepad spec; the generic HID driver leaves it clear.
GAMEPAD_SPEC_VERSION_BIT = 0x8000
#: hid-playstation's DualSense reports 13 buttons (its touchpad is a separate device); the
#: generic HID driver adds the touchpad click and the mute button (14-15).
DUALSENSE_SPEC_BUTTONS = 13

_HEX32 = re.compile(r"^[0-9a-fA-F]{32}$")


class SdlGuid(NamedTuple):
    """The fields of an SDL 2 joystick GUID made from a device's ids (16 bytes, little-endian words)."""

    bus: int
    vendor: int
    product: int
    version: int
    driver: int  # byte 14: 0 for the kernel (evdev) driver, ord('h') for SDL's HIDAPI driver, ...

    def ids(self) -> str:
        return "%04x:%04x" % (self.vendor, self.product)

    def bus_name(self) -> str:
        return BUS_NAMES.get(self.bus, "bus 0x%02x" % self.bus)


class LayoutGuess(NamedTuple):
    """A shipped layout's name (None: not identified) and one line saying why."""

    layout: Optional[str]
    reason: str


def _word(data: bytes, offset: int) -> int:
    return data[offset] | data[offset + 1] << 8


def parse_sdl_guid(guid: str) -> Optional[SdlGuid]:
    """The ids in a GUID string such as pygame's ``Joystick.get_guid()``; None if it holds none.

    SDL writes bus, name CRC, vendor, 0, product, 0, version (16-bit words), then a driver
    byte and a driver-specific byte. A device without ids gets its name in the GUID instead.
    """
    text = str(guid).strip()
    if not _HEX32.match(text):
        return None
    data = bytes.fromhex(text)
    vendor, product = _word(data, 4), _word(data, 8)
    if _word(data, 6) != 0 or _word(data, 10) != 0 or vendor == 0:
        return None  # the name-in-GUID form: no ids to read
    return SdlGuid(_word(data, 0), vendor, product, _word(data, 12), data[14])


def _checked(layout: str, why: str, num_axes: int, num_buttons: int) -> LayoutGuess:
    """The guess, unless the pad has fewer axes or buttons than the layout maps."""
    needed = load_layout(layout)
    if num_axes < needed.num_axes or num_buttons < needed.num_buttons:
        return LayoutGuess(None, "%s, but it reports %d axes and %d buttons where layout %s needs %d and %d"
                           % (why, num_axes, num_buttons, layout, needed.num_axes, needed.num_buttons))
    return LayoutGuess(layout, why)


def _from_ids(ids: SdlGuid, num_axes: int, num_buttons: int) -> Optional[LayoutGuess]:
    """The guess for a pad the GUID's vendor/product names; None if it names none we know."""
    where = "%s (%s) over %s by its GUID" % ("%s", ids.ids(), ids.bus_name())
    spec = ids.version & GAMEPAD_SPEC_VERSION_BIT
    if ids.driver != 0:
        return LayoutGuess(None, "%s is read through SDL's HIDAPI driver (GUID byte 14 is 0x%02x), whose raw "
                           "order no shipped layout describes; open it with SDL_JOYSTICK_HIDAPI=0 as the node does"
                           % (ids.ids(), ids.driver))
    if ids.vendor == SONY and ids.product in DUALSENSE:
        what = where % DUALSENSE[ids.product]
        if spec:
            return _checked("dualsense", what + ", driver hid-playstation", num_axes, num_buttons)
        return _checked("dualsense_hid_generic", what + ", generic HID driver (version 0x%04x)" % ids.version,
                        num_axes, num_buttons)
    if ids.vendor == SONY and ids.product in DUALSHOCK4:
        what = where % DUALSHOCK4[ids.product]
        if spec:
            return _checked("dualshock4", what + ", driver hid-sony/hid-playstation", num_axes, num_buttons)
        return LayoutGuess(None, "%s, but its driver (version 0x%04x: the generic HID driver or Linux < 4.10) "
                           "orders the buttons as no shipped layout does" % (what, ids.version))
    if ids.vendor == MICROSOFT:
        what = where % "Xbox pad"
        if ids.bus == BUS_USB:
            return _checked("xbox", what + ", driver xpad", num_axes, num_buttons)
        return LayoutGuess(None, "%s: over %s it uses another driver (hid-microsoft or xpadneo) with another "
                           "order; connect it with a USB cable" % (what, ids.bus_name()))
    return None


def _from_name(name: str, bus: Optional[int], num_axes: int, num_buttons: int) -> Optional[LayoutGuess]:
    """The guess from the pad's name alone (a GUID without ids, or ids we do not know)."""
    lower = name.lower()
    if "dualsense" in lower or "ps5 controller" in lower:
        if num_buttons > DUALSENSE_SPEC_BUTTONS:
            return _checked("dualsense_hid_generic", "DualSense by its name and its %d buttons (the generic HID "
                            "driver's count)" % num_buttons, num_axes, num_buttons)
        return _checked("dualsense", "DualSense by its name and its %d buttons (hid-playstation's count)"
                        % num_buttons, num_axes, num_buttons)
    if "dualshock 4" in lower or "ps4 controller" in lower:
        if num_buttons > DUALSENSE_SPEC_BUTTONS:
            return LayoutGuess(None, "DualShock 4 by its name, but its %d buttons say the generic HID driver, "
                               "whose order no shipped layout describes" % num_buttons)
        return _checked("dualshock4", "DualShock 4 by its name", num_axes, num_buttons)
    if "x-box" in lower or "xbox" in lower:
        if bus == BUS_BLUETOOTH:
            return LayoutGuess(None, "Xbox pad by its name, over Bluetooth, where its order differs; "
                               "connect it with a USB cable")
        return _checked("xbox", "Xbox pad by its name (driver xpad)", num_axes, num_buttons)
    return None


def identify_layout(guid: str, name: str, num_axes: int, num_buttons: int) -> LayoutGuess:
    """The shipped layout for a pad SDL reports, or None and why (see the module doc).

    The GUID's vendor/product decide; the name is the fallback for a GUID without known
    ids. A DualSense on the generic HID driver gets ``dualsense_hid_generic``; a guess is
    dropped when the pad has fewer axes or buttons than the layout maps.
    """
    ids = parse_sdl_guid(guid)
    if ids is not None:
        guess = _from_ids(ids, num_axes, num_buttons)
        if guess is not None:
            return guess
    guess = _from_name(str(name), ids.bus if ids is not None else None, num_axes, num_buttons)
    if guess is not None:
        return guess
    known = "vendor:product %s" % ids.ids() if ids is not None else "no vendor/product in its GUID"
    return LayoutGuess(None, "%r (%s) is not a pad the shipped layouts (%s) are known to fit"
                       % (str(name), known, ", ".join(available_layouts())))
