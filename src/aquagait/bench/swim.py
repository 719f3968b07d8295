"""``aquagait bench swim``: wall time per output frame of a coupled swim.

Each case swims a library creature with its shipped gait on its default
grid for half a second (the wake forms), then times whole frames (1/30 s simulated: the
CFL-limited coupled steps that make one frame). The baseline is the paper's
Table 1 (Tan et al. 2011, single core, C++, 2011) for the same grids: 0.64 s
per frame for the 2D eel at 128x64, 1.45 s for the fish at 64x32x32, up to
12.79 s for the frog at 96x64x48; a row for every library creature the paper
has. The target is 30x faster than the paper.

``--profile`` splits the coupled step into its phases (``profile``), and
``--compare-advection`` times the same frames with each advection scheme
beside the other (``compare_advection``), ``--compare-still`` with every
departure point traced at second order and with still water traced by one
Euler step (``compare_still``), ``--compare-precision`` with float64 and
float32 face velocities (``compare_precision``).
"""

from __future__ import annotations

import statistics
import time
from collections import defaultdict
from contextlib import contextmanager
from typing import TextIO

PAPER_SECONDS_PER_FRAME = {
    "accordion2d": 1.37, "eel2d": 0.64, "turtle2d": 0.34, "fish": 1.45, "eel3d": 1.31,
    "manta": 10.92, "turtle3d": 11.29, "frog": 12.79, "alien": 10.75,
}  # fmt: skip
"""Table 1 of the paper: seconds per frame on one 2.26 GHz core, at the same grids."""
TABLE_1 = tuple(PAPER_SECONDS_PER_FRAME)
"""The creatures timed by default: every one of the paper's Table 1."""
TARGET_RATIO = 30.0
WARMUP_FRAMES = 15

PHASES = {
    "voxelize": ("EulerFluid._voxels",),
    "advect": ("advect_velocity",),
    "predict body": ("servo_forces", "predict_body"),
    "coupled solve": ("EulerFluid._coupled_solve",),
    "rigid faces": ("rigid_faces_",),
    "move body, follow": ("move_body", "follow"),
}
"""The phases of ``EulerFluid.step`` (its docstring's algorithm box), by the
functions of ``aquagait.sim.fluids`` that make each one up."""


def run(repeats: int, out: TextIO) -> list[dict]:
    """Time ``repeats`` frames per creature and print the table; returns its rows."""
    import aquagait as ag

    print(
        f"{'creature':<10}{'grid':>11}{'s_per_frame':>13}{'steps':>7}{'paper_s':>9}"
        f"{'ratio':>8}{'target':>8}",
        file=out,
    )
    rows = []
    library = set(ag.creatures.names())
    for name, paper in PAPER_SECONDS_PER_FRAME.items():
        if name not in library:
            continue
        creature = ag.creatures.get(name)
        per_frame, steps = _time_frames(ag.make_scene(creature, fluid="euler"), creature, repeats)
        row = dict(
            creature=name,
            grid=_grid(creature),
            seconds_per_frame=per_frame,
            steps_per_frame=steps,
            paper=paper,
            ratio=paper / per_frame,
        )
        rows.append(row)
        print(
            f"{name:<10}{row['grid']:>11}{per_frame:>13.4f}{row['steps_per_frame']:>7.0f}"
            f"{paper:>9.2f}{row['ratio']:>7.1f}x{TARGET_RATIO:>7.0f}x",
            file=out,
            flush=True,
        )
    return rows


def profile(repeats: int, out: TextIO, creatures=TABLE_1) -> list[dict]:
    """Time each phase of the coupled step, per creature; print ms per step and share.

    The step itself carries no timing code: while the frames run, the phase
    functions that ``aquagait.sim.fluids`` calls are swapped for timed
    wrappers of themselves (``_timed_phases``), so the step timed is the step
    that runs. "other" is the rest of a frame's steps (CFL limit, checks,
    Python); "record frame" is the fluid plane a rollout keeps once per frame
    (``aquagait.sim.frames``), spread over the frame's steps.

    Returns:
        one dict per creature: name, grid, steps (timed), ms per step by phase.
    """
    import aquagait as ag
    from aquagait.sim import advance
    from aquagait.sim.frames import fluid_frame

    rows = []
    for name in creatures:
        creature = ag.creatures.get(name)
        scene = ag.make_scene(creature, fluid="euler")
        policy, state = _warmed_up(scene, creature)
        totals, steps, wall = defaultdict(float), 0, 0.0
        for _ in range(repeats):
            start, before = time.perf_counter(), state.steps
            with _timed_phases(totals):
                state = advance(scene, state, policy, state.time + 1 / 30)
            wall += time.perf_counter() - start
            steps += state.steps - before
            start = time.perf_counter()
            fluid_frame(scene, state)
            totals["record frame"] += time.perf_counter() - start
        totals["other"] = wall - sum(v for k, v in totals.items() if k != "record frame")
        ms = {phase: 1e3 * seconds / steps for phase, seconds in totals.items()}
        rows.append(dict(creature=name, grid=_grid(creature), steps=steps, ms_per_step=ms))
        _print_profile(rows[-1], out)
    return rows


