"""Shape and type checks of a side-car's JSON, every problem with its JSON path.

One ``Checker`` walks the decoded JSON and collects problems as
``"gait.mirror[0][2]: the sign must be +1 or -1, got 2"``: where, what is
wrong, what would be right. The format itself is documented in
``aquagait.creatures.metadata``; whether the entries fit the model is
checked there too.
"""

from __future__ import annotations

import json
import math

from aquagait.body.model import PLANAR_FLUIDS
from aquagait.control.gait import KINDS

VIEWS = ("follow", "side", "top", "side-above", "front-above")
"""The 3D pictures' views by name (``aquagait.viz.camera.VIEWS`` draws each); a side-car's
``view`` is one of them."""

KEYS = {
    "": (
        "description",
        "gait",
        "pd",
        "grid",
        "energy_bound",
        "energy_weight",
        "turn_limit",
        "forward",
        "planar_fluid",
        "view",
        "gaits",
    ),
    "gait": (
        "dofs",
        "free",
        "shared",
        "amplitude",
        "phase",
        "period",
        "offset",
        "mirror",
        "groups",
        "bounds",
    ),
    "pd": ("natural_frequency", "damping_ratio"),
    "grid": ("resolution", "cell_size"),
    "gaits.*": ("params", "provenance"),
}
"""The known keys of each object of the format."""


def at(where: str, key: str) -> str:
    """The JSON path of ``key`` in the object at ``where``: ``gait.bounds["amplitude[j1]"]``."""
    plain = key.replace("_", "").replace("-", "").isalnum() and not key[0].isdigit()
    return f"{where}.{key}" if plain else f"{where}[{json.dumps(key)}]"


def kind(value) -> str:
    """How a wrong JSON value is described: its type and its start."""
    names = {
        dict: "an object",
        list: "a list",
        str: "a string",
        bool: "a boolean",
        type(None): "null",
        int: "a number",
        float: "a number",
    }
    shown = json.dumps(value)
    return f"{names.get(type(value), type(value).__name__)} {shown[:40]}"


class Checker:
    """Checks one JSON value at a time, collecting problems as 'path: what; what is right'."""

    def __init__(self):
        self.problems: list[str] = []

    def add(self, where: str, what: str) -> None:
        self.problems.append(f"{where or 'the top level'}: {what}")

    def object(self, value, where: str, known=None) -> dict | None:
        """A JSON object; with ``known``, its other keys are refused (and dropped)."""
        if not isinstance(value, dict):
            self.add(where, f"must be a JSON object {{...}}, got {kind(value)}")
            return None
        if known is not None:
            unknown = [k for k in value if k not in known]
            if unknown:
                self.add(
                    where,
                    f"unknown key(s) {', '.join(map(repr, unknown))}; known: {', '.join(known)}",
                )
                return {k: v for k, v in value.items() if k in known}
        return value

    def string(self, value, where: str) -> str | None:
        """A JSON string."""
        if not isinstance(value, str):
            self.add(where, f"must be a string, got {kind(value)}")
            return None
        return value

    def number(self, value, where: str, lower=None, strict=False, unit="") -> float | None:
        """A finite number, above ``lower`` (``strict``) or at least it; ``unit`` for messages."""
        of, unit = (f" [{unit}]", f" {unit}") if unit else ("", "")
        if isinstance(value, bool) or not isinstance(value, int | float):
            self.add(where, f"must be a number{of}, got {kind(value)}")
            return None
        if not math.isfinite(value):
            self.add(where, f"must be a finite number{of}, got {value}")
            return None
        if lower is not None and (value <= lower if strict else value < lower):
            self.add(where, f"must be {'>' if strict else '>='} {lower:g}{unit}, got {value:g}")
            return None
        return float(value)

    def list(self, value, where: str, form: str | None = None) -> list | None:
        """A JSON list; with ``form`` (e.g. '[lower, upper]'), one of that many entries."""
        length = None if form is None else form.count(",") + 1
        if not isinstance(value, list) or (length is not None and len(value) != length):
            self.add(where, f"must be a list {form or '[...]'}, got {kind(value)}")
            return None
        return value

    def names(self, value, where: str, choices=None, distinct=True) -> tuple:
        """A list of distinct strings (of ``choices``, when given), as a tuple."""
        items = self.list(value, where)
        if items is None:
            return ()
        out = []
        for i, v in enumerate(items):
            s = self.string(v, f"{where}[{i}]")
            if s is not None and choices is not None and s not in choices:
                self.add(f"{where}[{i}]", f"{s!r} is not one of {', '.join(choices)}")
            elif s is not None and distinct and s in out:
                self.add(f"{where}[{i}]", f"{s!r} is listed twice")
            elif s is not None:
                out.append(s)
        return tuple(out)


