"""MJCF text: reading it, setting aside what aquagait ignores, and the checks only text answers.

Once MuJoCo has compiled a model it no longer shows whether a geom's density
was given or defaulted, whether a body had an ``<inertial>``, or which parts
only describe scenery; so the text is read here first (``prepare_mjcf``):

1. Parse it and inline every ``<include>`` the way MuJoCo does: a relative
   file name is looked up next to the main file first, then next to the file
   that includes it; the included ``<mujoco>``'s children replace the element.
2. Set aside, with one note per kind, what only describes scenery or another
   simulator's set-up (``aquagait.body.scenery``): geoms and joint-free
   bodies fixed to the world (floors, targets), lights, cameras, textures,
   skyboxes and materials, ``<visual>``/``<statistic>``, actuators, sensors,
   contact pairs and exclusions, tendons, keyframes, ``<option>`` (its fluid
   density and viscosity, gravity, time step, flags) and the joints' passive
   terms (armature, damping, stiffness, friction loss), which would otherwise
   enter MuJoCo's mass matrix or mean nothing here. Tendons are ignored since
   they act only through actuators, limits and springs; ``<equality>``
   constraints are refused instead, since they change how the body moves.
   Geom attributes for contacts or looks (``contype``, ``rgba``) and sites
   are harmless and kept without a note.
3. List every problem the text shows, each with its fix (``text_problems``),
   and neutralize it in the copy given to MuJoCo (a density of 1000 or a mass
   of 1 for a bad one, a placeholder mass for a link left without geoms) so
   the checks on the compiled model can still run and all problems come out
   at once. Masses are MuJoCo's to compute (geom ``density`` or ``mass``,
   ``<inertial>``); only values MuJoCo would misread are problems here. The
   ``<position>`` servos' targets are read first (``servo_ranges``): they
   bound the gait of a joint that has no range.
4. Serialize the cleaned tree for MuJoCo with the asset directories
   (``meshdir``, ``texturedir``, ``assetdir``) made absolute, so mesh files
   resolve as they would from the file itself.

Problems that leave nothing to check (no such file, not XML, not MJCF, an
include that cannot be read, no ``<worldbody>``) raise at once. The checks on
the compiled model live in ``aquagait.body.model``.
"""

from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from xml.parsers import expat

from aquagait.body.scenery import kids, names, remove_from, set_aside

GEOM_KINDS = ("capsule", "box", "sphere", "ellipsoid", "cylinder", "mesh")
FILE_ASSETS = {"mesh": "meshdir", "hfield": "meshdir", "skin": "meshdir", "texture": "texturedir"}


class ModelError(ValueError):
    """An MJCF that aquagait cannot load; every problem found, each with its fix.

    Args:
        source: the file (or '<string>') the problems are in.
        problems: one message per problem, each naming the element and the fix.
            Given a single string and no problems, that string is the message.

    The message starts with the file: ``'my.xml: <problem>'`` for one problem,
    ``'my.xml has 3 problems:\\n  - <problem>\\n  - ...'`` for several.
    """

    def __init__(self, source: str, problems: list[str] | str | None = None):
        if problems is None:
            source, problems = "", [source]
        elif isinstance(problems, str):
            problems = [problems]
        self.source, self.problems = source, list(problems)
        if not source:
            message = "\n".join(self.problems)
        elif len(self.problems) == 1:
            message = f"{source}: {self.problems[0]}"
        else:
            lines = "".join(f"\n  - {p}" for p in self.problems)
            message = f"{source} has {len(self.problems)} problems:{lines}"
        super().__init__(message)

    def __reduce__(self):
        return type(self), (self.source, self.problems)


def read_mjcf(mjcf) -> tuple[str, Path | None, str]:
    """The MJCF text, its path (None for a string) and a label for messages."""
    if isinstance(mjcf, str) and mjcf.lstrip().startswith("<"):
        return mjcf, None, "<string>"
    path = Path(mjcf)
    if not path.exists():
        raise ModelError(str(path), "no such MJCF file")
    if not path.is_file():
        raise ModelError(str(path), "is not a file; give the path of an MJCF (.xml) file")
    try:
        return path.read_text(encoding="utf-8"), path, str(path)
    except UnicodeDecodeError:
        raise ModelError(str(path), "is not a text file, so not MJCF (an XML file)") from None
    except OSError as err:
        raise ModelError(str(path), f"cannot be read: {err.strerror}") from None


