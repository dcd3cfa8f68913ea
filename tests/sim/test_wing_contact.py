"""The wings' own soft contact (a model set's ``[contact] wing_stiffness_n_m, wing_damping_n_s_m``;
sim.world.Contact): both or neither, refused in one line; the links the wing joints carry touch the ground
through it and every other link through the set's contact, so soft wing contact lets the held body sink."""

from pathlib import Path

import numpy as np
import pybullet as pb
import pytest

from sim.model import sim_model
from sim.model_set import ModelSetError, load_model_set
from sim.world import Contact, World


@pytest.mark.parametrize(
    "kw, match",
    [
        ({"wing_stiffness_n_m": 300.0}, "give both"),
        ({"wing_stiffness_n_m": 0.0, "wing_damping_n_s_m": 5.0}, "must be > 0"),
        ({"wing_stiffness_n_m": 300.0, "wing_damping_n_s_m": float("nan")}, "must be > 0"),
    ],
)
def test_bad_values_are_refused(kw, match):
    with pytest.raises(ValueError, match=match):
        Contact(**kw)


def test_the_set_takes_both_keys_or_neither(tmp_path):
    paper = load_model_set("paper")
    text = Path(paper.source).read_text()
    one = tmp_path / "one.toml"
    one.write_text(
        text.replace("solver_iterations = 20", "solver_iterations = 20\nwing_stiffness_n_m = 300.0")
    )
    with pytest.raises(ModelSetError, match="give both wing_stiffness_n_m and wing_damping_n_s_m"):
        load_model_set(one)
    both = tmp_path / "both.toml"
    both.write_text(
        text.replace(
            "solver_iterations = 20",
            "solver_iterations = 20\nwing_stiffness_n_m = 300.0\nwing_damping_n_s_m = 5.0",
        )
    )
    ms = load_model_set(both)
    assert (ms.contact.wing_stiffness_n_m, ms.contact.wing_damping_n_s_m) == (300.0, 5.0)
    assert ms.model_set_hash != paper.model_set_hash


def _held_com_height(contact: Contact) -> tuple[float, dict[str, float]]:
    """The built-in robot placed at pitch 70 deg with its wings at 75 deg, after 1 s: its CoM height (m) and each
    link's contact stiffness (N/m)."""
    with World(sim_model(), dt_s=5e-4, contact=contact) as w:
        names = {j: pb.getJointInfo(w.body, j, physicsClientId=w.cid)[12].decode() for j in range(w.n_joints)}
        stiffness = {
            names[j]: pb.getDynamicsInfo(w.body, j, physicsClientId=w.cid)[9] for j in range(w.n_joints)
        }
        w.place(np.deg2rad(70.0), 0.0, joints_rad=np.deg2rad([75.0, 75.0, 75.0, 75.0, 0.0]))
        w.advance(2000)
        return w.com_height_m(), stiffness


def test_the_wings_touch_through_their_own_contact_and_sink_into_it():
    rigid_h, rigid_k = _held_com_height(Contact())
    soft_h, soft_k = _held_com_height(Contact(wing_stiffness_n_m=300.0, wing_damping_n_s_m=5.0))
    wings = {"motor1", "motor2", "wing1", "wing2"}  # the roll motors and wing plates the wing joints carry
    assert set(rigid_k.values()) == {1e4}
    assert {n for n, k in soft_k.items() if k == 300.0} == wings
    assert all(k == 1e4 for n, k in soft_k.items() if n not in wings)
    assert soft_h < rigid_h - 5e-4  # the body rests on its wings, which sink about load / k into the ground
