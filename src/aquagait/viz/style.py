"""Colours shared by the 2D and the 3D pictures."""

ROUTE = (0.85, 0.1, 0.1)
"""RGB of a path to follow (paper Figure 10: red)."""
