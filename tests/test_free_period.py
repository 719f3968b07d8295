"""The period as a gait parameter (``--free-period``): its parameterization, the files that
carry it, the search, and what the inviscid fluid makes of a faster or slower rhythm."""

import json

import numpy as np
import pytest
from tests.creatures.test_metadata import SWIMMER, write

import aquagait as ag
from aquagait import cli
from aquagait.app import prepare_swim
from aquagait.app.errors import SetupError
from aquagait.app.follow import prepare_follow
from aquagait.app.optimize import (
    OptimizationSetupError,
    SwimObjective,
    best_swim,
    prepare_optimization,
)
from aquagait.control import GaitSpec, StablePD
from aquagait.control.gait import FREE_PERIOD
from aquagait.creatures import CreatureError, load
from aquagait.io import read_gait, write_gait
from aquagait.objectives import cruise
from aquagait.sim import init_state, make_scene, rollout

COARSE = dict(resolution=(48, 28), cell_size=0.025)
"""A coarse eel2d grid (as in test_optimization_run)."""


@pytest.fixture(scope="module")
def eel():
    return ag.creatures.get("eel2d")


def test_a_freed_period_is_one_number_after_the_phases_within_half_to_twice_the_period():
    spec = GaitSpec(dofs=("j1", "j2"), period=0.8, free=("amplitude", "phase", "offset"))
    free = spec.with_free_period()
    assert free.names == spec.names[:4] + ("period",) + spec.names[4:]
    assert free.bounds["period"] == pytest.approx((0.4, 1.6))
    assert FREE_PERIOD == (0.5, 2.0) and free.free_period and not spec.free_period
    gait = free.unpack(np.r_[0.1, 0.2, 0.0, 1.0, 1.3, 0.0, 0.05])
    np.testing.assert_array_equal(gait.period, [1.3, 1.3])  # one rhythm for every joint
    stated = GaitSpec(dofs=("j1",), bounds={"period": (0.9, 1.1)}).with_free_period()
    assert stated.bounds["period"] == (0.9, 1.1)  # a stated bound is kept
    with pytest.raises(ValueError, match="period is free already"):
        free.with_free_period()


def test_a_free_period_gait_round_trips_through_gait_json_and_swims(tmp_path, eel):
    spec = eel.spec(free_period=True)
    x = np.r_[eel.default_gait, 0.7]
    path = write_gait(tmp_path / "gait.json", eel, x, free_period=True)
    found = read_gait(path, eel)
    assert found.free_period and found.names == spec.names
    np.testing.assert_array_equal(found.params, x)
    setup = prepare_swim("eel2d", gait=path, seconds=0.1, fluid="none")
    assert setup.period == 0.7 and setup.spec is spec
    fixed = write_gait(tmp_path / "fixed.json", eel)
    assert not read_gait(fixed, eel).free_period
    with pytest.raises(ValueError, match="has 9 gait parameters"):
        write_gait(tmp_path / "bad.json", eel, x)  # a period the fixed gait has no room for


def test_a_shipped_gait_sets_its_own_period_by_name_but_not_as_straight(tmp_path):
    params = {"amplitude[joint_1]": 0.3, "amplitude[joint_2]": 0.4, "phase[joint_1]": 0.0,
              "phase[joint_2]": -1.5}  # fmt: skip
    sidecar = {"gaits": {"straight": {"params": params},
                         "brisk": {"params": {**params, "period": 0.6}}}}  # fmt: skip
    swimmer = load(write(tmp_path, "swimmer3", SWIMMER, sidecar))
    assert swimmer.gaits["brisk"].free_period and not swimmer.gaits["straight"].free_period
    assert swimmer.shipped_spec("brisk").unpack(swimmer.gaits["brisk"].params).period[0] == 0.6
    assert prepare_swim(str(tmp_path / "swimmer3.xml"), gait="brisk", fluid="none").period == 0.6
    sidecar["gaits"]["straight"]["params"] = {**params, "period": 0.6}
    with pytest.raises(CreatureError, match=r"gaits\.straight\.params: a gait with its own"):
        load(write(tmp_path, "swimmer4", SWIMMER.replace("swimmer3", "swimmer4"), sidecar))
    sidecar["gaits"] = {"brisk": {"params": {**params, "period": 3.0}}}
    with pytest.raises(CreatureError, match=r"period = 3 outside \[0\.5, 2\]"):
        load(write(tmp_path, "swimmer5", SWIMMER.replace("swimmer3", "swimmer5"), sidecar))


def test_the_search_frees_one_period_and_records_it(eel):
    setup = prepare_optimization("eel2d", free_period=True, fluid="none", **COARSE)
    assert setup.problem.names[-1] == "period" and setup.problem.x0[-1] == 1.0
    assert (setup.problem.lower[-1], setup.problem.upper[-1]) == (0.5, 2.0)
    assert setup.problem.feasible(setup.problem.x0)
    config = setup.config()
    assert config["free_period"] and config["cycles_per_sample"] is None
    assert config["seconds_per_sample"] == 2.0  # the distance objective: the same time for all


