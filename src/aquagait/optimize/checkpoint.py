"""Checkpoints and the logs (per generation, per penalized sample) of an optimization run.

After every generation the run writes `checkpoint.pkl` (the CMA-ES state with
the random generator it draws from, the best so far, the history),
`optimization.csv` (one row per generation: progress, and how many samples
failed, were lost or were infeasible) and `failures.csv` (one row per sample
that got the penalty: generation, group, sample index, status, the reason in
full, and its parameters; just the header while there is none). Each is
written to a temporary file in the same directory, flushed to disk and renamed
over the old one (`os.replace` is atomic), so a process killed at any moment,
SIGKILL included, leaves the last complete checkpoint behind, never a torn one.

The checkpoint is a pickle: load only run directories you wrote yourself.
"""

from __future__ import annotations

import csv
import io
import math
import os
import pickle
import tempfile
from pathlib import Path

import numpy as np

from aquagait.optimize.problem import Problem, Settings

CHECKPOINT = "checkpoint.pkl"
"""The checkpoint's file name in the run directory (``load``, ``save``)."""

LOG = "optimization.csv"
"""The log's file name: a row per generation, its columns ``LOG_COLUMNS``."""

FAILURES = "failures.csv"
"""The penalized samples' file name: a row each, its columns ``FAILURE_COLUMNS`` and the
parameters."""

FORMAT = 1  # bump when the checkpoint's layout changes

LOG_COLUMNS = (
    "generation",
    "group",
    "evaluations",
    "best",
    "mean",
    "sigma",
    "elapsed",
    "generation_best",
    "failures",
    "infeasible",
    "resamples",
    "failed",
    "lost",
    "refinements",
    "modelled",
    "tau",
)
FAILURE_COLUMNS = ("generation", "group", "sample", "status", "reason")


def fingerprint(problem: Problem, settings: Settings) -> dict:
    """What a checkpoint must share with a run that resumes it: the problem's shape, the
    settings, and the objective, where it says what makes it the same function: a dict
    from its ``fingerprint()`` method (and the refining objective's, as ``target``)."""
    values = {
        "parameters": problem.size,
        "x0": problem.x0.tolist(),
        "lower": problem.lower.tolist(),
        "upper": problem.upper.tolist(),
        "sigma0": problem.sigma0,
        "groups": [group.tolist() for group in problem.groups],
        "feasible": problem.feasible is not None,
        **_settings(problem, settings),
    }
    for key, objective in (("objective", problem.objective), ("target", problem.refine)):
        describe = getattr(objective, "fingerprint", None)
        if callable(describe):
            values[key] = describe()
    return values


LATER = ("objective", "target")
"""Fingerprint entries newer than some checkpoints: one without them resumes unchecked there."""


def _settings(problem: Problem, settings: Settings) -> dict:
    """The settings that shape the run: `refine_top` only for a coarse-to-fine one and the
    surrogate's only for a search with one, so checkpoints written before they existed
    still resume."""
    values = settings.as_dict()
    if problem.refine is None:
        del values["refine_top"]
    else:
        values["refine"] = True
    if not settings.surrogate:
        del values["surrogate"], values["surrogate_batch"]
    return values


def mismatch(saved: dict, wanted: dict) -> list[str]:
    """The differences between a checkpoint's fingerprint and this run's, in words; a
    dict entry by its own entries (``objective.weights.deviation: ...``)."""

    def brief(value):
        text = repr(value)
        return text if len(text) <= 60 else text[:57] + "..."

    wanted = {key: value for key, value in wanted.items() if key in saved or key not in LATER}
    saved, wanted = _flat(saved), _flat(wanted)
    keys = list(wanted) + [key for key in saved if key not in wanted]
    return [
        f"{key}: {brief(saved.get(key))} in the checkpoint, {brief(wanted.get(key))} now"
        for key in keys
        if saved.get(key) != wanted.get(key)
    ]


