"""The check's report as text: the tables ``aquagait check`` prints and keeps in ``check.txt``."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from aquagait.body.model import direction_label

if TYPE_CHECKING:
    from aquagait.app.check import CheckReport


UNITS = {"amplitude": "rad", "phase": "rad", "period": "s", "offset": "rad"}
"""Units of the gait's kinds."""


def mm(metres: float) -> str:
    """A length in millimetres, three digits."""
    return f"{metres * 1000:.3g} mm"


def format_check(report: CheckReport) -> str:
    """The check as text for people: the tables, the notes and the warnings."""
    n = report.numbers
    sections = [
        _heading(n),
        _link_table(n),
        _dof_table(n),
        _gait_table(n),
        _grid_lines(n),
        _notes(n),
    ]
    return "\n\n".join(s for s in sections if s)


def _heading(n: dict) -> str:
    body = f"{n['dim']}D" + (f", a prism {mm(n['depth'])} deep" if n["depth"] else "")
    return "\n".join([
        f"{n['creature']}: {n['description']}" if n["description"] else n["creature"],
        f"source: {n['source']}" + (" (the library's)" if n["library"] else ""),
        f"{body}; mass {n['mass']:.4g} kg; body length {n['body_length']:.3g} m; "
        f"{len(n['links'])} links, {len(n['dofs'])} actuated DOF{'s' * (len(n['dofs']) != 1)}",
        f"forward: {direction_label(n['forward'])} in the file's frame" + _turned(n["forward"]),
    ])  # fmt: skip


def _turned(forward) -> str:
    return "" if forward == [1.0, 0.0, 0.0] else ", turned to face +x (swims are in that frame)"


def _link_table(n: dict) -> str:
    h = n["grid"]["cell_size"]
    header = ("link", "mass [kg]", "volume [m^3]", "density [kg/m^3]", "x water", "size [mm]",
              "thickness [mm]", f"[cells of {h * 1000:g} mm]", "solid cells",
              "cells/volume", "fluid sees")  # fmt: skip
    rows = [header]
    for r in n["links"]:
        rows.append((
            r["name"], f"{r['mass']:.4g}", f"{r['volume']:.4g}", _maybe(r["density"], ".4g"),
            _maybe(r.get("buoyancy"), ".2f"),
            " x ".join(f"{side * 1000:.3g}" for side in r["size"]),
            f"{r['thickness'] * 1000:.3g}", f"{r['thickness_cells']:.2f}",
            str(r["solid_cells"]), _maybe(r["voxel_fraction"], ".0%"),
            _maybe(r.get("seen_fraction"), ".0%"),
        ))  # fmt: skip
    lines = ["links (volume from the geoms' shapes; density = mass / volume; x water: mass over "
             "that of the water displaced; solid cells: the "
             "staircase's at the reference pose on the default grid; fluid sees: the share of "
             "the volume the sub-cell faces see)", _table(rows)]  # fmt: skip
    t = n["thinnest"]
    if t:
        lines.append(f"thinnest link: {t['link']}, {t['thickness'] * 1000:.3g} mm = "
                     f"{t['cells']:.2f} cells")  # fmt: skip
    return "\n".join(lines)


def _dof_table(n: dict) -> str:
    rows = [("DOF", "kind", "lower [deg]", "upper [deg]", "kp [N m/rad]", "kd [N m s/rad]",
             "gait", "I vacuum", "I water", "w water [rad/s]", "zeta water")]  # fmt: skip
    for d in n["dofs"]:
        water = d.get("inertia_water") is not None
        rows.append((d["name"], d["kind"], f"{math.degrees(d['lower']):.4g}",
                     f"{math.degrees(d['upper']):.4g}", f"{d['kp']:.4g}", f"{d['kd']:.4g}",
                     d["gait"], f"{d['inertia']:.4g}",
                     f"{d['inertia_water']:.4g}" if water else "-",
                     f"{d['natural_frequency_water']:.3g}" if water else "-",
                     f"{d['damping_ratio_water']:.2f}" if water else "-"))  # fmt: skip
    root = f"root: {n['root']['kind']} ({', '.join(n['root']['dofs'])}), not servoed"
    inertia = ("I: each DOF's inertia, all others free [kg m^2 for a hinge]: in a vacuum "
               "1/(M^-1)_ii, in water 1/((M + M_a)^-1)_ii with the added mass of the default "
               "grid's Euler fluid; w, zeta: the servo's about it")  # fmt: skip
    return "\n".join(["DOFs", root, _table(rows), inertia])