def test_the_efficiency_search_swims_each_sample_its_own_cycles(tmp_path, eel):
    setup = prepare_optimization("eel2d", free_period=True, objective="efficiency", cycles=3,
                                 **COARSE)  # fmt: skip
    objective = setup.objective
    assert objective.cycles == 3.0 and setup.config()["cycles_per_sample"] == 3.0
    _, _, traj, period = objective._swim(np.r_[eel.default_gait, 0.5])
    assert period == 0.5 and traj.time[-1] == pytest.approx(1.5)
    write_gait(tmp_path / "gait.json", eel, np.r_[eel.default_gait, 0.5], free_period=True)
    assert best_swim(setup, tmp_path).seconds == pytest.approx(1.5)  # the best swims as a sample


@pytest.mark.parametrize(
    "flags, message",
    [
        ({"maneuver": "turn-left"}, "--free-period is for swimming straight"),
        ({"start": "PERIOD"}, None),
    ],
)
def test_bad_free_period_searches_say_what_would_be_right(tmp_path, eel, flags, message):
    if flags.get("start") == "PERIOD":  # a start with its own period, searched without one
        flags = {"start": write_gait(tmp_path / "g.json", eel, np.r_[eel.default_gait, 0.8],
                                     free_period=True)}  # fmt: skip
        with pytest.raises(OptimizationSetupError, match="sets its own period: search with"):
            prepare_optimization("eel2d", fluid="none", **COARSE, **flags)
        started = prepare_optimization("eel2d", fluid="none", free_period=True, **COARSE, **flags)
        assert started.problem.x0[-1] == 0.8
        return
    with pytest.raises(OptimizationSetupError, match=message):
        prepare_optimization("eel2d", fluid="none", free_period=True, **COARSE, **flags)


def test_a_side_car_that_frees_the_period_already_needs_no_flag(tmp_path):
    sidecar = {"gait": {"free": ["amplitude", "phase", "period"], "shared": ["period"]}}
    path = str(write(tmp_path, "swimmer3", SWIMMER, sidecar))
    with pytest.raises(OptimizationSetupError, match="has its period free already"):
        prepare_optimization(path, fluid="none", free_period=True)


def test_the_follower_refuses_a_gait_with_its_own_period(tmp_path, eel):
    mine = write_gait(tmp_path / "g.json", eel, np.r_[eel.default_gait, 0.8], free_period=True)
    with pytest.raises(SetupError, match="sets its own period"):
        prepare_follow("eel2d", "line", learned=[mine], fluid="none")


def test_the_command_line_takes_free_period(tmp_path, capsys):
    out = tmp_path / "run"
    code = cli.main(["optimize", "eel2d", "--free-period", "--generations", "1", "--popsize",
                     "4", "--workers", "1", "--resolution", "48", "28", "--cell-size", "0.025",
                     "--out", str(out), "--no-video"])  # fmt: skip
    assert code == 0
    assert json.loads((out / "config.json").read_text())["optimization"]["free_period"] is True
    assert read_gait(out / "gait.json").names[-1] == "period"


def test_an_inviscid_swim_has_no_time_scale_of_its_own(eel):
    """The Euler equations and the bodies' dynamics are unchanged when time is stretched:
    the same kinematics at half the period, stepped at half the step, with a servo
    twice as fast, cruise the same distance per cycle, and the work per cycle
    (force times stroke, forces going as velocity squared) is four times larger.
    Measured: 0.3453 and 0.3452 m a cycle, work 3.98 times. What breaks the symmetry
    in a real search is the servo's own time scale (the creature's fixed 100 rad/s:
    -14 % a cycle at half the period, work 3.1 times). So in this fluid the period
    cannot change the Strouhal number (tail amplitude over distance per cycle) but
    through the servo, and an efficiency search given the period slows it down to
    the least speed it may swim."""
    spec = eel.spec(free_period=True)
    scene = make_scene(eel, fluid="euler", **COARSE)
    per_cycle, cost = [], []
    for period in (1.0, 0.5):
        gait = spec.unpack(np.r_[eel.default_gait, period])
        servo = StablePD.tuned(eel.model, gait, eel.natural_frequency / period, eel.damping_ratio)
        traj = rollout(scene, init_state(scene), servo, 6 * period, dt=period / 90,
                       record_fluid=False)  # fmt: skip
        speed, cost_of_transport = cruise(eel.model, traj, (1.0, 0.0), period)
        per_cycle.append(speed * period)
        cost.append(cost_of_transport)
    assert per_cycle[1] == pytest.approx(per_cycle[0], rel=0.01)
    assert cost[1] == pytest.approx(4 * cost[0], rel=0.02)


def test_a_swim_objective_with_a_free_period_is_a_plain_objective_at_the_fixed_one(eel):
    fixed = SwimObjective("eel2d", COARSE["resolution"], COARSE["cell_size"], seconds=0.5)
    free = SwimObjective("eel2d", COARSE["resolution"], COARSE["cell_size"], seconds=0.5,
                         free_period=True)  # fmt: skip
    assert free(np.r_[eel.default_gait, 1.0]) == fixed(eel.default_gait)
