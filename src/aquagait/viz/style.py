"""Colours shared by the 2D and the 3D pictures, and how a plot is written."""

from pathlib import Path

ROUTE = (0.85, 0.1, 0.1)
"""RGB of a path to follow (paper Figure 10: red)."""


def save_plot(fig, path, dpi: int = 100) -> Path:
    """Lay out a matplotlib figure, write it to ``path`` (PNG by its suffix), close it."""
    fig.tight_layout()
    path = Path(path)
    fig.savefig(path, dpi=dpi)
    import matplotlib.pyplot as plt  # the viz extra; a figure to save means it is there

    plt.close(fig)
    return path
