"""The creature library (DESIGN.md §4, STYLE.md §14).

    import aquagait as ag
    ag.creatures.names()            # ['accordion2d', 'eel2d', 'fish']
    eel = ag.creatures.get("eel2d") # model, dim, default grid, gait spec
    ag.creatures.register("mine", build_function)

Each built-in creature is an MJCF file beside this module plus a short module
whose docstring tables its links, DOFs, gait parameters and bounds.
"""

from aquagait.creatures import accordion2d, eel2d, fish
from aquagait.creatures.registry import (
    Creature,
    UnknownCreatureError,
    energy_bound,
    format_table,
    get,
    names,
    register,
)

register("accordion2d", accordion2d.build)
register("eel2d", eel2d.build)
register("fish", fish.build)

__all__ = [
    "Creature",
    "UnknownCreatureError",
    "energy_bound",
    "format_table",
    "get",
    "names",
    "register",
]