def _flat(values: dict, prefix: str = "") -> dict:
    """Nested dicts' entries under dotted keys."""
    flat = {}
    for key, value in values.items():
        if isinstance(value, dict):
            flat.update(_flat(value, f"{prefix}{key}."))
        else:
            flat[prefix + key] = value
    return flat


def save(run_dir: Path, state: dict) -> None:
    """Write `state` to run_dir/checkpoint.pkl atomically."""
    _write_atomically(Path(run_dir) / CHECKPOINT, pickle.dumps({"format": FORMAT, **state}))


class CorruptCheckpoint(ValueError):
    """A checkpoint that is there but cannot be read: damaged, or not a checkpoint."""


def load(run_dir: Path) -> dict:
    """Read run_dir/checkpoint.pkl.

    Raises:
        FileNotFoundError: there is none.
        CorruptCheckpoint: it cannot be unpickled into a checkpoint (the message names
            the file, says that nothing else was touched and what to do).
        ValueError: it was written in another checkpoint format.
    """
    path = Path(run_dir) / CHECKPOINT
    if not path.is_file():
        raise FileNotFoundError(
            f"no checkpoint {path}: nothing to resume. Start a new run without resume."
        )
    try:
        with path.open("rb") as file:
            state = pickle.load(file)
    except Exception as err:  # a damaged pickle raises almost anything, by its first bytes
        raise CorruptCheckpoint(_unreadable(path, f"{type(err).__name__}: {err}")) from err
    if not isinstance(state, dict):
        raise CorruptCheckpoint(_unreadable(path, f"it holds a {type(state).__name__}"))
    if state.get("format") != FORMAT:
        raise ValueError(
            f"{path} has checkpoint format {state.get('format')!r}; this aquagait reads {FORMAT}"
        )
    return state


def _unreadable(path: Path, why: str) -> str:
    return (
        f"the checkpoint {path} cannot be read ({why}): it is damaged or not a checkpoint. "
        f"Nothing else in {path.parent} was touched: {LOG} and {FAILURES} hold the "
        "generations run so far. Restore the file from a copy to resume, or start "
        "the search again in another directory."
    )


def write_log(run_dir: Path, history: list[dict], names: tuple[str, ...]) -> None:
    """Write run_dir/optimization.csv: one row per generation, then the best x so far."""
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow([*LOG_COLUMNS, *names])
    for row in history:  # rows of checkpoints written before a column existed leave it empty
        writer.writerow(
            [_cell(row.get(key, "")) for key in LOG_COLUMNS] + [_cell(v) for v in row["best_x"]]
        )
    _write_atomically(Path(run_dir) / LOG, text.getvalue().encode())


def write_failures(run_dir: Path, history: list[dict], names: tuple[str, ...]) -> None:
    """Write run_dir/failures.csv: one row per penalized sample, with its reason and x."""
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow([*FAILURE_COLUMNS, *names])
    for row in history:
        for sample in row.get("penalized", ()):
            cells = [row["generation"], row["group"], sample["sample"], sample["status"]]
            writer.writerow([*cells, sample["reason"], *(_cell(v) for v in sample["x"])])
    _write_atomically(Path(run_dir) / FAILURES, text.getvalue().encode())


def remove_leftovers(run_dir: Path) -> None:
    """Delete temporary files a killed run left half written (never read)."""
    for name in (CHECKPOINT, LOG, FAILURES):
        for leftover in Path(run_dir).glob(f".{name}.*"):
            leftover.unlink(missing_ok=True)


def _cell(value) -> str:
    if isinstance(value, float | np.floating):
        return "nan" if math.isnan(value) else repr(float(value))
    return str(value)


def _write_atomically(path: Path, data: bytes) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    descriptor, temporary = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.")
    try:
        with os.fdopen(descriptor, "wb") as file:
            file.write(data)
            file.flush()
            os.fsync(file.fileno())
        os.replace(temporary, path)
    except BaseException:
        Path(temporary).unlink(missing_ok=True)
        raise
