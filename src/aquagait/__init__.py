"""aquagait: articulated creatures that swim in an incompressible fluid.

Implements Tan, Gu, Turk and Liu, "Articulated Swimming Creatures"
(SIGGRAPH 2011). The method is explained in docs/method-fluid.md,
docs/method-bodies.md, docs/method-coupling.md and docs/method-search.md, the
architecture in docs/development.md.

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
    Kp, Kd  PD gains
    D       (alone) the servos' implicit damping, Kd in the paper's stable PD
    Mt      M + dt D, the mass the pressure moves the body against
    qbar(t) the gait's reference joint angles [rad]
    n_f     a coupled face's normal, from the solid into the water
    J_f     (3 x nv) point Jacobian of the link that owns face f, at its centre
    B       (nv x cells) pressures beside coupled faces -> generalized force
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


def follow_path(creature, path, cycles: int = 10, out=None, video: bool = False, **options):
    """Swim a creature along a path with its learned manoeuvres (paper §5).

        run = ag.follow_path("eel2d", "circle:radius=0.6", cycles=12, out="runs/eel-circle")
        run.metrics["path_distance_mean_body_lengths"], run.decisions

    Args:
        creature: a library creature's name or the path of an MJCF file.
        path: a CSV or JSON file of points [m], a shape ``NAME[:key=value,...]``
            (line, circle, s-curve), or an ``aquagait.path.Path``.
        cycles: gait cycles to swim.
        out: a run directory to write (``aquagait.app.follow.write_follow``), or None.
        video: with ``out``, also the video with the path and the picture of the way.
        **options: ``learned``, ``resolution``, ``cell_size``, ``dead_band``,
            ``blend``, ``open_loop``, ``fps``, ``fluid``, ``steer``
            (``aquagait.app.follow.prepare_follow``).

    Returns:
        ``aquagait.app.follow.FollowRun``: trajectory, decisions per cycle, the
        distance to the path per frame, metrics.
    """
    from aquagait.app.follow import prepare_follow, run_follow, write_follow

    run = run_follow(prepare_follow(creature, path, cycles, **options))
    if out is not None:
        write_follow(run, out, video=video)
    return run


__all__ = [
    "EulerFluid",
    "Grid",
    "SimpleFluid",
    "Vacuum",
    "__version__",
    "creatures",
    "follow_path",
    "init_state",
    "load_model",
    "make_scene",
    "rollout",
    "step",
]
