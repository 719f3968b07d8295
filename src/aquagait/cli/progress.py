"""Progress on stderr: a text bar for frames and swims, a line per search generation."""

from __future__ import annotations

import math
import sys
import time


class GenerationLine:
    """``progress(report)`` of an optimization: one line per generation on stderr.

    The line counts the samples penalized in the generation (failed: the
    simulation raised or gave nan; lost: the worker died; infeasible: outside
    the joint limits). A generation that loses more than an eighth of its
    population (``GenerationReport.lossy``) adds a warning line with the first
    reason; every reason is in the run's failures.csv.
    """

    def __init__(self, stream=None):
        self.stream = stream or sys.stderr

    def __call__(self, report) -> None:
        left = f"{report.remaining:.0f} s left" if math.isfinite(report.remaining) else ""
        planned = "" if report.planned is None else f"/{report.planned}"
        print(
            f"generation {report.generation:>3}{planned}  best {report.best:.4g}  "
            f"mean {report.mean:.4g}  sigma {report.sigma:.3g}  failed {report.failed}  "
            f"lost {report.lost}  infeasible {report.infeasible}  {report.elapsed:.0f} s  {left}",
            file=self.stream,
            flush=True,
        )
        if report.lossy:
            print(
                f"warning: generation {report.generation} lost {report.failures} of "
                f"{report.samples} samples ({report.failed} failed, {report.lost} lost); "
                f"first: {' '.join(report.reasons[0].split())} (all reasons: failures.csv)",
                file=self.stream,
                flush=True,
            )


class ProgressBar:
    """``progress(done, total)`` drawn as a one-line text bar on stderr.

    On a terminal the bar is redrawn in place every call; into a file or a
    pipe (logs, CI) it is written as a new line at every tenth of the work.
    """

    def __init__(self, label: str, width: int = 30, stream=None):
        self.label, self.width, self.stream = label, width, stream or sys.stderr
        self.start = time.perf_counter()
        self.live = getattr(self.stream, "isatty", lambda: False)()
        self.shown = -1

    def __call__(self, done: int, total: int) -> None:
        tenth = 10 * done // max(total, 1)
        if not self.live and tenth == self.shown:
            return
        self.shown = tenth
        filled = self.width * done // max(total, 1)
        elapsed = time.perf_counter() - self.start
        bar = "#" * filled + "-" * (self.width - filled)
        line = f"{self.label} [{bar}] {done}/{total} frames {elapsed:.1f} s"
        if self.live:
            end = "\n" if done >= total else ""
            print(f"\r{line}", end=end, file=self.stream, flush=True)
        else:
            print(line, file=self.stream, flush=True)


def fluid_bar():
    """``progress(fluid, done, total)``: one ``ProgressBar`` per fluid, labelled with it."""
    bars = {}
    return lambda fluid, done, total: bars.setdefault(fluid, ProgressBar(fluid))(done, total)
