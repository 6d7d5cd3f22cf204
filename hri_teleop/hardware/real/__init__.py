"""The real devices: a pygame gamepad, the Arduino over a serial port."""
