"""Shared models for the body tests: every geom type, free root, ball and hinge joints."""

import pytest

from aquagait.body import Dynamics, load_model

# 3D: free root, a ball joint and two hinges with skew axes, every allowed geom type.
SNAKE3D = """
<mujoco model="snake3d">
  <asset>
    <mesh name="fin" vertex="0 0 -.03  0 0 .03  -.08 .004 -.05  -.08 .004 .05  -.08 -.004 0"/>
  </asset>
  <worldbody>
    <body name="torso" pos=".1 .02 -.03" euler="10 20 30">
      <freejoint/>
      <geom type="ellipsoid" size=".12 .04 .05" density="1000"/>
      <geom type="sphere" size=".03" pos=".1 0 .02" density="1100"/>
      <body name="neck" pos="-.12 0 0">
        <joint name="ball" type="ball" range="0 60"/>
        <geom type="capsule" fromto="0 0 0 -.1 .01 0" size=".025" density="950"/>
        <body name="mid" pos="-.1 .01 0">
          <joint name="h1" type="hinge" axis="0 .3 1" range="-40 40"/>
          <geom type="box" size=".05 .02 .03" pos="-.05 0 .01" density="1000"/>
          <body name="tail" pos="-.1 0 0">
            <joint name="h2" type="hinge" axis=".2 0 1" range="-50 50"/>
            <geom type="cylinder" fromto="0 0 0 -.06 0 0" size=".015" density="1000"/>
            <geom type="mesh" mesh="fin" pos="-.06 0 0" density="1000"/>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.fixture(scope="session")
def snake():
    return load_model(SNAKE3D)


@pytest.fixture(scope="session")
def snake_dynamics(snake):
    return Dynamics(snake.mj)
