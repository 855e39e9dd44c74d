"""Studies over families of designs: tolerance and pin-clearance bands."""