def _gait_table(n: dict) -> str:
    g = n["gait"]
    fixed = ", ".join(f"{k} {v:g} {UNITS[k]}" for k, v in g["fixed"].items()) or "none"
    rows = [("parameter", "lower", "upper", "default")]
    for name, lo, hi, x in zip(g["names"], g["lower"], g["upper"], g["default"], strict=True):
        rows.append((name, f"{lo:.4g}", f"{hi:.4g}", f"{x:.4g}"))
    mirror = ", ".join(f"{dof} = {sign:+g} x {src}" for dof, src, sign in g["mirror"])
    groups = "; ".join(", ".join(group) for group in g["groups"])
    return "\n".join([
        f"gait: {len(g['names'])} parameter{'s' * (len(g['names']) != 1)} (free: "
        f"{', '.join(g['free'])}; fixed: {fixed}); amplitude, phase, offset [rad], period [s]",
        _table(rows),
        f"shared: {', '.join(g['shared']) or 'none'}; mirrored: {mirror or 'none'}; "
        f"groups optimized in turn: {groups or 'one (all DOFs)'}",
    ])  # fmt: skip


def _grid_lines(n: dict) -> str:
    g, c = n["grid"], n["clearance"]
    cells = "x".join(str(x) for x in g["resolution"])
    metres = " x ".join(f"{x:.3g}" for x in g["extent"])
    lengths = " x ".join(f"{x:.2g}" for x in g["extent_body_lengths"])
    holds = (
        f"holds the body with {c['cells']} cells of water on every side "
        f"(nearest wall {c['room']:.1f} cells away; at the shipped gait's widest pose, "
        f"{' x '.join(f'{x:.3g}' for x in c['gait_box'])} m, {c['gait_room']:.1f} cells)"
        if c["holds"] else f"does not hold the body: {c['error']}"
    )  # fmt: skip
    pd = n["pd"]
    return "\n".join([
        f"default grid: {cells} cells of {g['cell_size'] * 1000:g} mm = {metres} m = "
        f"{lengths} body lengths",
        f"clearance (Euler fluid): {holds}",
        f"energy bound: {n['energy_bound']:.4g} J of actuator work over two cycles "
        f"(past it the objective adds {n['energy_weight']:g} times the work [J])",
        f"PD servos: natural frequency {pd['natural_frequency']:g} rad/s, "
        f"damping ratio {pd['damping_ratio']:g} about each DOF's inertia in a vacuum"
        f"{_in_water(n['dofs'])}; each step follows the continuous servo (sampled stable PD)",
    ])  # fmt: skip


def _in_water(dofs: list[dict]) -> str:
    """``; in water w .. rad/s, zeta ..``: the range of the servos' figures about their
    inertia in water, or nothing when it was not measured."""
    w = [d["natural_frequency_water"] for d in dofs if d.get("inertia_water") is not None]
    zeta = [d["damping_ratio_water"] for d in dofs if d.get("inertia_water") is not None]
    if not w:
        return ""
    return f"; in water, {_span(w, '.3g')} rad/s and damping ratio {_span(zeta, '.2f')}"


def _span(values: list[float], spec: str) -> str:
    low, high = f"{min(values):{spec}}", f"{max(values):{spec}}"
    return low if low == high else f"{low}-{high}"


def _notes(n: dict) -> str:
    lines = []
    if n["notes"]:
        lines += ["notes:", *(f"  - {note}" for note in n["notes"])]
    if n["warnings"]:
        lines += ["WARNINGS:", *(f"  - {w}" for w in n["warnings"])]
    return "\n".join(lines or ["no warnings"])


def _table(rows) -> str:
    widths = [max(len(r[i]) for r in rows) for i in range(len(rows[0]))]
    return "\n".join(
        "  ".join(cell.ljust(w) for cell, w in zip(row, widths, strict=True)).rstrip()
        for row in rows
    )


def _maybe(value, spec: str) -> str:
    return "-" if value is None else format(value, spec)
