"""Sine gaits: the parameter vector layout, sharing, mirroring, groups, bounds and limits."""

import numpy as np
import pytest

from aquagait.control import GaitSpec, SwitchedGait, mix

DOFS = ("j1", "j2", "j3")


def test_default_layout_is_amplitude_then_phase_per_dof():
    spec = GaitSpec(dofs=DOFS)
    assert spec.names == (
        "amplitude[j1]", "amplitude[j2]", "amplitude[j3]",
        "phase[j1]", "phase[j2]", "phase[j3]",
    )  # fmt: skip
    gait = spec.unpack([0.1, 0.2, 0.3, 0.0, -1.0, -2.0])
    np.testing.assert_array_equal(gait.amplitude, [0.1, 0.2, 0.3])
    np.testing.assert_array_equal(gait.phase, [0.0, -1.0, -2.0])
    np.testing.assert_array_equal(gait.period, [1.0, 1.0, 1.0])  # fixed by default
    np.testing.assert_array_equal(gait.offset, [0.0, 0.0, 0.0])


def test_angles_follow_the_sine_formula_and_rates_are_its_derivative():
    spec = GaitSpec(dofs=DOFS, free=("amplitude", "phase", "period", "offset"))
    x = spec.pack(amplitude=[0.1, 0.2, 0.3], phase=[0, 1, 2], period=[1, 2, 0.5], offset=0.05)
    gait = spec.unpack(x)
    t = 0.37
    expected = gait.amplitude * np.sin(2 * np.pi * t / gait.period + gait.phase) + gait.offset
    np.testing.assert_allclose(gait.angles(t), expected, rtol=1e-15)
    h = 1e-6
    fd = (gait.angles(t + h) - gait.angles(t - h)) / (2 * h)
    np.testing.assert_allclose(gait.rates(t), fd, rtol=1e-8)
    # a quarter period after phase 0 the first DOF is at amplitude + offset
    assert gait.angles(0.25)[0] == pytest.approx(0.15)


def test_pack_and_unpack_are_inverse():
    spec = GaitSpec(dofs=DOFS)
    x = np.array([0.1, 0.2, 0.3, 0.5, -0.5, 1.5])
    gait = spec.unpack(x)
    np.testing.assert_array_equal(spec.pack(amplitude=gait.amplitude, phase=gait.phase), x)


def test_shared_amplitude_drives_every_dof_with_one_number():
    """The accordion: one optimized number, no phase shift between DOFs."""
    spec = GaitSpec(dofs=DOFS, free=("amplitude",), shared=("amplitude",))
    assert spec.names == ("amplitude",)
    gait = spec.unpack([0.4])
    np.testing.assert_array_equal(gait.amplitude, [0.4, 0.4, 0.4])
    np.testing.assert_array_equal(gait.phase, [0.0, 0.0, 0.0])
    np.testing.assert_allclose(gait.angles(0.1), np.full(3, 0.4 * np.sin(0.2 * np.pi)))


def test_shared_period_is_one_number_among_per_dof_parameters():
    spec = GaitSpec(dofs=DOFS, free=("amplitude", "phase", "period"), shared=("period",))
    assert spec.size == 7 and spec.names[-1] == "period"
    np.testing.assert_array_equal(spec.unpack(np.r_[np.zeros(6), 1.5]).period, [1.5] * 3)


def test_mirror_copies_a_sine_with_a_sign_and_halves_the_parameters():
    spec = GaitSpec(
        dofs=("left", "right", "tail"),
        free=("amplitude", "phase", "offset"),
        mirror=(("right", "left", -1.0),),
    )
    assert spec.independent == ("left", "tail")
    assert spec.size == 6
    gait = spec.unpack(spec.pack(amplitude=[0.3, 0, 0.2], phase=[0.7, 0, 0.1], offset=0.1))
    for t in np.linspace(0, 1, 7):
        left, right, _ = gait.angles(t)
        assert right == pytest.approx(-left, abs=1e-15)


def test_mirrored_gait_negates_every_reference_angle():
    spec = GaitSpec(dofs=DOFS, free=("amplitude", "phase", "offset"))
    gait = spec.unpack(spec.pack(amplitude=[0.1, 0.2, 0.3], phase=[0, 1, 2], offset=[0.1, 0, -0.1]))
    np.testing.assert_allclose(gait.mirrored().angles(0.3), -gait.angles(0.3), atol=1e-15)


