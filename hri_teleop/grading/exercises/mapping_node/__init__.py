"""Ex. 5: ``scripts/mapping_node.py`` run as a node on a private master, fed counts, its /force_mapped judged.

``cases``: the public trace and the hidden inputs; ``session``: the node in lockstep with the grader's
counts (inside the session sandbox); ``judge``: its parts; ``check``: the check and its ``EXERCISE``.
"""
