"""What only describes scenery or another simulator's set-up: set aside with one note a kind.

``set_aside(root)`` removes from a parsed MJCF tree (``aquagait.body.mjcf``)
what aquagait does not simulate, and returns one note per kind saying what
was ignored and why (``IGNORED``): geoms and joint-free bodies fixed to the
world, lights, cameras, textures, materials, ``<visual>``/``<statistic>``,
actuators, sensors, contact pairs and exclusions, tendons, keyframes,
``<option>`` and the joints' passive terms.
"""

from __future__ import annotations

PASSIVE = ("armature", "damping", "stiffness", "frictionloss", "springref", "springdamper")
SECTIONS = {
    "actuator": "actuator",
    "sensor": "sensor",
    "contact": "contact pair or exclusion",
    "tendon": "tendon",
    "keyframe": "keyframe",
}
PLURALS = {
    "body fixed to the world": "bodies fixed to the world",
    "contact pair or exclusion": "contact pairs or exclusions",
}
IGNORED = {
    "scenery": "aquagait's water has no floor, walls or obstacles: only the creature is simulated",
    "light": "aquagait's pictures light the scene themselves",
    "camera": "aquagait's pictures place their own camera",
    "texture": "aquagait's pictures use no MuJoCo textures or skybox",
    "material": "aquagait's pictures use no MuJoCo materials",
    "visual": "these only set up MuJoCo's renderer",
    "actuator": "aquagait drives the joints itself, with the gait's PD torques",
    "sensor": "aquagait measures the swim itself",
    "contact": "aquagait's links do not collide; the objective penalizes overlapping links instead",
    "tendon": "tendons act only through actuators, limits and springs, none of which aquagait uses",
    "keyframe": "aquagait starts from the reference pose qpos0",
    "option": "aquagait simulates its own water and body, with gravity off (nothing sinks or "
    "floats)",
    "passive": "aquagait's joints feel only the gait's PD torques and the water: no springs, "
    "damping, friction or rotor inertia",
}


def kids(element, tag: str) -> list:
    """Children of ``element`` with ``tag``, looking through MuJoCo's <frame> elements."""
    found = []
    for child in element:
        if child.tag == tag:
            found.append(child)
        elif child.tag == "frame":
            found += kids(child, tag)
    return found


def remove_from(body, element) -> None:
    """Remove ``element`` from ``body``, wherever below it it sits (a <frame> among them)."""
    for holder in body.iter():
        if element in list(holder):
            holder.remove(element)
            return


def names(elements, kind=False, most=4) -> str:
    """Up to ``most`` elements' names (and types, with ``kind``), for a note or a problem."""

    def label(e):  # a geom's or texture's type too: "plane 'floor'", "skybox"
        name, kind_of = repr(e.get("name")) if e.get("name") else "", e.get("type") if kind else ""
        return " ".join(filter(None, [kind_of, name])) or "unnamed"

    return listing([label(e) for e in elements], most)


def listing(labels, most=4) -> str:
    """Up to ``most`` labels, comma-separated, and how many more: "'a', 'b' and 3 more"."""
    more = f" and {len(labels) - most} more" if len(labels) > most else ""
    return ", ".join(labels[:most]) + more


def set_aside(root) -> list[str]:
    """Remove from ``root`` what aquagait ignores (module doc, step 2); one note per kind."""
    notes: list[str] = []
    parent = {child: p for p in root.iter() for child in p}
    worldbody = root.find("worldbody")
    tops = kids(worldbody, "body")
    moving = [
        b for b in tops if b.find(".//joint") is not None or b.find(".//freejoint") is not None
    ]
    _drop(parent, kids(worldbody, "geom"), "geom fixed to the world", "scenery", notes)
    _drop(parent, [b for b in tops if moving and b not in moving], "body fixed to the world",
          "scenery", notes)  # fmt: skip
    for tag in ("light", "camera"):
        _drop(parent, list(worldbody.iter(tag)), tag, tag, notes)
    for tag in ("texture", "material"):
        _drop(parent, [e for a in root.findall("asset") for e in a.findall(tag)], tag, tag, notes)
    for element in root.iter():
        element.attrib.pop("material", None)
    for tag, noun in SECTIONS.items():
        sections = root.findall(tag)
        _drop(parent, [e for section in sections for e in section], noun, tag, notes)
        _drop(parent, sections, "", "", notes)
    renderer = root.findall("visual") + root.findall("statistic")
    if renderer:
        tags = ", ".join(sorted({f"<{e.tag}>" for e in renderer}))
        notes.append(f"ignored {tags}: {IGNORED['visual']}")
        _drop(parent, renderer, "", "", notes)
    _set_aside_options(root, parent, notes)
    _set_aside_passive(root, parent, notes)
    return notes


def _drop(parent, elements, noun, why, notes) -> None:
    """Remove ``elements``; note them as ignored ``noun``s unless ``noun`` is empty."""
    for element in elements:
        parent[element].remove(element)
    if elements and noun:
        plural = PLURALS.get(noun, noun.replace(" ", "s ", 1) if " " in noun else noun + "s")
        listed = names(elements, kind=noun.startswith(("geom", "texture")))
        count = f"{len(elements)} {noun if len(elements) == 1 else plural}"
        notes.append(f"ignored {count} ({listed}): {IGNORED[why]}")


def _set_aside_options(root, parent, notes) -> None:
    ignored = []
    for option in root.findall("option"):
        for name, value in option.attrib.items():
            if name != "gravity" or _nonzero(value):
                ignored.append(name)
        ignored += [f"<{child.tag}>" for child in option]
    if ignored:
        listed = ", ".join(dict.fromkeys(ignored))
        notes.append(f"ignored <option> {listed}: {IGNORED['option']}")
        _drop(parent, root.findall("option"), "", "", [])


def _set_aside_passive(root, parent, notes) -> None:
    terms, where = [], []
    for joint in root.iter("joint"):
        found = [a for a in PASSIVE if a in joint.attrib and _nonzero(joint.attrib[a])]
        for name in PASSIVE:
            joint.attrib.pop(name, None)
        if found:
            terms += found
            owner = parent[joint]
            if owner.tag == "default":
                where.append(f"default class {owner.get('class', 'main')!r}")
            else:
                where.append(repr(joint.get("name")) if joint.get("name") else "an unnamed joint")
    if where:
        listed = ", ".join(dict.fromkeys(terms))
        shown = ", ".join(where[:4]) + (f" and {len(where) - 4} more" if len(where) > 4 else "")
        notes.append(f"ignored joint {listed} (on {shown}): {IGNORED['passive']}")


def _nonzero(value: str) -> bool:
    try:
        return any(float(v) != 0 for v in value.split())
    except ValueError:
        return True