@contextmanager
def _timed_phases(totals: dict):
    """Swap the phase functions of ``aquagait.sim.fluids`` for timed ones, then restore them."""
    from aquagait.sim import fluids

    saved = []
    for phase, names in PHASES.items():
        for name in names:
            owner, attr = (fluids.EulerFluid, name.split(".")[1]) if "." in name else (fluids, name)
            original = getattr(owner, attr)
            saved.append((owner, attr, original))
            setattr(owner, attr, _timed(original, phase, totals))
    try:
        yield
    finally:
        for owner, attr, original in reversed(saved):
            setattr(owner, attr, original)


def _timed(function, phase: str, totals: dict):
    def timed(*args, **kwargs):
        start = time.perf_counter()
        try:
            return function(*args, **kwargs)
        finally:
            totals[phase] += time.perf_counter() - start

    return timed


def _print_profile(row: dict, out: TextIO) -> None:
    ms = row["ms_per_step"]
    total = sum(ms.values())
    print(f"{row['creature']} {row['grid']}: {total:.2f} ms per step "
          f"({row['steps']} steps timed)", file=out)  # fmt: skip
    for phase in [*PHASES, "other", "record frame"]:
        share = 100 * ms.get(phase, 0.0) / total
        print(f"  {phase:<20}{ms.get(phase, 0.0):>9.3f} ms{share:>7.1f}%", file=out)
    out.flush()


def _warmed_up(scene, creature):
    """The creature's policy and its state after ``WARMUP_FRAMES`` frames of swimming."""
    import aquagait as ag
    from aquagait.sim import advance

    policy, state = creature.policy(), ag.init_state(scene)
    for _ in range(WARMUP_FRAMES):
        state = advance(scene, state, policy, state.time + 1 / 30)
    return policy, state


def _time_frames(scene, creature, repeats: int) -> tuple[float, float]:
    """Median wall time of a frame after the warm-up, and median steps per frame."""
    from aquagait.sim import advance

    policy, state = _warmed_up(scene, creature)
    seconds, steps = [], []
    for _ in range(repeats):
        start, before = time.perf_counter(), state.steps
        state = advance(scene, state, policy, state.time + 1 / 30)
        seconds.append(time.perf_counter() - start)
        steps.append(state.steps - before)
    return statistics.median(seconds), statistics.median(steps)


def _grid(creature) -> str:
    return "x".join(map(str, creature.resolution))


def compare_advection(repeats: int, out: TextIO, creatures=TABLE_1) -> list[dict]:
    """The coupled step with the previous and the current BFECC, in one run.

    Each creature swims the same frames once with each scheme
    (``EulerFluid(advect=...)``), frame about (``_interleaved_swims``);
    printed: ms per step of the advection phase and of the whole step, the
    schemes side by side with their ratio, and how far apart the two swims'
    roots end [m] (the same to round-off: the kernels' fused multiply-adds).

    Returns:
        one dict per creature with both schemes' figures.
    """
    from aquagait.fluid.advection import bfecc, bfecc_previous

    fluids = {"previous": dict(advect=bfecc_previous), "bfecc": dict(advect=bfecc)}
    return _two_fluids(out, repeats, creatures, fluids, ADVECT_AND_STEP, extra=_roots_apart)


def compare_still(repeats: int, out: TextIO, creatures=TABLE_1) -> list[dict]:
    """The coupled step with every departure point traced at second order, and with
    still water traced by one Euler step (today's), in one run.

    ``bfecc(still=0)`` against ``bfecc`` (``aquagait.fluid.advection``, "Still
    water"); printed as ``compare_advection``: ms per step of the advection and
    of the whole step with their ratio, and how far apart the two swims' roots
    end [m].

    Returns:
        one dict per creature with both traces' figures.
    """
    from functools import partial

    from aquagait.fluid.advection import bfecc

    fluids = {"rk2": dict(advect=partial(bfecc, still=0.0)), "still": {}}
    return _two_fluids(out, repeats, creatures, fluids, ADVECT_AND_STEP, extra=_roots_apart)


