"""Ex. 8-9: ``scripts/teleoperation.py``: its Teleoperation class against pad-event traces, then the node with a scripted pad.

``cases``: the public traces and hidden inputs; ``session``: the node on a private master (inside the
session sandbox); ``judge_parts`` (Ex. 8) and ``judge_node`` (Ex. 9): its parts; ``check``: the check
and its ``EXERCISE``.
"""
