"""Control: sine gaits (``gait``) and the PD servos that track them (``pd``).

Above ``sim`` in the layers: the simulation receives a policy object and never
imports this package (see ``aquagait.sim`` for the seam).
"""

from aquagait.control.gait import KINDS, GaitSpec, SineGait, SwitchedGait, mix
from aquagait.control.pd import PD, StablePD, gains, joint_angles

__all__ = [
    "KINDS",
    "PD",
    "GaitSpec",
    "SineGait",
    "StablePD",
    "SwitchedGait",
    "gains",
    "joint_angles",
    "mix",
]
