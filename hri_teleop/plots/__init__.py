"""Figures shared by the demos, the notebooks and the study analysis (matplotlib, imported lazily)."""
