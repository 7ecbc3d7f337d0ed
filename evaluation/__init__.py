"""Positioning metrics and test protocols (thesis ch. 6)."""
