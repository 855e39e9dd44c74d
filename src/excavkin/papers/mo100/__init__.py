"""Eremyants & Raiymbekova: the MO-100 crank-rocker hammer (reference, study, figures, CLI)."""
