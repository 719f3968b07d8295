"""The creature library: a registry of named creatures (STYLE.md §14).

A creature is an MJCF model plus what the rest of aquagait needs to swim it:
the gait's parameterization and bounds, a hand-set default gait, the default
fluid grid, the energy bound of the objective and the PD servo gains.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from aquagait.body.model import Model, load_model
from aquagait.control.gait import GaitSpec
from aquagait.control.pd import StablePD

HERE = Path(__file__).resolve().parent
ENERGY_COEFFICIENT = 5.0
"""Energy bound = ENERGY_COEFFICIENT * mass * (body_length / period)^2 over two cycles.

Estimate: the body swings about 0.1 L at 2 pi / T, so at speeds v^2 ~ 0.4 (L/T)^2,
accelerating its own mass plus about as much added water mass; |tau qd| counts
speeding up and slowing down, four times a cycle: ~1.6 m (L/T)^2 per cycle,
~3.2 over two, rounded up to 5. Calibrate once the fluid is coupled.
"""


class UnknownCreatureError(KeyError):
    """No creature of that name; the message lists the known ones."""

    def __str__(self) -> str:
        return str(self.args[0])


@dataclass(frozen=True, eq=False)
class Creature:
    """A library creature.

    Attributes:
        name: registry name.
        model: the checked MJCF model.
        gait: which sine parameters are optimized, and their bounds.
        default_gait: (gait.size,) a hand-set travelling wave, within bounds and limits.
        resolution: default grid cells per axis, (nx, ny) or (nx, ny, nz).
        cell_size: default h [m].
        energy_bound: [J] actuator work over two cycles above which the
            objective's energy term switches on (DESIGN.md §2.4).
        natural_frequency: PD servo w [rad/s] (see ``aquagait.control.pd``).
        damping_ratio: PD servo zeta.
        description: one line.
    """

    name: str
    model: Model
    gait: GaitSpec
    default_gait: np.ndarray
    resolution: tuple[int, ...]
    cell_size: float
    energy_bound: float
    natural_frequency: float = 100.0
    damping_ratio: float = 1.5
    description: str = ""

    def __post_init__(self):
        object.__setattr__(self, "default_gait", np.asarray(self.default_gait, dtype=float))
        _check_creature(self)

    @property
    def dim(self) -> int:
        return self.model.dim

    def gait_limits(self) -> tuple[np.ndarray, np.ndarray]:
        """Joint limits (lower, upper) of the gait's DOFs, each (n,) [rad]."""
        index = [list(self.model.dof_names).index(d) for d in self.gait.dofs]
        position = {int(d): i for i, d in enumerate(self.model.actuated_dofs)}
        rows = [position[i] for i in index]
        return self.model.lower[rows], self.model.upper[rows]

    def policy(self, params=None) -> StablePD:
        """The stable PD servo tracking gait ``params`` (default: ``default_gait``)."""
        x = self.default_gait if params is None else params
        gait = self.gait.unpack(x)
        return StablePD.tuned(self.model, gait, self.natural_frequency, self.damping_ratio)


def energy_bound(model: Model, period: float = 1.0) -> float:
    """The energy bound [J] of a creature over two cycles (see ``ENERGY_COEFFICIENT``)."""
    return ENERGY_COEFFICIENT * model.mass * (model.body_length / period) ** 2


def load_creature_model(filename: str) -> Model:
    """Load an MJCF shipped with the package (``aquagait/creatures/<filename>``)."""
    return load_model(HERE / filename)


def _check_creature(c: Creature) -> None:
    actuated = {c.model.dof_names[d] for d in c.model.actuated_dofs}
    missing = [d for d in c.gait.dofs if d not in actuated]
    if missing:
        raise ValueError(f"creature {c.name!r}: gait DOFs {missing} are not actuated DOFs")
    if c.default_gait.shape != (c.gait.size,):
        raise ValueError(
            f"creature {c.name!r}: default gait has {c.default_gait.size} numbers, "
            f"the gait has {c.gait.size}: {c.gait.names}"
        )
    outside = (c.default_gait < c.gait.lower) | (c.default_gait > c.gait.upper)
    if np.any(outside):
        names = [n for n, o in zip(c.gait.names, outside, strict=True) if o]
        raise ValueError(f"creature {c.name!r}: default gait outside its bounds at {names}")
    violations = c.gait.limit_violations(c.default_gait, *c.gait_limits())
    if violations:
        raise ValueError(f"creature {c.name!r}: default gait leaves joint limits: {violations}")
    if len(c.resolution) != c.dim:
        raise ValueError(f"creature {c.name!r}: resolution {c.resolution} is not {c.dim}D")
    span = np.asarray(c.resolution) * c.cell_size
    need = c.model.extent[: c.dim] + 8 * c.cell_size
    if np.any(span < need):
        raise ValueError(
            f"creature {c.name!r}: grid {c.resolution} x {c.cell_size} m spans {span} m, "
            f"too small for a body of extent {c.model.extent[: c.dim]} m plus 4 cells a side"
        )


_FACTORIES: dict[str, Callable[[], Creature]] = {}
_BUILT: dict[str, Creature] = {}


def register(name: str, creature: Creature | Callable[[], Creature], replace: bool = False):
    """Add a creature (or a function that builds one on first ``get``) to the library.

    Raises:
        ValueError: the name is taken and ``replace`` is False.
    """
    if name in _FACTORIES and not replace:
        raise ValueError(f"creature {name!r} is already registered; pass replace=True")
    _FACTORIES[name] = creature if callable(creature) else (lambda: creature)
    _BUILT.pop(name, None)


def names() -> list[str]:
    """Registered creature names, sorted."""
    return sorted(_FACTORIES)


def get(name: str) -> Creature:
    """The creature called ``name`` (built on first use, then cached)."""
    if name not in _FACTORIES:
        raise UnknownCreatureError(
            f"unknown creature {name!r}; known creatures: {', '.join(names())}"
        )
    if name not in _BUILT:
        _BUILT[name] = _FACTORIES[name]()
    return _BUILT[name]


def format_table() -> str:
    """The library as a text table: name, dim, DOFs, optimized parameters, grid, cell size."""
    header = ("name", "dim", "DOFs", "optimized parameters", "default grid", "cell size")
    rows = [header]
    for name in names():
        c = get(name)
        rows.append(
            (
                name,
                f"{c.dim}D",
                str(len(c.model.actuated_dofs)),
                str(c.gait.size),
                "x".join(str(n) for n in c.resolution),
                f"{c.cell_size * 1000:g} mm",
            )
        )
    widths = [max(len(r[i]) for r in rows) for i in range(len(header))]
    lines = [
        "  ".join(cell.ljust(w) for cell, w in zip(row, widths, strict=True)).rstrip()
        for row in rows
    ]
    return "\n".join(lines)
