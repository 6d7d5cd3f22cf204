"""Step 4 of grading: many submissions, as folders or through nbgrader, two at a time."""
