"""The fluid: inviscid, incompressible Euler equations on a MAC grid (paper §3.1).

Modules: ``advection`` (semi-Lagrangian and BFECC), ``operators`` (divergence,
gradient, vorticity), ``multigrid`` and ``pcg`` (the pressure solver),
``projection`` (making a field divergence free around static solids), and
``shift`` (moving the field by whole cells as the grid follows the swimmer).
"""
