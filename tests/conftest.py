"""Models shared by tests in several folders."""

import dataclasses

import numpy as np
import pytest

import aquagait as ag

# A planar two-link body: one actuated DOF, so a servo's stability bound is exact.
TWO_LINKS = """<mujoco><custom><numeric name="aquagait_depth" data="0.04"/></custom>
  <worldbody><body name="front">
    <joint type="slide" axis="1 0 0"/><joint type="slide" axis="0 1 0"/>
    <joint type="hinge" axis="0 0 1"/>
    <geom type="box" size=".1 .02 .02" density="1000"/>
    <body name="back" pos="-.1 0 0"><joint name="j" type="hinge" axis="0 0 1" range="-60 60"/>
      <geom type="box" size=".1 .015 .02" pos="-.1 0 0" density="1000"/></body>
  </body></worldbody></mujoco>"""


@pytest.fixture
def two_links() -> str:
    """MJCF text of the planar two-link body."""
    return TWO_LINKS


@pytest.fixture(scope="session")
def eel():
    """The library's eel2d creature."""
    return ag.creatures.get("eel2d")


@pytest.fixture(scope="session")
def hand_set_eel(eel):
    """eel2d swimming its hand-set travelling wave (the side-car's ``hand-set`` gait, its
    default until the optimized one shipped): for tests whose figures were measured with it."""
    return dataclasses.replace(eel, default_gait=eel.gaits["hand-set"].params)


WIDE_EEL_GAIT = [0.44341793, 0.46879662, 0.57438825, 0.45675016,
                 -0.58368707, -1.78715780, -2.48963701, 3.08331931]  # fmt: skip
"""eel2d's optimized straight gait shipped from 2026-11-30 to 2026-12-04 (amplitudes, then
phases [rad]): its widest pose is 0.17 m across."""


@pytest.fixture(scope="session")
def wide_eel(eel):
    """eel2d swimming ``WIDE_EEL_GAIT``: for tests whose grid sizes were measured with it,
    so that they do not move when the library's gait is optimized again."""
    return dataclasses.replace(eel, default_gait=np.array(WIDE_EEL_GAIT))


# A planar body: a 40 mm wide block and behind it a fin plate 2 mm thick, a fifth of a
# 10 mm cell: on cells centred on y = +-5 mm the fin holds no cell centre at all.
FIN_PLATE = """<mujoco><custom><numeric name="aquagait_depth" data="0.04"/></custom>
  <worldbody><body name="block">
    <joint type="slide" axis="1 0 0"/><joint type="slide" axis="0 1 0"/>
    <joint type="hinge" axis="0 0 1"/>
    <geom type="box" size=".05 .02 .02" density="1000"/>
    <body name="fin" pos="-.05 0 0"><joint name="j" type="hinge" axis="0 0 1" range="-30 30"/>
      <geom type="box" size=".05 .001 .02" pos="-.05 0 0" density="1000"/></body>
  </body></worldbody></mujoco>"""


@pytest.fixture
def fin_plate() -> str:
    """MJCF text of the block with a 2 mm fin."""
    return FIN_PLATE
