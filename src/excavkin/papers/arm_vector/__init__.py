"""The excavator arm's vector model (reference, study, figures, CLI)."""
