"""Step 3 of grading: one judge per deliverable, comparing what it did with the reference."""
