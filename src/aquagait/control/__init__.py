"""Control: sine gaits (``gait``), the PD servos that track them (``pd``), and how a
stable PD servo is applied over a step (``discretization``).

Above ``sim`` in the layers: the simulation receives a policy object and never
imports this package (see ``aquagait.sim`` for the seam).
"""

from aquagait.control.discretization import ServoStep, end_of_step, sampled
from aquagait.control.gait import KINDS, GaitSpec, SineGait, SwitchedGait, mix
from aquagait.control.pd import (
    PD,
    StablePD,
    apparent_inertia,
    gains,
    joint_angles,
    servo_figures,
)

__all__ = [
    "KINDS",
    "PD",
    "GaitSpec",
    "ServoStep",
    "SineGait",
    "StablePD",
    "SwitchedGait",
    "apparent_inertia",
    "end_of_step",
    "gains",
    "joint_angles",
    "mix",
    "sampled",
    "servo_figures",
]
