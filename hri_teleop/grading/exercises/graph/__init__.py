"""Ex. 15: ``graph.yaml``, the student's computation graph, against the lab's pipeline as it runs.

``session``: the lab's reference pipeline on a private master, its graph read (inside the session
sandbox); ``judge``: the parts; ``check``: the check, the lab's graph cached, and its ``EXERCISE``.
"""
