"""Step 4 of grading: many submissions, as folders or through nbgrader, one per core at a time (or JOBS)."""
