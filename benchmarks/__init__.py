"""Benchmarks of the lab's claims (``make bench``): feedback latency, command timing,
simulation speed, grading throughput and notebook/setup times.

Every benchmark measures its figure and, in the same run, the reference it is judged
against, so the ratio holds on a noisy shared machine. Each one gives rows of
:class:`benchmarks.report.BenchRow`; ``python -m benchmarks`` prints them as
one table and writes ``results.json`` and ``results.md``.
"""
