"""Step 1 of grading: what a deliverable is fed (inputs, reference traces) and where answers are marked."""
