"""layout: auto: the shipped layout identified from a pad's SDL GUID, its name and its counts."""

from __future__ import annotations

import pytest
from test_gamepad_pygame import FakeJoystick, FakePygame  # tests/unit, on sys.path under pytest

from hri_teleop.core.gamepad import DEFAULT_LAYOUT, available_layouts
from hri_teleop.core.gamepad.identify import LayoutGuess, SdlGuid, identify_layout, parse_sdl_guid
from hri_teleop.hardware.real.pygame_pad import PygamePad

# (GUID as pygame's Joystick.get_guid() gives it on Linux, name, axes, buttons) -> layout.
# Bus 0x03 = USB, 0x05 = Bluetooth; version bit 0x8000 = Sony's gamepad-spec kernel drivers.
PADS = [
    ("030000004c050000c405000011810000", "Sony Computer Entertainment Wireless Controller", 6, 13, "dualshock4"),
    ("030000004c050000cc09000011810000", "Sony Interactive Entertainment Wireless Controller", 6, 13, "dualshock4"),
    ("050000004c050000cc09000000810000", "Wireless Controller", 6, 13, "dualshock4"),
    ("03008fe54c050000cc09000011810000", "PS4 Controller", 6, 13, "dualshock4"),  # SDL >= 2.26: name CRC
    ("030000004c050000e60c000011810000", "Sony Interactive Entertainment DualSense Wireless Controller", 6, 13,
     "dualsense"),
    ("050000004c050000e60c000000810000", "DualSense Wireless Controller", 6, 13, "dualsense"),
    ("030000004c050000f20d000011810000", "DualSense Edge Wireless Controller", 6, 13, "dualsense"),
    ("030000004c050000e60c000011010000", "Sony Interactive Entertainment Wireless Controller", 6, 15,
     "dualsense_hid_generic"),
    ("050000004c050000e60c000000010000", "Wireless Controller", 6, 15, "dualsense_hid_generic"),
    ("030000005e0400008e02000010010000", "Microsoft X-Box 360 pad", 6, 11, "xbox"),
    ("030000005e040000d102000001010000", "Microsoft X-Box One pad", 6, 11, "xbox"),
    ("030000005e040000120b000011050000", "Microsoft Xbox Series S|X Controller", 6, 12, "xbox"),
]


@pytest.mark.parametrize("guid, name, axes, buttons, layout", PADS)
def test_each_pad_over_usb_and_bluetooth_gets_its_layout_from_the_guid(guid, name, axes, buttons, layout):
    guess = identify_layout(guid, name, axes, buttons)
    assert guess.layout == layout and layout in available_layouts()
    assert "by its GUID" in guess.reason and "\n" not in guess.reason
    ids = parse_sdl_guid(guid)
    assert ids is not None and ids.ids() in guess.reason and ids.bus_name() in guess.reason


def test_the_guid_decides_over_a_misleading_name():
    # Both Sony pads are "Wireless Controller" over Bluetooth: only the product id tells them apart.
    assert identify_layout("050000004c050000e60c000000810000", "Wireless Controller", 6, 13).layout == "dualsense"
    assert identify_layout("050000004c050000cc09000000810000", "PS5 Controller", 6, 13).layout == "dualshock4"


def test_guid_fields_are_decoded_little_endian():
    assert parse_sdl_guid("050000004c050000e60c000000810000") == SdlGuid(0x05, 0x054C, 0x0CE6, 0x8100, 0)
    assert parse_sdl_guid("03008fe54c050000cc09000011810000") == SdlGuid(0x03, 0x054C, 0x09CC, 0x8111, 0)
    assert parse_sdl_guid("050000004c050000e60c000000006800").driver == ord("h")


@pytest.mark.parametrize("guid", ["", "not a guid", "030000004c050000cc0900001181000",  # 31 digits
                                  "05000000576972656c65737320436f6e",  # the name-in-GUID form: no ids
                                  "00000000000000000000000000000000"])
def test_a_guid_without_ids_gives_none(guid):
    assert parse_sdl_guid(guid) is None


@pytest.mark.parametrize("guid, name, why", [
    ("050000004c050000cc09000000010000", "Wireless Controller", "orders the buttons"),  # DS4, generic HID driver
    ("050000004c050000e60c000000006800", "PS5 Controller", "HIDAPI"),
    ("050000005e040000fd02000030110000", "Xbox Wireless Controller", "USB cable"),  # Xbox over Bluetooth
    ("050000007e0500000920000001800000", "Nintendo Switch Pro Controller", "not a pad"),
    ("05000000576972656c65737320436f6e", "Wireless Controller", "not a pad"),  # DS4 or DualSense: cannot tell
])
def test_pads_no_layout_fits_give_none_and_a_one_line_reason(guid, name, why):
    guess = identify_layout(guid, name, 6, 13)
    assert guess.layout is None and why in guess.reason and "\n" not in guess.reason


