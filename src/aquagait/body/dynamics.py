"""Articulated-body dynamics: the one adapter to MuJoCo (docs/method-bodies.md).

MuJoCo supplies the mass matrix ``M(q)``, the bias forces ``c(q, qd)``
(Coriolis and centrifugal; gravity is switched off because creatures are
neutrally buoyant), link poses, link Jacobians and position integration
(quaternions for free and ball joints). Our own code decides the forces and
the accelerations; nothing here steps MuJoCo's simulator, so MJCF contacts,
actuators and joint limits play no part in the motion.

Conventions:

- ``q`` (nq,) and ``qd`` (nv,) are MuJoCo's ``qpos`` and ``qvel``. A free
  joint's ``qd`` is (world linear velocity of the body origin, angular
  velocity in the body frame); a ball joint's angular velocity is in the
  child body's frame.
- A *link* is a MuJoCo body other than the world: link ``k`` is body ``k + 1``.
- Lengths in metres, masses in kilograms, angles in radians.

Nothing outside ``aquagait.body`` should touch the ``mujoco`` objects held here.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass
from pathlib import Path

import mujoco
import numba
import numpy as np

JOINT_KINDS = {
    int(value): name.removeprefix("mjJNT_").lower()
    for name, value in mujoco.mjtJoint.__members__.items()
}
GEOM_KINDS = {
    int(value): name.removeprefix("mjGEOM_").lower()
    for name, value in mujoco.mjtGeom.__members__.items()
    if name != "mjNGEOMTYPES"
}


def compile_mjcf(path: str | Path | None = None, xml: str | None = None):
    """Compile an MJCF file or string into a MuJoCo model with gravity off.

    Args:
        path: an MJCF file (meshes and includes resolve relative to it), or
        xml: the MJCF text (meshes must be inline or given by absolute path).

    Returns:
        The compiled ``mujoco.MjModel`` (opaque to the rest of aquagait).

    Raises:
        ValueError: MuJoCo's own compiler message, unchanged.
    """
    if path is not None:
        mj = mujoco.MjModel.from_xml_path(str(path))
    else:
        mj = mujoco.MjModel.from_xml_string(xml)
    mj.opt.gravity[:] = 0.0
    return mj


def compose_mjcf(parts):
    """One MuJoCo model of several MJCF trees under one world, each renamed ``LABEL/NAME``.

    The trees keep their order, so part ``i``'s links, joints, positions and
    velocities follow part ``i - 1``'s, each in its own order; their mass
    matrix is block-diagonal (nothing joins them).

    Args:
        parts: ``(label, mjcf_text)`` pairs, each a model with one root body
            (``Model.mjcf``).

    Returns:
        ``(mj, xml)``: the compiled model with gravity off, and its MJCF text.
    """
    spec = mujoco.MjSpec()
    spec.option.gravity = [0.0, 0.0, 0.0]
    for label, xml in parts:
        child = mujoco.MjSpec.from_string(xml)
        spec.worldbody.add_frame().attach_body(child.worldbody.first_body(), f"{label}/", "")
    mj = spec.compile()
    return mj, spec.to_xml()


@dataclass(frozen=True)
class CompiledFacts:
    """What the model loader needs to know of a compiled MJCF, at ``q = qpos0``.

    Per link (nb = number of links, world excluded): ``link_names``, ``parent``
    (link index of the parent, -1 for the world), ``link_mass`` [kg],
    ``link_pos`` (nb, 3) and ``link_rot`` (nb, 3, 3) world frames [m];
    ``link_inertia`` (nb, 3) principal moments [kg m^2] about the centre of
    mass ``link_ipos`` (nb, 3) [m], in axes ``link_iquat`` (nb, 4) (w, x, y,
    z), both in the link's own frame, as MuJoCo computed them.
    Per joint (nj): ``joint_names``, ``joint_kind`` ('free', 'ball', 'slide',
    'hinge'), ``joint_link``, ``joint_qpos``, ``joint_dof`` (addresses),
    ``joint_axis`` (nj, 3) world axis, ``joint_limited``, ``joint_range``
    (nj, 2) [rad or m], ``joint_passive`` (stiffness or damping is set).
    Per geom (ng): ``geom_names``, ``geom_kind`` ('box', 'mesh', ...),
    ``geom_link``, ``geom_size`` (ng, 3), ``geom_pos`` (ng, 3), ``geom_rot``
    (ng, 3, 3) world frames, ``geom_vertices`` (list of (nv_i, 3) world mesh
    vertices or None), ``geom_box`` (ng, 2, 3) world axis-aligned bounds [m],
    ``geom_rgba`` (ng, 4) colour in [0, 1] (its material's where the geom sets none),
    ``geom_group`` (ng,) MuJoCo's visibility group (0-2 shown by its viewer),
    ``geom_local_pos`` (ng, 3) and ``geom_local_quat`` (ng, 4) its frame in its link's.
    ``numeric``: the MJCF ``<custom><numeric>`` entries; ``qpos0`` (nq,); ``nv``.
    """

    link_names: tuple[str, ...]
    parent: np.ndarray
    link_mass: np.ndarray
    link_pos: np.ndarray
    link_rot: np.ndarray
    link_inertia: np.ndarray
    link_ipos: np.ndarray
    link_iquat: np.ndarray
    joint_names: tuple[str, ...]
    joint_kind: tuple[str, ...]
    joint_link: np.ndarray
    joint_qpos: np.ndarray
    joint_dof: np.ndarray
    joint_axis: np.ndarray
    joint_limited: np.ndarray
    joint_range: np.ndarray
    joint_passive: np.ndarray
    geom_names: tuple[str, ...]
    geom_kind: tuple[str, ...]
    geom_link: np.ndarray
    geom_size: np.ndarray
    geom_pos: np.ndarray
    geom_rot: np.ndarray
    geom_vertices: tuple
    geom_box: np.ndarray
    geom_rgba: np.ndarray
    geom_group: np.ndarray
    geom_local_pos: np.ndarray
    geom_local_quat: np.ndarray
    numeric: dict
    qpos0: np.ndarray
    nv: int


def _names(mj, objtype, count: int) -> tuple[str, ...]:
    return tuple(mujoco.mj_id2name(mj, objtype, i) or "" for i in range(count))


def describe(mj, qpos=None) -> CompiledFacts:
    """The facts of a compiled model at its reference pose ``qpos0`` (see CompiledFacts), or
    with its links and geoms at ``qpos`` (nq,) where given."""
    data = mujoco.MjData(mj)
    if qpos is not None:
        data.qpos[:] = qpos
    mujoco.mj_kinematics(mj, data)
    vertices = []
    for g in range(mj.ngeom):
        mesh = mj.geom_dataid[g]
        if mj.geom_type[g] != mujoco.mjtGeom.mjGEOM_MESH or mesh < 0:
            vertices.append(None)
            continue
        start, count = mj.mesh_vertadr[mesh], mj.mesh_vertnum[mesh]
        local = mj.mesh_vert[start : start + count].astype(float)
        vertices.append(data.geom_xpos[g] + local @ data.geom_xmat[g].reshape(3, 3).T)
    centre, half = mj.geom_aabb[:, :3], mj.geom_aabb[:, 3:]
    rot = data.geom_xmat.reshape(-1, 3, 3)
    world_centre = data.geom_xpos + np.einsum("gij,gj->gi", rot, centre)
    world_half = np.einsum("gij,gj->gi", np.abs(rot), half)
    numeric = {
        mujoco.mj_id2name(mj, mujoco.mjtObj.mjOBJ_NUMERIC, i): mj.numeric_data[
            mj.numeric_adr[i] : mj.numeric_adr[i] + mj.numeric_size[i]
        ].copy()
        for i in range(mj.nnumeric)
    }
    return CompiledFacts(
        link_names=_names(mj, mujoco.mjtObj.mjOBJ_BODY, mj.nbody)[1:],
        parent=mj.body_parentid[1:] - 1,
        link_mass=mj.body_mass[1:].copy(),
        link_pos=data.xpos[1:].copy(),
        link_rot=data.xmat[1:].reshape(-1, 3, 3).copy(),
        link_inertia=mj.body_inertia[1:].copy(),
        link_ipos=mj.body_ipos[1:].copy(),
        link_iquat=mj.body_iquat[1:].copy(),
        joint_names=_names(mj, mujoco.mjtObj.mjOBJ_JOINT, mj.njnt),
        joint_kind=tuple(JOINT_KINDS[int(t)] for t in mj.jnt_type),
        joint_link=mj.jnt_bodyid - 1,
        joint_qpos=mj.jnt_qposadr.copy(),
        joint_dof=mj.jnt_dofadr.copy(),
        joint_axis=data.xaxis.copy(),
        joint_limited=mj.jnt_limited.astype(bool),
        joint_range=mj.jnt_range.copy(),
        joint_passive=(mj.jnt_stiffness != 0) | (mj.dof_damping[mj.jnt_dofadr] != 0),
        geom_names=_names(mj, mujoco.mjtObj.mjOBJ_GEOM, mj.ngeom),
        geom_kind=tuple(GEOM_KINDS.get(int(t), str(t)) for t in mj.geom_type),
        geom_link=mj.geom_bodyid - 1,
        geom_size=mj.geom_size.copy(),
        geom_pos=data.geom_xpos.copy(),
        geom_rot=rot.copy(),
        geom_vertices=tuple(vertices),
        geom_box=np.stack([world_centre - world_half, world_centre + world_half], axis=1),
        geom_rgba=_geom_rgba(mj),
        geom_group=mj.geom_group.copy(),
        geom_local_pos=mj.geom_pos.copy(),
        geom_local_quat=mj.geom_quat.copy(),
        numeric=numeric,
        qpos0=mj.qpos0.copy(),
        nv=mj.nv,
    )


def _geom_rgba(mj) -> np.ndarray:
    """Each geom's colour (ng, 4): its own ``rgba``, or its material's where it has one
    and left ``rgba`` at MuJoCo's default grey (as MuJoCo's own renderer does)."""
    rgba = mj.geom_rgba.astype(float)
    default = np.all(rgba == [0.5, 0.5, 0.5, 1.0], axis=1)
    material = (mj.geom_matid >= 0) & default
    rgba[material] = mj.mat_rgba[mj.geom_matid[material]]
    return rgba


def massless_geoms(xml: str) -> np.ndarray:
    """Which geoms MuJoCo gives no mass, as the MJCF ``xml`` writes them.

    A geom's mass is its ``mass`` where given, else ``density`` times its volume
    (default classes resolved, as MuJoCo's compiler resolves them); a geom whose
    group lies outside the compiler's ``inertiagrouprange`` adds none. A
    body's ``<inertial>`` overrides its geoms' masses, but a geom written with
    mass 0 or density 0 is still massless here: that is how a file says a
    geom is only to be drawn (``aquagait.body.reshape.visual_only``).

    Args:
        xml: MJCF text that compiles (``compile_mjcf``).
    Returns:
        (ng,) bool, in the compiled model's geom order.
    """
    spec = mujoco.MjSpec.from_string(xml)
    spec.compile()  # numbers the geoms as the compiled model does
    lo, hi = spec.compiler.inertiagrouprange
    out = np.zeros(len(spec.geoms), dtype=bool)
    for geom in spec.geoms:
        given = not np.isnan(geom.mass)
        out[geom.id] = (geom.mass == 0 if given else geom.density == 0) or not (
            lo <= geom.group <= hi
        )
    return out


def mesh_faces(mj) -> tuple:
    """The triangles of every mesh geom, for building its inside test (``voxelize``).

    A mesh given by vertices only gets the faces of its convex hull (MuJoCo's
    compiler computes them); a mesh given with faces keeps its own, convex or
    not. MuJoCo's mass uses the same triangles, so a volume from them agrees
    with ``link_mass / density``.

    Args:
        mj: a compiled ``mujoco.MjModel``.
    Returns:
        per geom: an (nf, 3) int array of vertex indices into
        ``describe(mj).geom_vertices[g]``, counter-clockwise seen from outside
        (right-hand normals point out of the mesh); None for other geoms.
    """
    faces = []
    for g in range(mj.ngeom):
        mesh = mj.geom_dataid[g]
        if mj.geom_type[g] != mujoco.mjtGeom.mjGEOM_MESH or mesh < 0:
            faces.append(None)
            continue
        start, count = mj.mesh_faceadr[mesh], mj.mesh_facenum[mesh]
        faces.append(mj.mesh_face[start : start + count].astype(np.int64))
    return tuple(faces)


class Dynamics:
    """Mass matrix, bias forces, kinematics and integration of one articulated body.

    Built once per scene from a compiled model. Every method takes the
    configuration explicitly; results for the last ``q`` (and ``qd``) are
    cached, so asking for ``M``, ``c`` and Jacobians at the same state costs
    one kinematics pass.

    Threads: the ``MjModel`` is only read; the MuJoCo scratch ``MjData`` and
    the cache belong to the calling thread (one of each per thread, kept while
    the thread lives), so threads may share one ``Dynamics``, and a scene
    holding it, and each gets exactly its serial numbers (docs/development.md,
    "Layers"). Pickling keeps only the model; the scratch is rebuilt on
    first use, so a scene can be shipped to worker processes.

    Args:
        mj: a compiled ``mujoco.MjModel`` (from ``compile_mjcf``).
    """

    def __init__(self, mj):
        self.mj = mj
        self.nq, self.nv = mj.nq, mj.nv
        self.nlinks = mj.nbody - 1
        self.link_mass = mj.body_mass[1:].copy()
        self._local = threading.local()

    def __getstate__(self):
        return {"mj": self.mj}

    def __setstate__(self, state):
        self.__init__(state["mj"])

    # --- state and caches -------------------------------------------------
    def _at(self, q, qd=None) -> _Scratch:
        """This thread's scratch, brought to configuration ``q`` (and velocity ``qd``)."""
        s = getattr(self._local, "scratch", None)
        if s is None:
            s = self._local.scratch = _Scratch(mujoco.MjData(self.mj))
        d = s.data
        q = np.asarray(q, dtype=float)
        if q.shape != (self.nq,):
            raise ValueError(f"q has shape {q.shape}; this body has nq = {self.nq}")
        if s.q is None or not np.array_equal(q, s.q):
            d.qpos[:] = q
            mujoco.mj_kinematics(self.mj, d)
            mujoco.mj_comPos(self.mj, d)
            mujoco.mj_makeM(self.mj, d)
            s.q, s.qd, s.jac = q.copy(), None, None
        if qd is not None:
            qd = np.asarray(qd, dtype=float)
            if qd.shape != (self.nv,):
                raise ValueError(f"qd has shape {qd.shape}; this body has nv = {self.nv}")
            if s.qd is None or not np.array_equal(qd, s.qd):
                d.qvel[:] = qd
                mujoco.mj_comVel(self.mj, d)
                s.qd = qd.copy()
        return s

    def _jacobians(self, s: _Scratch) -> tuple[np.ndarray, np.ndarray]:
        """The cached link Jacobians at the scratch's ``q`` (not copies: read only)."""
        if s.jac is None:
            jacp = np.zeros((self.nlinks, 3, self.nv))
            jacr = np.zeros((self.nlinks, 3, self.nv))
            for k in range(self.nlinks):
                mujoco.mj_jacBody(self.mj, s.data, jacp[k], jacr[k], k + 1)
            s.jac = (jacp, jacr)
        return s.jac

    # --- dynamics ---------------------------------------------------------
    def mass_matrix(self, q) -> np.ndarray:
        """Joint-space inertia ``M(q)``, (nv, nv), symmetric positive definite [kg, kg m^2]."""
        d = self._at(q).data
        out = np.zeros((self.nv, self.nv))
        mujoco.mj_fullM(self.mj, d, out)
        return out

    def bias(self, q, qd) -> np.ndarray:
        """Bias forces ``c(q, qd)`` (Coriolis, centrifugal), (nv,) [N, N m]: ``M qdd + c = tau``."""
        d = self._at(q, qd).data
        out = np.zeros(self.nv)
        mujoco.mj_rne(self.mj, d, 0, out)
        return out

    # --- kinematics -------------------------------------------------------
    def link_poses(self, q) -> tuple[np.ndarray, np.ndarray]:
        """World frames of the links: origins (nlinks, 3) [m] and rotations (nlinks, 3, 3)."""
        d = self._at(q).data
        return d.xpos[1:].copy(), d.xmat[1:].reshape(-1, 3, 3).copy()

    def link_jacobians(self, q) -> tuple[np.ndarray, np.ndarray]:
        """Jacobians of the link origins: linear (nlinks, 3, nv) and angular (nlinks, 3, nv).

        ``jacp[k] @ qd`` is the world velocity of link k's origin [m/s],
        ``jacr[k] @ qd`` its world angular velocity [rad/s].
        """
        jacp, jacr = self._jacobians(self._at(q))
        return jacp.copy(), jacr.copy()

    def point_jacobians(self, q, points, links) -> np.ndarray:
        """Jacobians of world points rigidly attached to links, (n, 3, nv).

        Args:
            q: (nq,) configuration.
            points: (n, 3) world positions [m].
            links: (n,) integer link index owning each point.

        Returns:
            ``J`` with ``J[i] @ qd`` the world velocity of point i [m/s]:
            ``J_i = Jp_k - [r_i]x Jr_k`` with ``r_i`` from the link origin.
        """
        points, links = self._check_points(points, links)
        s = self._at(q)
        jacp, jacr = self._jacobians(s)
        return _point_jacobians(jacp, jacr, s.data.xpos[1:], points, links)

    def point_velocities(self, q, qd, points, links) -> np.ndarray:
        """Rigid velocity of world points attached to links, (n, 3) [m/s].

        Vectorized over points: one Jacobian per link, then
        ``v_i = v_k + w_k x (p_i - x_k)``.
        """
        points, links = self._check_points(points, links)
        return rigid_velocity(self.link_motion(q, qd), points, links)

    def link_motion(self, q, qd) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The links' rigid motion: world origins ``x_k`` [m], their velocities ``v_k``
        [m/s] and angular velocities ``w_k`` [rad/s], each (nlinks, 3)."""
        s = self._at(q)
        jacp, jacr = self._jacobians(s)
        qd = np.asarray(qd, dtype=float)
        return s.data.xpos[1:].copy(), jacp @ qd, jacr @ qd

    def _check_points(self, points, links):
        points = np.asarray(points, dtype=float).reshape(-1, 3)
        links = np.asarray(links, dtype=int).reshape(-1)
        if links.shape[0] != points.shape[0]:
            raise ValueError(f"{points.shape[0]} points but {links.shape[0]} link indices")
        if links.size and (links.min() < 0 or links.max() >= self.nlinks):
            raise ValueError(f"link indices must lie in [0, {self.nlinks}); got {links}")
        return points, links

    def center_of_mass(self, q) -> np.ndarray:
        """Centre of mass of the whole body, (3,) [m]."""
        d = self._at(q).data
        return self.link_mass @ d.xipos[1:] / self.link_mass.sum()

    def momentum(self, q, qd) -> tuple[np.ndarray, np.ndarray]:
        """Linear momentum (3,) [kg m/s] and angular momentum about the origin (3,) [kg m^2/s]."""
        d = self._at(q, qd).data
        com = d.xipos[1:].copy()
        v = self.point_velocities(q, qd, com, np.arange(self.nlinks))
        _, jacr = self.link_jacobians(q)
        w = jacr @ np.asarray(qd, dtype=float)
        rot = d.ximat[1:].reshape(-1, 3, 3)
        inertia = np.einsum("kij,kj,klj->kil", rot, self.mj.body_inertia[1:], rot)
        p = self.link_mass[:, None] * v
        spin = np.einsum("kij,kj->ki", inertia, w)
        return p.sum(axis=0), (np.cross(com, p) + spin).sum(axis=0)

    # --- integration ------------------------------------------------------
    def integrate(self, q, qd, dt: float) -> np.ndarray:
        """Positions after moving with constant velocity ``qd`` for ``dt`` [s], (nq,).

        Quaternions of free and ball joints are advanced on the unit sphere.
        """
        out = np.array(q, dtype=float)
        mujoco.mj_integratePos(self.mj, out, np.asarray(qd, dtype=float), float(dt))
        return out

    def difference(self, q1, q0, dt: float = 1.0) -> np.ndarray:
        """The velocity (nv,) that carries ``q0`` to ``q1`` in ``dt``: inverse of ``integrate``."""
        out = np.zeros(self.nv)
        mujoco.mj_differentiatePos(
            self.mj, out, float(dt), np.asarray(q0, dtype=float), np.asarray(q1, dtype=float)
        )
        return out


class _Scratch:
    """One thread's MuJoCo data for a ``Dynamics``, and the state it was last brought to.

    Attributes:
        data: the ``MjData`` the MuJoCo calls write into.
        q: (nq,) the configuration ``data`` holds kinematics for, or None.
        qd: (nv,) the velocity ``data`` holds velocity terms for, or None.
        jac: the link Jacobians ``(jacp, jacr)`` at ``q``, or None until asked for.
    """

    __slots__ = ("data", "q", "qd", "jac")

    def __init__(self, data):
        self.data = data
        self.q = self.qd = self.jac = None


def rigid_velocity(motion, points: np.ndarray, links: np.ndarray) -> np.ndarray:
    """The velocity (n, 3) [m/s] of world ``points`` (n, 3) moving with ``links`` (n,),
    ``v_k + w_k x (p - x_k)``, given the links' motion ``(x, v, w)`` (``Dynamics.link_motion``)."""
    origins, linear, angular = motion
    return linear[links] + np.cross(angular[links], points - origins[links])


@numba.njit(cache=True, nogil=True)
def _point_jacobians(jacp, jacr, origins, points, links):
    """``J_i = Jp_k - [r_i]x Jr_k``, ``r_i = p_i - x_k``, for every point i on link k, (n, 3, nv).

    The numbers ``jacp[links] - np.cross(r[:, :, None], jacr[links], axis=1)``
    gives, bit for bit, without its temporaries (a 3D creature's coupled
    faces are thousands of points a step).
    """
    n, nv = points.shape[0], jacp.shape[2]
    out = np.empty((n, 3, nv))
    for i in range(n):
        k = links[i]
        r0, r1, r2 = (
            points[i, 0] - origins[k, 0],
            points[i, 1] - origins[k, 1],
            points[i, 2] - origins[k, 2],
        )
        for j in range(nv):
            w0, w1, w2 = jacr[k, 0, j], jacr[k, 1, j], jacr[k, 2, j]
            out[i, 0, j] = jacp[k, 0, j] - (r1 * w2 - r2 * w1)
            out[i, 1, j] = jacp[k, 1, j] - (r2 * w0 - r0 * w2)
            out[i, 2, j] = jacp[k, 2, j] - (r0 * w1 - r1 * w0)
    return out