@dataclass
class Prepared:
    """An MJCF ready for MuJoCo, with what was set aside and what is wrong.

    Attributes:
        xml: the cleaned MJCF text to compile.
        notes: one line per kind of thing ignored, saying why.
        problems: the text's problems, each with its fix.
        angle: 'degree' or 'radian', the unit of the model's joint ranges.
        origin: for each line of ``xml`` that opens an element, the (file, line)
            it came from; used to point MuJoCo's own errors back at the file.
        servos: joint name -> (lo, hi), the targets its ``<position>`` actuator
            takes [rad or m] (``servo_ranges``), read before actuators are set aside.
    """

    xml: str
    notes: list[str]
    problems: list[str]
    angle: str
    origin: dict = field(default_factory=dict)
    servos: dict = field(default_factory=dict)

    def compile_error(self, err: Exception) -> str:
        """MuJoCo's compiler message as one problem, its line numbers those of the files."""

        def back(match):
            file, line = self.origin.get(int(match.group(1)), (None, None))
            return f"line {line} of {file}" if file else "line ?"

        reason = re.sub(r"line (\d+)", back, str(err).strip())
        massless = re.search(r"mass and inertia of moving bodies.*Element name '([^']*)'", reason,
                             re.S)  # fmt: skip
        if massless:
            return (
                f"link {massless.group(1)!r} has no mass (its geoms all have mass 0 or density 0"
                ", or its <inertial> none): give a geom a density or a mass; MuJoCo says: "
                + re.sub(r"\s*\n\s*", "; ", reason)
            )
        return "MuJoCo cannot compile it: " + re.sub(r"\s*\n\s*", "; ", reason)


def prepare_mjcf(text: str, path: Path | None, source: str) -> Prepared:
    """Parse, inline includes, set aside the ignored parts and list the problems (module doc)."""
    origin: dict = {}
    root = _parse(text, source, origin, source)
    if root.tag != "mujoco":
        fix = (
            " (a URDF? MuJoCo converts one: model = mujoco.MjModel.from_xml_path('robot.urdf'),"
            " then mujoco.mj_saveLastXML('robot.xml', model))"
        )
        raise ModelError(
            source,
            f"the root element is <{root.tag}>; an MJCF starts with <mujoco>"
            + (fix if root.tag == "robot" else ""),
        )
    base = path.absolute().parent if path is not None else Path.cwd()
    _inline_includes(root, base, base, origin, source, [])
    worldbody, *more = root.findall("worldbody") or [None]
    if worldbody is None:
        raise ModelError(source, "no <worldbody>: the creature's bodies go inside it")
    for extra in more:  # MuJoCo reads several (a scene file's and the model's) as one
        worldbody.extend(list(extra))
        root.remove(extra)
    servos = servo_ranges(root)
    notes = set_aside(root)
    problems = text_problems(root)
    if path is not None:
        _absolute_asset_dirs(root, base, origin)
    xml, lines = _serialize(root, origin)
    angle = ([c.get("angle") for c in root.iter("compiler") if c.get("angle")] or ["degree"])[-1]
    return Prepared(xml, notes, problems, angle, lines, servos)


def check_xml(text: str, source: str) -> None:
    """Raise ModelError listing the problems the text alone shows (see ``text_problems``)."""
    prepared = prepare_mjcf(text, None, source)
    if prepared.problems:
        raise ModelError(source, prepared.problems)


# --- reading: parse with line numbers, includes -----------------------------------


def _parse(data, label: str, origin: dict, source: str) -> ET.Element:
    """The element tree of ``data`` (text or bytes); records each element's (file, line)."""
    builder, parser = ET.TreeBuilder(), expat.ParserCreate()

    def start(tag, attrs):
        origin[builder.start(tag, attrs)] = (label, parser.CurrentLineNumber)

    parser.StartElementHandler, parser.EndElementHandler = start, builder.end
    parser.CharacterDataHandler = builder.data
    try:
        parser.Parse(data, True)
    except expat.ExpatError as err:
        what = "" if label == source else f"the included file {label} "
        raise ModelError(source, f"{what}is not well-formed XML: {err}") from None
    return builder.close()


