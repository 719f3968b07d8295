"""What a fluid model is (the protocol ``Scene`` holds), and the registry of them by name.

A fluid model is an object passed to ``make_scene``, not a string tested in
branches (docs/development.md, "Layers"). Each has

    name                          'none', 'simple' or 'euler'
    max_dt                        its default longest step [s]
    bind(model, grid) -> model    the model with what it bakes for this creature
    init(scene, state) -> State   the state with its fields at rest
    step(scene, state, dt, policy) -> State
    longest_step(state, dt) -> float   the largest stable step now, at most dt
    memory(grid) -> int           bytes its fields and scratch take on this grid
    settings() -> dict            its parameters, for config.json

This module holds the protocol and the registry only, so that ``scene``
depends on it and the models themselves (``aquagait.sim.fluids``, which
registers ``Vacuum``, ``SimpleFluid`` and ``EulerFluid``) depend on
``scene``, not both ways. ``Scene`` and ``State`` are named here for the
annotations alone.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, ClassVar, Protocol

if TYPE_CHECKING:
    from aquagait.body.model import Model
    from aquagait.grid import Grid
    from aquagait.sim.scene import Scene, State


class FluidModel(Protocol):
    """What ``aquagait.sim`` asks of a fluid model (module docstring)."""

    name: ClassVar[str]
    max_dt: float

    def bind(self, model: Model, grid: Grid | None) -> FluidModel:
        """This model with what it bakes for the creature on this grid (None: no grid).

        Raises ValueError when the model cannot simulate it (e.g. no grid, or
        one too small)."""

    def init(self, scene: Scene, state: State) -> State:
        """``state`` with this fluid's fields at rest (face velocities [m/s], pressure [Pa])."""

    def step(self, scene: Scene, state: State, dt: float, policy) -> State:
        """The state ``dt`` [s] later under ``policy`` (``aquagait.sim.servo``)."""

    def longest_step(self, state: State, dt: float) -> float:
        """The largest stable step [s] from ``state``, at most ``dt``."""

    def memory(self, grid: Grid) -> int:
        """The bytes its fields and scratch take at the peak of a swim on ``grid`` (0:
        none); ``make_scene`` refuses a grid whose estimate does not fit. Optional: a model
        without it is not checked."""

    def settings(self) -> dict:
        """The model's parameters as plain values, for ``config.json``."""


FLUIDS: dict[str, type] = {}
"""The fluid models by name, for ``make_scene(fluid="euler")`` and the command line
(``aquagait.sim.fluids`` registers its three on import)."""

REQUIRED = ("bind", "init", "step", "longest_step", "max_dt")
"""What an object needs to be taken for a fluid model."""


def register(model: type) -> type:
    """Add a fluid model class to ``FLUIDS`` under its ``name``; returns the class, so it
    decorates one.

    Raises:
        ValueError: another class is registered under that name.
    """
    known = FLUIDS.get(model.name)
    if known is not None and known is not model:
        raise ValueError(
            f"a fluid model called {model.name!r} is registered already ({known.__qualname__}); "
            "give the new one another name"
        )
    FLUIDS[model.name] = model
    return model


def fluid_model(fluid) -> FluidModel:
    """A fluid model from itself or its name ('none', 'simple', 'euler').

    Raises:
        ValueError: an unknown name.
        TypeError: neither a name nor an object with the protocol's methods.
    """
    if isinstance(fluid, str):
        if fluid not in FLUIDS:
            raise ValueError(f"unknown fluid {fluid!r}; fluids: {', '.join(FLUIDS)}")
        return FLUIDS[fluid]()
    if all(hasattr(fluid, a) for a in REQUIRED):
        return fluid
    raise TypeError(
        f"fluid must be a fluid model (Vacuum(), SimpleFluid(), EulerFluid()) or one of "
        f"{', '.join(map(repr, FLUIDS))}; got {fluid!r}"
    )
