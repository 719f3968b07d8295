"""The MJCF text checks: default classes, childclass, and reading paths or strings."""

import numpy as np
import pytest

from aquagait.body import load_model
from aquagait.body.mjcf import ModelError, check_xml, read_mjcf


def test_density_through_default_classes_and_childclass():
    xml = """<mujoco>
      <default><geom density="500"/>
        <default class="dense"><geom density="2000"/></default></default>
      <worldbody><body name="a"><freejoint/><geom type="box" size=".1 .1 .1"/>
        <body name="b" childclass="dense" pos=".3 0 0">
          <joint type="hinge" axis="0 0 1" range="-10 10"/><geom type="box" size=".1 .1 .1"/>
        </body></body></worldbody></mujoco>"""
    model = load_model(xml)
    np.testing.assert_allclose(model.link_mass, [500 * 0.008, 2000 * 0.008])


def test_density_is_looked_up_through_nested_default_classes():
    xml = """<mujoco><default><geom density="800"/>
        <default class="a"><default class="b"><geom type="box"/></default></default></default>
      <worldbody><body name="x"><freejoint/><geom class="b" size=".1 .1 .1"/></body></worldbody>
      </mujoco>"""
    check_xml(xml, "<string>")  # 'b' inherits density from the top-level default
    assert load_model(xml).mass == pytest.approx(800 * 0.008)


def test_a_bad_density_through_a_default_class_is_refused():
    xml = """<mujoco><default><default class="a"><geom type="box" density="-5"/></default>
      </default><worldbody><body name="x"><freejoint/><geom class="a" size=".1 .1 .1"/></body>
      </worldbody></mujoco>"""
    with pytest.raises(ModelError, match="geom #0 in body 'x' has density '-5'; it must be a"):
        check_xml(xml, "<string>")


def test_read_tells_strings_from_paths(tmp_path):
    text = "<mujoco/>"
    assert read_mjcf("  " + text) == ("  " + text, None, "<string>")
    path = tmp_path / "m.xml"
    path.write_text(text)
    assert read_mjcf(path) == (text, path, str(path))
    assert read_mjcf(str(path))[1] == path