def _roots_apart(first: dict, second: dict) -> tuple[dict, str]:
    """How far apart two swims' roots end [m]: a row's fields and its line."""
    import numpy as np

    dim = 2 if len(first["grid"].split("x")) == 2 else 3
    metres = float(np.linalg.norm(first["qpos"][:dim] - second["qpos"][:dim]))
    return {"apart": metres}, f"{'roots apart':>14}{metres:>20.2e} m"


def compare_precision(repeats: int, out: TextIO, creatures=TABLE_1) -> list[dict]:
    """The coupled step with float64 and float32 face velocities, in one run.

    Each creature swims the same frames once with each precision
    (``EulerFluid(dtype=...)``), frame about; printed: ms per step of the
    advection and of the whole step, side by side with their ratio (float64
    over float32: the speed-up), and how far apart the two swims' roots end
    [m] against the distance swum.

    Returns:
        one dict per creature with both precisions' figures.
    """
    import numpy as np

    fluids = {"float64": dict(dtype=np.float64), "float32": dict(dtype=np.float32)}
    return _two_fluids(out, repeats, creatures, fluids, ADVECT_AND_STEP, extra=_roots_apart)


def compare_boundary(repeats: int, out: TextIO, creatures=TABLE_1) -> list[dict]:
    """The coupled step on the staircase and with sub-cell boundaries, in one run.

    Each creature swims the same frames once with each boundary
    (``EulerFluid(boundary=...)``), frame about; printed: ms per step of the
    voxelization, the coupled solve and the whole step, and CG iterations per
    step, side by side with their ratio (sub-cell over staircase: the cost).

    Returns:
        one dict per creature with both boundaries' figures.
    """
    from aquagait.body.subcell import voxelize_subcell
    from aquagait.body.voxelize import voxelize

    fluids = {"staircase": dict(boundary=voxelize), "subcell": dict(boundary=voxelize_subcell)}
    figures = (("voxelize ms", "voxelize"), ("solve ms", "solve"), ("step ms", "step"),
               ("CG its", "iterations"))  # fmt: skip
    return _two_fluids(out, repeats, creatures, fluids, figures, ratio="cost", cost=True)


def compare_thin(repeats: int, out: TextIO, creatures=TABLE_1) -> list[dict]:
    """The coupled step before and after thin parts were closed, in one run.

    Before: water fractions alone, faces under half water held to the body once
    a step (``boundary=voxelize_fractions, mostly_water=0.5``); after: the
    default. Printed as ``compare_boundary``: ms per step of the voxelization,
    the coupled solve and the whole step, and CG iterations per step, with
    their ratio (after over before: the cost).
    """
    from aquagait.body.subcell import voxelize_fractions

    fluids = {"fractions": dict(boundary=voxelize_fractions, mostly_water=0.5), "closed": {}}
    figures = (("voxelize ms", "voxelize"), ("solve ms", "solve"), ("step ms", "step"),
               ("CG its", "iterations"))  # fmt: skip
    return _two_fluids(out, repeats, creatures, fluids, figures, ratio="cost", cost=True)


ADVECT_AND_STEP = (("advect ms", "advect"), ("step ms", "step"))


def _two_fluids(out: TextIO, repeats: int, creatures, fluids: dict, figures, extra=None,
                ratio="ratio", cost=False) -> list[dict]:  # fmt: skip
    """Each of ``creatures`` swum with each of two Euler fluids, frame about, in one run.

    Args:
        fluids: two labels, each with its ``EulerFluid`` keyword arguments.
        figures: (label, key) of the figures printed side by side with their
            ratio, the first over the second (``cost``: the second over the first).
        extra: ``extra(first, second) -> (fields, line)``: more fields for the
            row and a line printed below its figures.
        ratio: the ratio column's heading.
    Returns:
        one dict per creature: its name, grid, each fluid's figures by label, and
        ``extra``'s fields.
    """
    (a, b) = fluids
    print(f"{'creature':<10}{'grid':>11}{'':>14}{a:>10}{b:>10}{ratio:>8}", file=out)
    rows = []
    for name in creatures:
        first, second = _interleaved_swims(name, fluids, repeats).values()
        fields, line = extra(first, second) if extra else ({}, None)
        rows.append(dict(creature=name, grid=first["grid"], **{a: first, b: second}, **fields))
        for label, key in figures:
            x, y = first[key], second[key]
            _side_by_side(out, name, first["grid"], label, x, y, y / x if cost else x / y)
        if line:
            print(f"{'':<21}{line}", file=out)
        out.flush()
    return rows