def test_a_pad_with_fewer_controls_than_the_layout_maps_is_not_given_it():
    guid = "030000004c050000e60c000011810000"
    assert identify_layout(guid, "DualSense", 6, 13).layout == "dualsense"
    short = identify_layout(guid, "DualSense", 6, 12)
    assert short.layout is None and "12 buttons" in short.reason and "needs 6 and 13" in short.reason
    assert identify_layout(guid, "DualSense", 5, 13).layout is None


def test_without_ids_the_name_and_the_button_count_tell_the_dualsense_drivers_apart():
    no_ids = "05000000576972656c65737320436f6e"
    assert identify_layout(no_ids, "PS5 Controller", 6, 13).layout == "dualsense"
    assert identify_layout(no_ids, "PS5 Controller", 6, 14).layout == "dualsense_hid_generic"
    assert identify_layout("", "DualShock 4", 6, 13).layout == "dualshock4"
    assert identify_layout("", "DualShock 4", 6, 14).layout is None


def test_a_third_party_xbox_pad_is_known_by_its_name_over_usb_only():
    assert identify_layout("03000000d62000000120000000000000", "PowerA Xbox One Controller", 6, 11) == \
        LayoutGuess("xbox", "Xbox pad by its name (driver xpad)")
    assert identify_layout("05000000d62000000120000000000000", "PowerA Xbox One Controller", 6, 11).layout is None


# ------------------------------------------------------------------ layout: auto in the real pad

class GuidJoystick(FakeJoystick):
    def __init__(self, guid: str, name: str, axes: int, buttons: int):
        super().__init__(name, axes=axes, buttons=buttons)
        self.guid = guid

    def get_guid(self) -> str:
        return self.guid


def test_auto_opens_a_generic_hid_dualsense_with_its_own_layout():
    js = GuidJoystick("050000004c050000e60c000000010000", "Wireless Controller", 6, 15)
    js.buttons[1] = 1  # cross on the generic HID driver
    logged: list = []
    pad = PygamePad("auto", joystick=js, log=logged.append)
    assert pad.layout.name == "dualsense_hid_generic" and pad.poll().pressed("south")
    assert pad.layout_reason.startswith("auto: DualSense (054c:0ce6) over Bluetooth") and logged == []


def test_an_explicit_layout_wins_over_the_pads_guid():
    js = GuidJoystick("030000004c050000e60c000011810000", "DualSense", 6, 15)
    pad = PygamePad("dualsense_hid_generic", joystick=js)
    assert pad.layout.name == "dualsense_hid_generic" and pad.layout_reason == "set by the configuration"


def test_auto_with_an_unknown_pad_logs_one_line_naming_it_and_uses_the_default():
    js = GuidJoystick("050000007e0500000920000001800000", "Nintendo Switch Pro Controller", 6, 16)
    logged: list = []
    pad = PygamePad("auto", joystick=js, log=logged.append)
    assert pad.layout.name == DEFAULT_LAYOUT and len(logged) == 1 and "\n" not in logged[0]
    assert "Nintendo Switch Pro Controller" in logged[0] and js.guid in logged[0]
    assert "layout:=" in logged[0] and "pad_check" in logged[0]


def test_auto_identifies_again_when_another_pad_is_plugged_in():
    first = GuidJoystick("030000004c050000cc09000011810000", "Wireless Controller", 6, 13)
    second = GuidJoystick("030000005e0400008e02000010010000", "Microsoft X-Box 360 pad", 6, 11)
    second.instance_id = 1
    pygame = FakePygame(first)
    pad = PygamePad("auto", pygame_module=pygame, log=lambda _m: None)
    assert pad.layout.name == "dualshock4"
    pygame.unplug(first)
    pad.poll()
    pygame.plug(second)
    assert pad.poll().connected and pad.layout.name == "xbox"


# ------------------------------------------------------------------ the reason, word for word (pad_check prints it)

LAYOUTS = "dualsense, dualsense_hid_generic, dualshock4, xbox"


