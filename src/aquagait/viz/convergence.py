"""The convergence plot of an optimization: best and mean objective per generation.

    from aquagait.viz import plot_convergence
    plot_convergence("runs/eel2d/optimization.csv", "runs/eel2d/convergence.png")

Reads the run's ``optimization.csv`` (``aquagait.optimize``); matplotlib is
imported inside the function (the ``viz`` extra).
"""

from __future__ import annotations

import csv
from pathlib import Path

from aquagait.viz.style import save_plot


def read_log(path) -> dict[str, list[float]]:
    """The per-generation columns of an ``optimization.csv``, as floats."""
    with open(path, newline="") as handle:
        rows = [row for row in csv.DictReader(handle) if row.get("generation", "").isdigit()]
    if not rows:
        raise ValueError(f"{path} has no generations logged; is it an optimization.csv?")
    columns = ("generation", "evaluations", "best", "mean", "sigma")
    return {key: [_number(row[key]) for row in rows] for key in columns}


def plot_convergence(log_path, out_path, title: str = "") -> Path:
    """Draw the best-so-far and the generation mean of the objective, and sigma.

    Args:
        log_path: the run's ``optimization.csv``.
        out_path: the PNG to write.
        title: a heading (e.g. the creature's name).
    Returns:
        the path written.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    log = read_log(log_path)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(6, 5), sharex=True, height_ratios=(3, 1))
    top.plot(log["generation"], log["mean"], color="0.6", label="generation mean")
    top.plot(log["generation"], log["best"], color="C3", linewidth=2, label="best so far")
    top.set_ylabel("objective E")
    top.legend(frameon=False)
    top.set_title(title)
    bottom.plot(log["generation"], log["sigma"], color="C0")
    bottom.set_ylabel("sigma")
    bottom.set_xlabel("generation")
    return save_plot(fig, out_path)


def plot_budgets(runs: dict[str, list], out_path, title: str = "") -> Path:
    """Best objective so far against samples evaluated, for searches on several budgets.

    Args:
        runs: ``{label: [optimization.csv, ...]}``, e.g. ``{"default": [...],
            "paper 16 x 100": [...]}``: one line per run, one colour per label.
        out_path: the PNG to write.
        title: a heading (e.g. the creature's name).
    Returns:
        the path written.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(figsize=(6.4, 4))
    for colour, (label, paths) in enumerate(runs.items()):
        for n, path in enumerate(paths):
            log = read_log(path)
            axes.step(log["evaluations"], log["best"], where="post", color=f"C{colour}",
                      alpha=0.85, label=label if n == 0 else None)  # fmt: skip
            axes.plot(log["evaluations"][-1], log["best"][-1], "o", color=f"C{colour}")
    axes.set_xlabel("samples evaluated")
    axes.set_ylabel("best objective E so far")
    axes.set_title(title)
    axes.legend(frameon=False)
    return save_plot(fig, out_path)


def _number(text: str) -> float:
    try:
        return float(text)
    except (TypeError, ValueError):
        return float("nan")