def test_groups_select_their_parameters_and_shared_ones_belong_to_all():
    spec = GaitSpec(
        dofs=("hind_l", "hind_r", "fore_l", "fore_r"),
        free=("amplitude", "phase", "period"),
        shared=("period",),
        groups=(("hind_l", "hind_r"), ("fore_l", "fore_r")),
    )
    hind = [spec.names[i] for i in spec.group_indices(0)]
    fore = [spec.names[i] for i in spec.group_indices(1)]
    assert hind == ["amplitude[hind_l]", "amplitude[hind_r]", "phase[hind_l]", "phase[hind_r]",
                    "period"]  # fmt: skip
    assert fore == ["amplitude[fore_l]", "amplitude[fore_r]", "phase[fore_l]", "phase[fore_r]",
                    "period"]  # fmt: skip
    with pytest.raises(IndexError, match="2 group"):
        spec.group_indices(2)


def test_bounds_by_kind_and_by_parameter():
    spec = GaitSpec(dofs=DOFS, bounds={"amplitude": (0, 0.5), "amplitude[j3]": (0, 0.9)})
    np.testing.assert_allclose(spec.lower, [0, 0, 0, -np.pi, -np.pi, -np.pi])
    np.testing.assert_allclose(spec.upper, [0.5, 0.5, 0.9, np.pi, np.pi, np.pi])


def test_limit_violations_name_the_dofs_that_swing_too_far():
    spec = GaitSpec(dofs=DOFS, free=("amplitude", "phase", "offset"))
    x = spec.pack(amplitude=[0.3, 0.5, 0.2], phase=0.0, offset=[0.0, 0.0, 0.35])
    limits = np.full(3, 0.4)
    problems = spec.limit_violations(x, -limits, limits)
    assert len(problems) == 2
    assert problems[0].startswith("j2: swings over [-0.5, 0.5]")
    assert problems[1].startswith("j3: swings over [0.15, 0.55]")
    assert spec.limit_violations(spec.pack(amplitude=0.4, phase=0, offset=0), -limits, limits) == []


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"dofs": ("a", "a")}, "distinct names"),
        ({"dofs": DOFS, "free": ("amplitude", "speed")}, "unknown"),
        ({"dofs": DOFS, "shared": ("period",)}, "must also be free"),
        ({"dofs": DOFS, "mirror": (("j2", "fin", -1),)}, "names a DOF not in"),
        ({"dofs": DOFS, "mirror": (("j2", "j1", 2),)}, "must be \\+1 or -1"),
        ({"dofs": DOFS, "mirror": (("j2", "j1", 1), ("j3", "j2", 1))}, "independent DOF"),
        ({"dofs": DOFS, "groups": (("j1",), ("j2",))}, "every DOF"),
        ({"dofs": DOFS, "bounds": {"speed": (0, 1)}}, "not gait parameters"),
        ({"dofs": DOFS, "bounds": {"amplitude": (1, 0)}}, "lower < upper"),
    ],
)
def test_bad_specs_say_what_is_wrong(kwargs, message):
    with pytest.raises(ValueError, match=message):
        GaitSpec(**kwargs)


