"""Figures shared by the demos, the notebooks and the study analysis, drawn with matplotlib without a screen."""
