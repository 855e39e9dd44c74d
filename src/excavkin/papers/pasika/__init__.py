"""Pasika & Koruniak: the cylinder–rocker module with an internal driving link; motion laws."""
