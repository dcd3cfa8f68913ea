"""URDF edits for simulation (sim/urdf_edits.py): mass properties in closed form."""

import numpy as np
import pytest
from lxml import etree as ET

from sim.urdf_edits import base_link, merge_fixed_links, shift_com

TWO_BOXES = (
    '<robot name="r"><link name="a"><inertial><mass value="{m1}"/><inertia ixx="{i}" iyy="{i}" izz="{i}"/>'
    '</inertial></link><link name="b"><inertial><mass value="{m2}"/><inertia ixx="{i}" iyy="{i}" izz="{i}"/>'
    '</inertial></link><joint name="j" type="fixed"><parent link="a"/><child link="b"/>'
    '<origin xyz="{d} 0 0"/></joint></robot>'
)


@pytest.mark.parametrize("m1,m2,d", [(1.0, 1.0, 0.5), (2.0, 0.5, 0.1)])
def test_merging_two_masses_gives_the_parallel_axis_inertia(m1, m2, d):
    root = ET.fromstring(TWO_BOXES.format(m1=m1, m2=m2, d=d, i=0.01))
    assert merge_fixed_links(root) == ["b"]
    el = root.find("link/inertial")
    com = np.array([float(v) for v in el.find("origin").get("xyz").split()])
    mass = m1 + m2
    assert float(el.find("mass").get("value")) == pytest.approx(mass, rel=1e-15)
    np.testing.assert_allclose(com, [m2 * d / mass, 0, 0], rtol=0, atol=1e-15)
    reduced = m1 * m2 / mass * d**2  # both masses about their common CoM
    inertia = el.find("inertia")
    assert float(inertia.get("ixx")) == pytest.approx(0.02, rel=1e-12)
    assert float(inertia.get("iyy")) == pytest.approx(0.02 + reduced, rel=1e-12)
    assert float(inertia.get("izz")) == pytest.approx(0.02 + reduced, rel=1e-12)


def test_shift_com_moves_the_whole_com_by_the_offset():
    root = ET.fromstring(
        TWO_BOXES.format(m1=1.0, m2=3.0, d=0.2, i=0.01).replace('type="fixed"', 'type="revolute"')
    )
    assert base_link(root).get("name") == "a"
    shift_com(root, [0.0, 0.002, 0.0])
    com_a = np.array([float(v) for v in root.find("link/inertial/origin").get("xyz").split()])
    np.testing.assert_allclose(com_a, [0.0, 0.008, 0.0], rtol=0, atol=1e-15)  # 2 mm * 4 kg / 1 kg
