"""The creature library, and creatures from any MJCF file (docs/own-creature.md).

    import aquagait as ag
    ag.creatures.names()                 # ['accordion2d', 'eel2d', 'fish']
    eel = ag.creatures.get("eel2d")      # model, dim, default grid, gait spec
    mine = ag.creatures.load("my.xml")   # my.xml (+ my.aquagait.json), defaults filled,
                                         # thin parts thickened (thicken=False: as written)
    ag.creatures.resolve("eel2d")        # a library name, or a path to an MJCF file
    ag.creatures.register("mine", build_function)

Each built-in creature is an MJCF file beside this module, its metadata
``<name>.aquagait.json`` (format: ``aquagait.creatures.metadata``) and a
module whose docstring tables its links, DOFs, gait parameters and bounds
(``eel2d``, ``fish``, ``accordion2d``). What metadata leaves out comes from
the model: ``aquagait.creatures.defaults``. Why a registry: docs/development.md,
"How the code reads".
"""

from aquagait.creatures.creature import Creature, CreatureError, ShippedGait, UnknownCreatureError
from aquagait.creatures.defaults import ENERGY_COEFFICIENT, energy_bound
from aquagait.creatures.registry import (
    AS_WRITTEN,
    THICKEN_CELLS,
    as_written,
    format_table,
    get,
    load,
    names,
    register,
    register_library,
    resolve,
)

register_library()

__all__ = [
    "AS_WRITTEN",
    "ENERGY_COEFFICIENT",
    "THICKEN_CELLS",
    "as_written",
    "Creature",
    "CreatureError",
    "ShippedGait",
    "UnknownCreatureError",
    "energy_bound",
    "format_table",
    "get",
    "load",
    "names",
    "register",
    "resolve",
]