@pytest.mark.parametrize("guid, buttons, layout, reason", [
    ("030000004c050000e60c000011810000", 13, "dualsense",
     "DualSense (054c:0ce6) over USB by its GUID, driver hid-playstation"),
    ("050000004c050000e60c000000010000", 15, "dualsense_hid_generic",
     "DualSense (054c:0ce6) over Bluetooth by its GUID, generic HID driver (version 0x0100)"),
    ("030000004c050000cc09000011810000", 13, "dualshock4",
     "DualShock 4 (second model) (054c:09cc) over USB by its GUID, driver hid-sony/hid-playstation"),
    ("050000004c050000cc09000000010000", 13, None,
     "DualShock 4 (second model) (054c:09cc) over Bluetooth by its GUID, but its driver (version 0x0100: the "
     "generic HID driver or Linux < 4.10) orders the buttons as no shipped layout does"),
    ("030000005e0400008e02000010010000", 11, "xbox", "Xbox pad (045e:028e) over USB by its GUID, driver xpad"),
    ("050000005e040000fd02000030110000", 11, None,
     "Xbox pad (045e:02fd) over Bluetooth by its GUID: over Bluetooth it uses another driver (hid-microsoft or "
     "xpadneo) with another order; connect it with a USB cable"),
    ("060000005e040000fd02000030110000", 11, None,  # bus 0x06 (virtual): named by its number
     "Xbox pad (045e:02fd) over bus 0x06 by its GUID: over bus 0x06 it uses another driver (hid-microsoft or "
     "xpadneo) with another order; connect it with a USB cable"),
    ("050000004c050000e60c000000006800", 13, None,
     "054c:0ce6 is read through SDL's HIDAPI driver (GUID byte 14 is 0x68), whose raw order no shipped layout "
     "describes; open it with SDL_JOYSTICK_HIDAPI=0 as the node does"),
    ("030000004c050000e60c000011810000", 12, None,
     "DualSense (054c:0ce6) over USB by its GUID, driver hid-playstation, but it reports 6 axes and 12 buttons "
     "where layout dualsense needs 6 and 13"),
])
def test_the_reason_for_a_pad_known_by_its_guid_says_pad_ids_bus_and_driver(guid, buttons, layout, reason):
    assert identify_layout(guid, "some name", 6, buttons) == LayoutGuess(layout, reason)


@pytest.mark.parametrize("name, buttons, layout, reason", [
    ("DualSense Wireless Controller", 14, "dualsense_hid_generic",
     "DualSense by its name and its 14 buttons (the generic HID driver's count)"),
    ("DualSense Wireless Controller", 13, "dualsense", "DualSense by its name and its 13 buttons (hid-playstation's count)"),
    ("DualShock 4", 14, None,
     "DualShock 4 by its name, but its 14 buttons say the generic HID driver, whose order no shipped layout describes"),
    ("DualShock 4", 13, "dualshock4", "DualShock 4 by its name"),
    ("Microsoft X-Box 360 pad", 11, "xbox", "Xbox pad by its name (driver xpad)"),
    ("Nintendo Switch Pro Controller", 13, None,
     "'Nintendo Switch Pro Controller' (no vendor/product in its GUID) is not a pad the shipped layouts (%s) are "
     "known to fit" % LAYOUTS),
])
def test_the_reason_for_a_pad_known_by_its_name_alone(name, buttons, layout, reason):
    assert identify_layout("", name, 6, buttons) == LayoutGuess(layout, reason)


def test_an_xbox_pad_known_by_its_name_over_bluetooth_is_sent_to_a_usb_cable():
    unknown_ids_bluetooth = "05000000d62000000120000000000000"  # PowerA (20d6:2001)
    assert identify_layout(unknown_ids_bluetooth, "PowerA Xbox One Controller", 6, 11) == LayoutGuess(
        None, "Xbox pad by its name, over Bluetooth, where its order differs; connect it with a USB cable")


def test_a_sony_pad_no_layout_describes_is_named_with_its_ids():
    # a PlayStation 3 pad: Sony's vendor id, a product that is neither a DualShock 4 nor a DualSense
    assert identify_layout("050000004c0500006802000000800000", "Sony PLAYSTATION(R)3 Controller", 6, 17) == \
        LayoutGuess(None, "'Sony PLAYSTATION(R)3 Controller' (vendor:product 054c:0268) is not a pad the shipped "
                          "layouts (%s) are known to fit" % LAYOUTS)


@pytest.mark.parametrize("guid", ["030000004c050100cc09000011810000",   # the word after the vendor is not 0
                                  "030000004c050000cc09010011810000"])  # the word after the product is not 0
def test_a_guid_whose_padding_words_are_not_zero_holds_no_ids(guid):
    assert parse_sdl_guid(guid) is None


def test_a_bus_without_a_name_is_named_by_its_number():
    assert SdlGuid(0x06, 0x045E, 0x02FD, 0x1130, 0).bus_name() == "bus 0x06"
    assert SdlGuid(0x03, 0x045E, 0x02FD, 0x1130, 0).bus_name() == "USB"


def test_a_pad_named_ps4_controller_without_ids_is_a_dualshock_4():
    assert identify_layout("", "PS4 Controller", 6, 13) == LayoutGuess("dualshock4", "DualShock 4 by its name")