def _inline_includes(element, main_dir: Path, here: Path, origin, source, chain) -> None:
    """Replace each <include> below ``element`` by the included file's children, in place."""
    for index, child in reversed(list(enumerate(element))):
        if child.tag != "include":
            _inline_includes(child, main_dir, here, origin, source, chain)
            continue
        name = child.get("file")
        if not name:
            raise ModelError(source, '<include> has no file="..."; name the MJCF file to include')
        found = [d / name for d in (main_dir, here) if (d / name).is_file()]
        if not found:
            raise ModelError(
                source,
                f'<include file="{name}">: no such file (looked in {_places(main_dir, here)})',
            )
        target = found[0].resolve()
        if target in chain:
            raise ModelError(source, f'<include file="{name}"> includes itself, in a loop')
        try:
            data = target.read_bytes()
        except OSError as err:
            raise ModelError(source, f'<include file="{name}"> cannot be read: {err}') from None
        included = _parse(data, str(found[0]), origin, source)
        if included.tag != "mujoco":
            raise ModelError(
                source, f"the included file {found[0]} starts with <{included.tag}>, not <mujoco>"
            )
        here_next = found[0].absolute().parent
        _inline_includes(included, main_dir, here_next, origin, source, [*chain, target])
        element[index : index + 1] = list(included)


def _places(main_dir: Path, here: Path) -> str:
    return str(main_dir) if main_dir == here else f"{main_dir} or {here}"


# --- what the text shows is wrong ------------------------------------------------------


def text_problems(root) -> list[str]:
    """Every problem the text shows, each with its fix; neutralized in ``root`` (module doc)."""
    problems: list[str] = []
    for equality in root.findall("equality"):
        if len(equality):
            problems.append(
                f"<equality> holds {len(equality)} constraint(s) ({names(list(equality))}); "
                "aquagait solves no constraints between links: remove it (to move joints "
                "together, give them shared gait parameters)"
            )
        root.remove(equality)
    classes = _default_classes(root)
    _walk_bodies(root.find("worldbody"), "main", classes, problems)
    return problems


def _default_classes(root) -> dict[str, tuple[str | None, dict]]:
    """Default classes: name -> (parent class name, {element tag: its default attributes})."""
    classes: dict[str, tuple[str | None, dict]] = {}

    def visit(element, name, parent):
        classes[name] = (parent, {c.tag: dict(c.attrib) for c in element if c.tag != "default"})
        for child in element.findall("default"):
            visit(child, child.get("class", "main"), name)

    for top in root.findall("default"):
        visit(top, top.get("class", "main"), None)
    classes.setdefault("main", (None, {}))
    return classes


def _default_attr(classes, name, attr, tag="geom"):
    """The attribute ``attr`` of ``<tag>`` in default class ``name`` or its ancestors."""
    while name is not None and name in classes:
        parent, defaults = classes[name]
        if attr in defaults.get(tag, {}):
            return defaults[tag][attr]
        name = parent
    return None


def servo_ranges(root) -> dict[str, tuple[float, float]]:
    """Joint name -> the range of targets its ``<position>`` servo can be given [rad or m].

    MuJoCo does not convert a ``ctrlrange`` to radians (whatever the compiler's
    ``angle``), and a servo with gear ``g`` holds its joint at ``ctrl / g``. A
    servo whose control is not limited bounds nothing and is left out.
    """
    classes, found = _default_classes(root), {}
    for servo in (e for section in root.findall("actuator") for e in section.iter("position")):
        cls = servo.get("class", "main")
        ctrlrange, limited, gear = (
            servo.get(attr) or _default_attr(classes, cls, attr, "position")
            for attr in ("ctrlrange", "ctrllimited", "gear")
        )
        joint = servo.get("joint")
        if not joint or not ctrlrange or (limited or "auto").lower() == "false":
            continue
        try:
            lo, hi = (float(v) for v in ctrlrange.split())
            gear = float((gear or "1").split()[0])
        except ValueError:
            continue  # MuJoCo's compiler will say what is wrong with it
        if gear != 0 and hi > lo:
            found[joint] = tuple(sorted((lo / gear, hi / gear)))
    return found