def _mirror(check: Checker, value, where: str) -> tuple:
    out = []
    for i, triple in enumerate(check.list(value, where) or ()):
        here = f"{where}[{i}]"
        if check.list(triple, here, "[dof, source dof, sign +1 or -1]") is None:
            continue
        dof = check.string(triple[0], f"{here}[0]")
        source = check.string(triple[1], f"{here}[1]")
        sign = check.number(triple[2], f"{here}[2]")
        if sign is not None and sign not in (-1.0, 1.0):
            check.add(f"{here}[2]", f"the sign must be +1 or -1, got {sign:g}")
        elif None not in (dof, source, sign):
            out.append((dof, source, sign))
    return tuple(out)


def _groups(check: Checker, value, where: str) -> tuple:
    groups = [check.names(g, f"{where}[{i}]") for i, g in enumerate(check.list(value, where) or ())]
    return tuple(g for g in groups if g)


def _bounds_entry(check: Checker, value, where: str) -> dict:
    out = {}
    for key, pair in (check.object(value, where) or {}).items():
        here = at(where, key)
        name, bracket, rest = key.partition("[")
        if name not in KINDS or (bracket and not (rest.endswith("]") and len(rest) > 1)):
            check.add(
                here, f"bounds are named 'kind' or 'kind[dof]' with kind one of {', '.join(KINDS)}"
            )
            continue
        if check.list(pair, here, "[lower, upper]") is None:
            continue
        lo, hi = check.number(pair[0], f"{here}[0]"), check.number(pair[1], f"{here}[1]")
        if lo is not None and hi is not None:
            if lo < hi:
                out[key] = (lo, hi)
            else:
                check.add(here, f"lower {lo:g} must be below upper {hi:g}")
    return out


def _resolution(check: Checker, value, where: str) -> tuple | None:
    cells = check.list(value, where)
    if cells is None:
        return None
    bad = [c for c in cells if isinstance(c, bool) or not isinstance(c, int) or c < 1]
    if bad or len(cells) not in (2, 3):
        check.add(
            where,
            f"must be 2 or 3 whole numbers of cells >= 1 ([nx, ny] or [nx, ny, nz]), "
            f"got {json.dumps(value)}",
        )
        return None
    return tuple(cells)


def _dofs(check: Checker, value, where: str) -> tuple:
    dofs = check.names(value, where)
    if isinstance(value, list) and not value:
        check.add(where, "must name at least one DOF (or leave it out: every actuated DOF)")
    return dofs


GAIT = {
    "dofs": _dofs,
    "free": lambda c, v, w: c.names(v, w, choices=KINDS),
    "shared": lambda c, v, w: c.names(v, w, choices=KINDS),
    "amplitude": lambda c, v, w: c.number(v, w),
    "phase": lambda c, v, w: c.number(v, w),
    "period": lambda c, v, w: c.number(v, w, lower=0, strict=True, unit="s"),
    "offset": lambda c, v, w: c.number(v, w),
    "mirror": _mirror,
    "groups": _groups,
    "bounds": _bounds_entry,
}
PD = {
    "natural_frequency": lambda c, v, w: c.number(v, w, lower=0, strict=True, unit="rad/s"),
    "damping_ratio": lambda c, v, w: c.number(v, w, lower=0),
}
GRID = {
    "resolution": _resolution,
    "cell_size": lambda c, v, w: c.number(v, w, lower=0, strict=True, unit="m"),
}