def _side_by_side(out: TextIO, name: str, grid: str, label: str, a: float, b: float, ratio):
    """One row of a two-column comparison: the figure of each, and their ratio."""
    print(f"{name:<10}{grid:>11}{label:>14}{a:>10.2f}{b:>10.2f}{ratio:>7.2f}x", file=out)


def compare_start(repeats: int, out: TextIO, creatures=TABLE_1) -> list[dict]:
    """The coupled step as it was when the 3D-speed work began, beside today's.

    Three fluids swim the same frames, frame about: the start (the previous
    BFECC kernels, the staircase, solve tolerance 1e-5), today's step with the
    same staircase physics, and today's default (sub-cell boundaries).
    Printed: ms per step of advection, coupled solve and the whole step, CG
    iterations a step, and each column's speed-up over the start.

    Returns:
        one dict per creature with the three fluids' figures.
    """
    from aquagait.body.voxelize import voxelize
    from aquagait.fluid.advection import bfecc_previous

    fluids = {
        "start": dict(advect=bfecc_previous, boundary=voxelize, tolerance=1e-5),
        "staircase": dict(boundary=voxelize),
        "subcell": {},
    }
    print(f"{'creature':<10}{'grid':>11}{'':>14}" + "".join(f"{k:>11}" for k in fluids)
          + f"{'speed-up':>18}", file=out)  # fmt: skip
    rows = []
    for name in creatures:
        figures = _interleaved_swims(name, fluids, repeats)
        grid = figures["start"]["grid"]
        rows.append(dict(creature=name, grid=grid, **figures))
        for label, key in (("advect ms", "advect"), ("solve ms", "solve"),
                           ("step ms", "step"), ("CG its", "iterations")):  # fmt: skip
            values = [figures[k][key] for k in fluids]
            faster = (
                ""
                if key == "iterations"
                else "  ".join(f"{values[0] / v:.2f}x" for v in values[1:])
            )
            print(f"{name:<10}{grid:>11}{label:>14}"
                  + "".join(f"{v:>11.2f}" for v in values) + f"{faster:>18}", file=out)  # fmt: skip
        out.flush()
    return rows


class _CountingSolve:
    """``pcg`` that adds up its iterations (for the benchmark's table)."""

    def __init__(self):
        self.iterations = 0

    def __call__(self, *args, **kwargs):
        from aquagait.fluid.pcg import pcg

        result = pcg(*args, **kwargs)
        self.iterations += result.iterations
        return result


def _interleaved_swims(name: str, fluids: dict[str, dict], repeats: int) -> dict[str, dict]:
    """Swim ``name`` once per fluid, a frame of each in turn.

    Taking turns spreads the load of a shared machine over all of them alike.

    Args:
        name: a library creature.
        fluids: ``EulerFluid`` settings by column name (its solver is a
            counting ``pcg``).
        repeats: frames timed.
    Returns:
        per column: ms per step (voxelize, advect, coupled solve, whole step)
        over the timed frames, CG iterations per step, the grid and the final q.
    """
    import aquagait as ag
    from aquagait.sim import EulerFluid, advance

    creature = ag.creatures.get(name)
    swims = {}
    for column, settings in fluids.items():
        fluid = EulerFluid(solve=_CountingSolve(), **settings)
        scene = ag.make_scene(creature, fluid=fluid)
        policy, state = _warmed_up(scene, creature)
        swims[column] = dict(scene=scene, policy=policy, state=state, totals=defaultdict(float),
                             solve=fluid.solve, warm=fluid.solve.iterations)  # fmt: skip
    for _ in range(repeats):
        for swim in swims.values():
            state, start = swim["state"], time.perf_counter()
            with _timed_phases(swim["totals"]):
                swim["state"] = advance(swim["scene"], state, swim["policy"], state.time + 1 / 30)
            swim["totals"]["step"] += time.perf_counter() - start
            swim["totals"]["steps"] += swim["state"].steps - state.steps
    figures = {}
    for column, swim in swims.items():
        totals, steps = swim["totals"], swim["totals"]["steps"]
        figures[column] = dict(
            grid=_grid(creature),
            qpos=swim["state"].qpos,
            voxelize=1e3 * totals["voxelize"] / steps,
            advect=1e3 * totals["advect"] / steps,
            solve=1e3 * totals["coupled solve"] / steps,
            step=1e3 * totals["step"] / steps,
            iterations=(swim["solve"].iterations - swim["warm"]) / steps,
        )
    return figures
