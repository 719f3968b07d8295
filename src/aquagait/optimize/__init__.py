"""Gait optimization: CMA-ES over a black-box objective (paper §4).

The optimizer knows nothing of physics (docs/development.md): it minimizes
`objective(x) -> float` over a box, rejecting infeasible samples before they
are evaluated, optimizing groups of parameters in turn, evaluating a
generation serially, in local processes or on a Dask cluster (same seed, same
result), and checkpointing every generation so that a killed run resumes to
exactly the result it would have reached. A lost executor (its Dask scheduler
died, no worker for too long) stops the run with `ExecutorLost`, the
interrupted generation unsaved, to be resumed on any executor.

    problem = Problem(objective, x0, lower, upper, feasible=within_joint_limits)
    with local_executor() as executor:
        result = optimize(problem, Settings(seed=1), executor, run_dir="runs/eel2d")

`Settings()` fits the budget to the problem (CMA-ES's population for the
number of parameters, stop when converged); `Settings.paper(2)` is the
paper's 16 x 100.
"""

from aquagait.optimize import checkpoint
from aquagait.optimize.checkpoint import CHECKPOINT, FAILURES, LOG, CorruptCheckpoint
from aquagait.optimize.cmaes import finished_run, optimize
from aquagait.optimize.evaluate import ExecutorLost, Outcome, evaluate
from aquagait.optimize.executors import (
    DaskExecutor,
    ProcessExecutor,
    dask_executor,
    local_executor,
)
from aquagait.optimize.problem import (
    GenerationReport,
    Problem,
    Result,
    Settings,
    default_patience,
    default_popsize,
)

__all__ = [
    "CHECKPOINT",
    "CorruptCheckpoint",
    "FAILURES",
    "LOG",
    "DaskExecutor",
    "ExecutorLost",
    "GenerationReport",
    "Outcome",
    "ProcessExecutor",
    "Problem",
    "Result",
    "Settings",
    "checkpoint",
    "dask_executor",
    "default_patience",
    "default_popsize",
    "evaluate",
    "finished_run",
    "local_executor",
    "optimize",
]
