"""The Gradescope autograder of Task 4, one module per step of its work.

``build`` writes the zip, ``layout`` finds the hri_lab and the notebooks in an upload of any
folder layout, ``container`` is run_autograder's work and ``report`` writes results.json with
each part's visibility. How to build and upload it: grading/README.md, section Gradescope.
"""