def shipped(check: Checker, value) -> dict:
    """The ``gaits`` entry: ``{name: {"params": dict | list, "provenance": dict}}``."""
    out = {}
    for name, entry in (check.object(value, "gaits") or {}).items():
        where = at("gaits", name)
        entry = check.object(entry, where, KEYS["gaits.*"])
        if entry is None:
            continue
        if "params" not in entry:
            check.add(where, "needs 'params': the parameter vector, by name or as a list")
            continue
        params = entry["params"]
        if isinstance(params, dict):
            ok = all(
                check.number(v, at(f"{where}.params", k)) is not None for k, v in params.items()
            )
        elif isinstance(params, list):
            ok = all(
                check.number(v, f"{where}.params[{i}]") is not None for i, v in enumerate(params)
            )
        else:
            check.add(
                f"{where}.params",
                f"must be an object {{name: number}} or a list of numbers, got {kind(params)}",
            )
            ok = False
        provenance = check.object(entry.get("provenance", {}), f"{where}.provenance")
        if ok and provenance is not None:
            out[name] = {"params": params, "provenance": provenance}
    return out


SECTIONS = {"gait": GAIT, "pd": PD, "grid": GRID}
"""The checker of each entry of each object section of the format."""


def check_sidecar(data) -> tuple[dict, list[str]]:
    """Check decoded side-car JSON: the entries given, converted, and the problems found.

    Returns:
        ``{"description": str, "gait": {...}, "pd": {...}, "grid": {...},
        "energy_bound": float, "energy_weight": float, "turn_limit": float,
        "forward": (x, y, z),
        "planar_fluid": "2d" | "3d", "view": str, "gaits": {...}}``
        with only the entries given
        (lists of names as tuples, bounds as (lo, hi) pairs), and the list of
        problems (empty: the shapes and types are right).
    """
    check = Checker()
    top = check.object(data, "", KEYS[""])
    if top is None:
        return {}, check.problems
    out = {}
    for section, entries in SECTIONS.items():
        given = check.object(top.get(section, {}), section, KEYS[section]) or {}
        out[section] = {k: entries[k](check, v, f"{section}.{k}") for k, v in given.items()}
    if "description" in top:
        out["description"] = check.string(top["description"], "description")
    if "energy_bound" in top:
        out["energy_bound"] = check.number(top["energy_bound"], "energy_bound", 0, True, "J")
    if "energy_weight" in top:
        out["energy_weight"] = check.number(top["energy_weight"], "energy_weight", lower=0)
    if "turn_limit" in top:
        out["turn_limit"] = check.number(top["turn_limit"], "turn_limit", 0, True, "rad")
    if "forward" in top:
        out["forward"] = _forward(check, top["forward"])
    if "planar_fluid" in top:
        value = top["planar_fluid"]
        if value in PLANAR_FLUIDS:
            out["planar_fluid"] = value
        else:
            check.add("planar_fluid", f"must be one of {', '.join(map(repr, PLANAR_FLUIDS))}, "
                      f"got {value!r}")  # fmt: skip
    if "view" in top:
        value = top["view"]
        if value in VIEWS:
            out["view"] = value
        else:
            check.add("view", f"must be one of {', '.join(map(repr, VIEWS))}, got {value!r}")
    out["gaits"] = shipped(check, top.get("gaits", {}))
    return out, check.problems


def _forward(check: Checker, value) -> tuple[float, ...] | None:
    """A direction in the MJCF's frame: two or three numbers, not all zero."""
    if not isinstance(value, list) or len(value) not in (2, 3):
        check.add("forward", f"must be a list [x, y] or [x, y, z], got {kind(value)}")
        return None
    numbers = [check.number(v, f"forward[{i}]") for i, v in enumerate(value)]
    if any(n is None for n in numbers):
        return None
    if not any(numbers):
        check.add("forward", "must not be all zeros: it is the direction the head points")
        return None
    return tuple(numbers) + (0.0,) * (3 - len(numbers))
