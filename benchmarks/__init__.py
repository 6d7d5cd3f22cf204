"""Benchmarks of the lab's claims (``make bench``), each figure beside a reference from the same run.

Feedback latency, command timing, simulation speed, grading throughput and notebook/setup times;
measuring the reference in the same run keeps the ratio true on a noisy shared machine. Each
benchmark gives rows of :class:`benchmarks.report.BenchRow`; ``python -m benchmarks`` prints them as
one table and writes ``results.json`` and ``results.md``. What each row measures: docs/benchmarks.md.
"""
