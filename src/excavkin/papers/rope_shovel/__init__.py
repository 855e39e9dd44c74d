"""Maksimov: the EO-4112 rope backhoe's bucket-turning mechanism."""
