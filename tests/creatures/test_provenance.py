"""Each shipped gait found by ``aquagait optimize`` says how: its side-car provenance's
command runs with today's command line and sets up the search that found it
(``tools/ship_gait.py`` writes it, ``tools/check_provenance.py`` runs it)."""

import shlex

import pytest
from check_provenance import AGREE, check, optimized_gaits

import aquagait as ag
from aquagait.cli import build_parser
from aquagait.objectives import MANEUVERS

OPTIMIZED = sorted(optimized_gaits(ag.creatures.names()))


def reproducible():
    """The gaits shipped with their start by value (since 2026-12-04): those a later
    change of the physics or of the shipped straight gait must not leave stale."""
    return [(name, gait) for name, gait in OPTIMIZED
            if "start" in ag.creatures.get(name).gaits[gait].provenance]  # fmt: skip


@pytest.mark.parametrize("name, gait", OPTIMIZED)
def test_an_optimized_gait_names_the_command_that_found_it(name, gait):
    provenance = ag.creatures.get(name).gaits[gait].provenance
    words = shlex.split(provenance["command"])
    assert words[:2] == ["aquagait", "optimize"]
    args = build_parser().parse_args(words[1:])  # exits (fails) on a flag it no longer has
    assert args.name == name and args.seed == provenance["seed"]
    maneuver = gait if gait in MANEUVERS else "straight"  # as the side-car ships it
    assert args.maneuver == provenance.get("maneuver", maneuver) == maneuver
    assert args.objective == provenance.get("objective_kind", "distance")


@pytest.mark.parametrize("name, gait", reproducible())
def test_a_recorded_start_is_in_its_searchs_parameters(name, gait):
    creature = ag.creatures.get(name)
    provenance = creature.gaits[gait].provenance
    names = tuple(provenance["start"])
    assert names == creature.spec(provenance["maneuver"], "period" in names).names


@pytest.mark.slow
@pytest.mark.parametrize("name, gait", reproducible())
def test_the_provenance_reproduces_the_gaits_objective(name, gait):
    """The search is deterministic for its seed: a gait that scores today what its search
    recorded comes out of its command again. It fails when the physics moves a shipped
    gait: optimize it again (the library's gaits shipped before 2026-12-04 have no start
    recorded: ``tools/check_provenance.py`` measures how far they have moved)."""
    row = check(name, gait)
    print(row)
    assert row["relative_change"] <= AGREE