def test_a_wrong_vector_lists_the_parameters():
    spec = GaitSpec(dofs=("j1",))
    with pytest.raises(ValueError, match=r"this gait has 2: amplitude\[j1\], phase\[j1\]"):
        spec.unpack([1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="needs a value for 'phase'"):
        spec.pack(amplitude=0.1)
    with pytest.raises(ValueError, match="not free"):
        spec.pack(amplitude=0.1, phase=0, period=2)


def test_non_positive_period_is_refused():
    spec = GaitSpec(dofs=("j1",), free=("period",), bounds={"period": (0.1, 2)})
    with pytest.raises(ValueError, match="periods must be > 0"):
        spec.unpack([0.0])


# --- a manoeuvre's parameters, and switching between gaits (paper §5) ------------

TIMES = np.linspace(0.0, 2.0, 41)


def _angles(gait, times=TIMES):
    return np.array([gait.angles(t) for t in times])


def test_vector_is_unpack_s_inverse_and_folds_a_negative_amplitude_into_the_phase():
    spec = GaitSpec(dofs=("a", "b", "c"), free=("amplitude", "phase", "offset"))
    x = np.array([0.2, 0.3, 0.4, -2.0, 0.5, 3.0, 0.1, -0.2, 0.0])
    np.testing.assert_allclose(spec.vector(spec.unpack(x)), x)
    mirrored = spec.unpack(x).mirrored()  # negative amplitudes
    y = spec.vector(mirrored)
    assert np.all(spec.unpack(y).amplitude >= 0)
    assert np.all((-np.pi <= y[3:6]) & (y[3:6] < np.pi))
    np.testing.assert_allclose(_angles(spec.unpack(y)), _angles(mirrored), atol=1e-12)


def test_vector_refuses_a_gait_of_other_dofs():
    with pytest.raises(ValueError, match="drives"):
        GaitSpec(dofs=("a",)).vector(GaitSpec(dofs=("b",)).unpack([0.1, 0.0]))


def _pair():
    spec = GaitSpec(dofs=("a", "b"), free=("amplitude", "phase", "offset"))
    return spec.unpack([0.3, 0.5, 0.0, 1.0, 0.0, 0.0]), spec.unpack(
        [0.4, 0.2, 2.0, -1.0, 0.3, -0.2]
    )


def test_a_switch_is_the_old_gait_before_and_the_new_one_after():
    before, after = _pair()
    switch = SwitchedGait(before, after, start=0.5, duration=0.25)
    early, late = TIMES[TIMES <= 0.5], TIMES[TIMES >= 0.75]
    np.testing.assert_allclose(_angles(switch, early), _angles(before, early), atol=1e-15)
    np.testing.assert_allclose(_angles(switch, late), _angles(after, late), atol=1e-15)
    assert switch.dofs == ("a", "b")


def test_a_switch_neither_jumps_the_angles_nor_their_rates():
    """Sampled every 0.1 ms across the hand-over, no step exceeds what the rates allow."""
    before, after = _pair()
    switch = SwitchedGait(before, after, start=0.5, duration=0.25)
    times = np.arange(0.45, 0.8, 1e-4)
    angles = _angles(switch, times)
    rates = np.array([switch.rates(t) for t in times])
    central = (angles[2:] - angles[:-2]) / 2e-4
    smooth = (np.abs(times[1:-1] - 0.5) > 2e-4) & (np.abs(times[1:-1] - 0.75) > 2e-4)
    # rates are the derivative (away from the blend's ends, where the second derivative jumps)
    np.testing.assert_allclose(central[smooth], rates[1:-1][smooth], atol=1e-5)
    assert np.abs(np.diff(rates, axis=0)).max() < 1e-2  # and continuous: no kink


def test_a_mix_is_the_weighted_sum_of_the_references_and_one_gait_whole_is_itself():
    before, after = _pair()
    half = mix([before, after], [0.7, 0.3])
    np.testing.assert_allclose(_angles(half, TIMES),
                               0.7 * _angles(before, TIMES) + 0.3 * _angles(after, TIMES),
                               atol=1e-12)  # fmt: skip
    rates = np.array([half.rates(t) for t in TIMES])
    np.testing.assert_allclose(
        rates, [0.7 * before.rates(t) + 0.3 * after.rates(t) for t in TIMES], atol=1e-12
    )
    assert mix([before, after], [0.0, 1.0]) is after
    with pytest.raises(ValueError, match="one weight per gait"):
        mix([before, after], [1.0])
    with pytest.raises(ValueError, match="same DOFs"):
        mix([before, GaitSpec(dofs=("b", "a")).unpack([0.1] * 4)], [0.5, 0.5])


def test_a_switch_of_no_duration_jumps_and_bad_switches_are_refused():
    before, after = _pair()
    jump = SwitchedGait(before, after, start=0.5, duration=0.0)
    np.testing.assert_allclose(jump.angles(0.5), after.angles(0.5))
    np.testing.assert_allclose(jump.angles(0.4999), before.angles(0.4999))
    with pytest.raises(ValueError, match="same DOFs"):
        SwitchedGait(before, GaitSpec(dofs=("b", "a")).unpack([0.1] * 4), 0.0, 0.1)
    with pytest.raises(ValueError, match="duration"):
        SwitchedGait(before, after, 0.0, -1.0)


def test_held_dofs_only_hold_an_offset():
    spec = GaitSpec(dofs=("a", "b", "rudder"), free=("amplitude", "phase", "offset"),
                    held=("rudder",))  # fmt: skip
    assert spec.names == ("amplitude[a]", "amplitude[b]", "phase[a]", "phase[b]", "offset[a]",
                          "offset[b]", "offset[rudder]")  # fmt: skip
    gait = spec.unpack([0.3, 0.4, 0.0, 1.0, 0.1, 0.0, -0.2])
    assert gait.amplitude[2] == 0.0 and gait.offset[2] == -0.2
    np.testing.assert_allclose([gait.angles(t)[2] for t in (0.0, 0.3, 0.7)], -0.2)
    np.testing.assert_array_equal(spec.vector(gait), [0.3, 0.4, 0.0, 1.0, 0.1, 0.0, -0.2])
    with pytest.raises(ValueError, match="held DOFs"):
        GaitSpec(dofs=("a",), held=("b",))


def test_a_gait_on_more_dofs_holds_the_others_at_rest():
    gait = GaitSpec(dofs=("a", "b")).unpack([0.3, 0.4, 0.0, 1.0])
    wider = gait.on(("c", "b", "a"))
    assert wider.dofs == ("c", "b", "a")
    for t in (0.0, 0.25, 0.6):
        np.testing.assert_allclose(wider.angles(t), [0.0, *gait.angles(t)[::-1]])
    with pytest.raises(ValueError, match="not among"):
        gait.on(("a",))
