"""MJCF text: reading it, and the checks that only the text can answer.

Once MuJoCo has compiled a model it no longer shows whether a geom's density
was given or defaulted, whether a body had an ``<inertial>``, or which files
were included; these checks run on the XML itself (default classes and
``childclass`` resolved), before MuJoCo sees it. The checks on the compiled
model live in ``aquagait.body.model``.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

GEOM_KINDS = ("capsule", "box", "sphere", "ellipsoid", "cylinder", "mesh")


class ModelError(ValueError):
    """An MJCF that aquagait cannot simulate; the message says where and why."""


def read_mjcf(mjcf) -> tuple[str, Path | None, str]:
    """The MJCF text, its path (None for a string) and a label for messages."""
    if isinstance(mjcf, str) and mjcf.lstrip().startswith("<"):
        return mjcf, None, "<string>"
    path = Path(mjcf)
    if not path.is_file():
        raise ModelError(f"{path}: no such MJCF file")
    return path.read_text(), path, str(path)


def check_xml(text: str, source: str) -> None:
    """Raise ModelError for what the compiled model can no longer show (module doc)."""
    try:
        root = ET.fromstring(text)
    except ET.ParseError as err:
        raise ModelError(f"{source}: not well-formed XML: {err}") from None
    if root.tag != "mujoco":
        raise ModelError(
            f"{source}: the root element is <{root.tag}>; an MJCF starts with <mujoco>"
        )
    for tag, why in [
        ("include", "aquagait checks densities in one file; inline the included MJCF"),
        ("equality", "aquagait does not solve equality constraints"),
    ]:
        if root.find(f".//{tag}") is not None:
            raise ModelError(f"{source}: <{tag}> is not supported: {why}")
    for compiler in root.iter("compiler"):
        if compiler.get("inertiafromgeom", "").lower() == "false":
            raise ModelError(
                f"{source}: <compiler inertiafromgeom='false'>: masses must come from geoms"
            )
    worldbody = root.find("worldbody")
    if worldbody is None:
        raise ModelError(f"{source}: no <worldbody>: the creature's bodies go inside it")
    static = worldbody.find("geom")
    if static is not None:
        raise ModelError(
            f"{source}: {_geom_label(static)} sits directly in <worldbody>: "
            "a creature is one tree of bodies; static scenery is not supported"
        )
    classes = _default_classes(root)
    _walk_bodies(worldbody, "main", classes, source)


def _default_classes(root) -> dict[str, tuple[str | None, dict]]:
    """Default classes: name -> (parent class name, geom attributes)."""
    classes: dict[str, tuple[str | None, dict]] = {}

    def visit(element, name, parent):
        geom = element.find("geom")
        classes[name] = (parent, dict(geom.attrib) if geom is not None else {})
        for child in element.findall("default"):
            visit(child, child.get("class", "main"), name)

    for top in root.findall("default"):
        visit(top, top.get("class", "main"), None)
    classes.setdefault("main", (None, {}))
    return classes


def _default_attr(classes, name, attr):
    while name is not None and name in classes:
        parent, attrs = classes[name]
        if attr in attrs:
            return attrs[attr]
        name = parent
    return None


def _walk_bodies(element, childclass, classes, source) -> None:
    for body in element.findall("body"):
        label = f"body {body.get('name')!r}" if body.get("name") else "an unnamed body"
        if body.find("inertial") is not None:
            raise ModelError(
                f"{source}: {label} has an <inertial> element: masses must come from geom "
                "densities so they match the volume the fluid sees; remove it"
            )
        if body.find("geom") is None:
            raise ModelError(
                f"{source}: {label} has no <geom>; every link needs volume (and so mass)"
            )
        cls = body.get("childclass", childclass)
        for index, geom in enumerate(body.findall("geom")):
            _check_geom_xml(geom, index, label, geom.get("class", cls), classes, source)
        _walk_bodies(body, cls, classes, source)


def _check_geom_xml(geom, index, body_label, cls, classes, source) -> None:
    where = f"{_geom_label(geom, index)} in {body_label}"
    kind = geom.get("type") or _default_attr(classes, cls, "type") or "sphere"
    if kind not in GEOM_KINDS:
        raise ModelError(f"{source}: {where} is a {kind}; allowed: {', '.join(GEOM_KINDS)}")
    if geom.get("mass") is not None or _default_attr(classes, cls, "mass") is not None:
        raise ModelError(f"{source}: {where} sets mass; give density [kg/m^3] instead")
    density = geom.get("density") or _default_attr(classes, cls, "density")
    if density is None:
        raise ModelError(f'{source}: {where} has no density; add density="1000" (water) [kg/m^3]')
    try:
        value = float(density)
    except ValueError:
        raise ModelError(f"{source}: {where} has density {density!r}, not a number") from None
    if not value > 0:
        raise ModelError(f"{source}: {where} has density {value:g}; it must be > 0 [kg/m^3]")


def _geom_label(geom, index=None) -> str:
    if geom.get("name"):
        return f"geom {geom.get('name')!r}"
    return "an unnamed geom" if index is None else f"geom #{index}"