def _walk_bodies(element, childclass, classes, problems) -> None:
    for body in kids(element, "body"):
        label = f"body {body.get('name')!r}" if body.get("name") else "an unnamed body"
        cls = body.get("childclass", childclass)
        geoms = kids(body, "geom")
        if not geoms:
            problems.append(
                f"{label} has no <geom>; every link needs a shape for the water to push on "
                "(an <inertial> gives it mass, not a shape): give it a geom"
            )
        for index, geom in enumerate(geoms):
            _check_geom(body, geom, index, label, geom.get("class", cls), classes, problems)
        if not kids(body, "geom") and not body.findall("inertial"):
            # only a placeholder, for MuJoCo to check the rest
            ET.SubElement(body, "inertial", pos="0 0 0", mass="1", diaginertia="1 1 1")
        _walk_bodies(body, cls, classes, problems)


def _check_geom(body, geom, index, body_label, cls, classes, problems) -> None:
    where = f"{_geom_label(geom, index)} in {body_label}"
    kind = geom.get("type") or _default_attr(classes, cls, "type") or "sphere"
    if kind not in GEOM_KINDS:
        problems.append(f"{where} is a {kind}; allowed: {', '.join(GEOM_KINDS)}")
        remove_from(body, geom)
        return
    for attr, unit in (("density", "kg/m^3"), ("mass", "kg")):
        value = geom.get(attr) or _default_attr(classes, cls, attr)
        if value is None:
            continue
        try:
            number = float(value)
        except ValueError:
            number = None
        if number is None or not number >= 0:
            example = 'density="1000" (water)' if attr == "density" else 'mass="0.01"'
            problems.append(
                f"{where} has {attr} {value!r}; it must be a number >= 0 [{unit}], e.g. {example}"
            )
            geom.set(attr, "1000" if attr == "density" else "1")  # a placeholder, as above


def _geom_label(geom, index=None) -> str:
    if geom.get("name"):
        return f"geom {geom.get('name')!r}"
    return "an unnamed geom" if index is None else f"geom #{index}"


# --- the text MuJoCo compiles ---------------------------------------------------------


def _absolute_asset_dirs(root, base: Path, origin) -> None:
    """Asset directories made absolute (relative to the main file), as MuJoCo reads them."""
    compilers = root.findall("compiler")
    if not compilers:
        compilers = [ET.Element("compiler")]
        root.insert(0, compilers[0])
        origin[compilers[0]] = (None, None)
    dirs = {"assetdir": str(base)}
    for compiler in compilers:
        for name in ("assetdir", "meshdir", "texturedir"):
            if compiler.get(name) is not None:
                dirs[name] = str(base / compiler.get(name))
                compiler.set(name, dirs[name])
    compilers[0].set("assetdir", dirs["assetdir"])
    for asset in root.iter():  # declared in an included file: MuJoCo's second place to look
        name = asset.get("file")
        if asset.tag not in FILE_ASSETS or not name or Path(name).is_absolute():
            continue
        folder = Path(dirs.get(FILE_ASSETS[asset.tag], dirs["assetdir"]))
        home = Path(origin[asset][0]).absolute().parent
        nested = folder / os.path.relpath(home, base) / name
        if not (folder / name).is_file() and nested.is_file():
            asset.set("file", str(nested))


def _serialize(root, origin) -> tuple[str, dict]:
    """The tree as text, one element per line, and the source (file, line) of each line."""
    ET.indent(root)
    xml = ET.tostring(root, encoding="unicode")
    opening = [n for n, line in enumerate(xml.splitlines(), 1) if re.match(r"\s*<[^/!?]", line)]
    elements = list(root.iter())
    if len(opening) != len(elements):
        return xml, {}
    return xml, {n: origin.get(e, (None, None)) for n, e in zip(opening, elements, strict=True)}
