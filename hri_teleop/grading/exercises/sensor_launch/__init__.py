"""Ex. 6-7: ``launch/sensor.launch`` parsed with roslaunch's loader, then launched: /force_mapped flows in [0, 1].

``session``: the launch recorded on the grader's clock (inside the session sandbox); ``judge``: its
parts; ``check``: the check and its ``EXERCISE``.
"""
