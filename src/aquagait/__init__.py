"""aquagait: articulated creatures that swim in an incompressible fluid.

Implements Tan, Gu, Turk and Liu, "Articulated Swimming Creatures"
(SIGGRAPH 2011). See DESIGN.md for the method and the architecture.

Glossary of symbols (SI units throughout):

    h       cell size [m]
    dt      time step [s]
    rho     fluid density [kg/m^3] (water: 1000)
    u       face velocities, one array per axis [m/s]
    p       pressure at cell centres [Pa]
    L       the cell-centred Laplacian over fluid faces (unscaled: sum of p_i - p_j)
    D u     net outflow of a cell through its faces per unit face area [m/s]
    q, qd   generalized positions and velocities (MuJoCo qpos, qvel)
    M, c    mass matrix and bias forces of the articulated body
    Kp, Kd  PD gains; Mt = M + dt Kd
    A       coupled face area: h^2 in 3D, h * depth in 2D [m^2]
"""

from importlib.metadata import PackageNotFoundError, version

from aquagait import creatures
from aquagait.body.model import load_model
from aquagait.grid import Grid
from aquagait.sim import EulerFluid, SimpleFluid, Vacuum, init_state, make_scene, rollout, step

try:
    __version__ = version("aquagait")
except PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0.0.0+unknown"

__all__ = [
    "EulerFluid",
    "Grid",
    "SimpleFluid",
    "Vacuum",
    "__version__",
    "creatures",
    "init_state",
    "load_model",
    "make_scene",
    "rollout",
    "step",
]
