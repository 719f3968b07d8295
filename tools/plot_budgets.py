"""Convergence curves of searches on different budgets, one picture (docs/method-search.md).

    python tools/plot_budgets.py docs/optimize/eel2d-budgets.png --title eel2d \
        --runs "default=runs/eel2d-default-s*" --runs "paper 16 x 100=runs/eel2d-paper-s*"

Each ``--runs LABEL=GLOB`` names run directories (``aquagait optimize --out``)
whose ``optimization.csv`` are drawn as best objective so far against samples
evaluated, one colour per label.
"""

import argparse
import glob
from pathlib import Path

from aquagait.viz import plot_budgets


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", help="the PNG to write")
    parser.add_argument("--runs", action="append", required=True, metavar="LABEL=GLOB")
    parser.add_argument("--title", default="")
    args = parser.parse_args()
    runs = {}
    for entry in args.runs:
        label, _, pattern = entry.partition("=")
        paths = sorted(Path(d) / "optimization.csv" for d in glob.glob(pattern)
                       if (Path(d) / "optimization.csv").is_file())  # fmt: skip
        if not paths:
            parser.error(f"--runs {entry}: no run directories match {pattern!r}")
        runs[label] = paths
    print(f"wrote {plot_budgets(runs, args.out, args.title)}")


if __name__ == "__main__":
    main()
