"""The engine seam (sim/engine.py): the engines' names, the one-line errors for an unknown or missing engine,
MuJoCo's parameters and their ``[mujoco]`` table, the engine in a model set's identity (its hash), and the soft
servos both worlds share."""

import json
import math
import pickle
import sys
from dataclasses import dataclass, replace
from pathlib import Path
from typing import ClassVar

import numpy as np
import pytest

from sim.engine import (
    ENGINES,
    MUJOCO_DEFAULTS,
    MUJOCO_EXTRA,
    EngineError,
    EngineMissingError,
    EngineWorld,
    SoftServos,
    check_engine,
    open_world,
    require_engine,
)
from sim.model_set import ModelSetError, engine_hash, load_model_set, shipped_model_sets
from sim.modifier import Modifier
from tests.conftest import set_with_table


def test_the_engines_and_an_unknown_one():
    assert ENGINES == ("pybullet", "mujoco")
    with pytest.raises(EngineError, match=r"^unknown engine 'bullet'; choose one of pybullet, mujoco$"):
        check_engine("bullet")
    with pytest.raises(EngineError, match="unknown engine"):
        load_model_set().with_engine("ode")


@pytest.fixture
def without_mujoco(monkeypatch):
    """The interpreter as it is without the optional extra: ``import mujoco`` fails."""
    monkeypatch.setitem(sys.modules, "mujoco", None)
    monkeypatch.delitem(sys.modules, "sim.mujoco_world", raising=False)


def test_mujoco_without_the_extra_is_one_line(without_mujoco):
    from sim.model import sim_model

    with pytest.raises(
        EngineMissingError, match=r"^the mujoco engine needs the optional extra: pip install "
    ):
        require_engine("mujoco")
    with pytest.raises(EngineMissingError) as err:
        open_world("mujoco", sim_model(), dt_s=5e-4)
    assert str(err.value) == MUJOCO_EXTRA and "\n" not in str(err.value)
    require_engine("pybullet")  # pybullet needs no extra


def test_pybullet_world_implements_the_protocol():
    from sim.model import sim_model

    with open_world("pybullet", sim_model(), dt_s=5e-4) as w:
        assert isinstance(w, EngineWorld)
        assert len(w.driven) == len(w.wing_joints) + len(w.leg_joints) == 5


@pytest.mark.parametrize(
    "kw, match",
    [
        ({"solref_time_s": 0.0}, "solref_time_s must be a finite number > 0"),
        ({"solref_dampratio": math.nan}, "solref_dampratio must be a finite number > 0"),
        ({"servo_kv_n_m_s_rad": -1.0}, "servo_kv_n_m_s_rad must be"),
        ({"margin_m": 0.1}, r"margin_m must be in \[0, 0.01\] m"),
        ({"solimp": (0.9, 0.95, 0.001, 0.5)}, "solimp must be five numbers"),
        ({"solimp": (0.96, 0.95, 0.001, 0.5, 2.0)}, "dmin <= dmax"),
        ({"cone": "round"}, "cone must be one of elliptic, pyramidal"),
        ({"integrator": "leapfrog"}, "integrator must be one of implicitfast"),
        ({"solver_iterations": 0}, "solver_iterations must be a whole number >= 1"),
    ],
)
def test_bad_mujoco_parameters_are_refused(kw, match):
    with pytest.raises(EngineError, match=match):
        replace(MUJOCO_DEFAULTS, **kw)


def test_soft_servos_torque_is_the_spring_damper_and_integral_capped():
    """k e + c de/dt, then the integral of the error held since the last command (left rectangles), each joint
    capped at its effort limit, the integral clamped so its torque never exceeds the limit."""
    s = SoftServos([(2.0, 0.5, 0.0), (1.0, 0.0, 10.0)], [1.0, 1.0])
    tau = s.torques([0.1, 0.0], [0.2, 0.0], [0.3, 0.05], [0.0, 0.0], elapsed_s=0.0)
    assert tau == pytest.approx([2.0 * 0.2 + 0.5 * -0.2, 0.05])  # no integral yet: 0.3, 0.05
    tau = s.torques([0.1, 0.0], [0.0, 0.0], [0.3, 0.05], [0.0, 0.0], elapsed_s=0.01)
    assert tau == pytest.approx([0.4, 0.05 + 10.0 * 0.05 * 0.01])  # integral 5e-4 rad s
    tau = s.torques([0.1, 0.0], [0.0, 0.0], [1.0, 5.0], [0.0, 0.0], elapsed_s=100.0)
    assert tau == [1.0, 1.0]  # capped; the integral clamped at limit / ki = 0.1 rad s
    assert s.integral[1] == pytest.approx(0.1)


# ------------------------------------------------------------------------------------------------ identity
MUJOCO_HASHES = {
    "paper": "21b75935aaa2cfa3",
    "physical": "286f3d4d7b1aa1f5",
    "physical-head": "deaa8e2a82e8e07c",
    "physical-offset": "20e89a458ef0d8b2",
    "physical-posed": "8bad56033acec4f2",
}
"""Every shipped set's hash in MuJoCo with the measured defaults (:data:`sim.engine.MUJOCO_DEFAULTS`)."""


@pytest.mark.parametrize("name", sorted(MUJOCO_HASHES))
def test_every_shipped_set_has_a_mujoco_hash_of_its_own(name):
    assert shipped_model_sets() == sorted(MUJOCO_HASHES)
    ms = load_model_set(name)
    mj = ms.with_engine("mujoco")
    assert (ms.engine, mj.engine) == ("pybullet", "mujoco")
    assert mj.model_set_hash == MUJOCO_HASHES[name] != ms.model_set_hash
    assert mj.with_engine("pybullet") == ms and mj.with_engine("pybullet").model_set_hash == ms.model_set_hash
    assert mj.label.endswith("[mujoco]") and not ms.label.endswith("]")
    assert pickle.loads(pickle.dumps(mj)) == mj  # travels to a worker with its engine


def test_the_two_engines_hash_only_what_they_read(tmp_path):
    """pybullet's hash ignores [mujoco]; MuJoCo's ignores pybullet's own contact keys (restitution, its soft
    contact spring, solver iterations, friction axes) and sees the shared friction and every MuJoCo parameter."""
    paper = load_model_set("paper")
    text = "solref_time_s = 0.005\nsolimp = [0.9, 0.95, 0.001, 0.5, 2]\n"
    tuned = load_model_set(set_with_table(tmp_path, "mujoco", text))
    assert tuned.mujoco == replace(MUJOCO_DEFAULTS, solref_time_s=0.005)
    assert tuned.model_set_hash == paper.model_set_hash  # pybullet does not read [mujoco]
    assert tuned.with_engine("mujoco").model_set_hash != paper.with_engine("mujoco").model_set_hash
    text = (tmp_path / "mujoco.toml").read_text()
    f = tmp_path / "x.toml"
    f.write_text(
        text.replace("restitution = 0.1", "restitution = 0.5").replace(
            "solver_iterations = 20", "solver_iterations = 7"
        )
    )
    other = load_model_set(f)
    assert other.model_set_hash != tuned.model_set_hash
    assert other.with_engine("mujoco").model_set_hash == tuned.with_engine("mujoco").model_set_hash
    f.write_text(text.replace("lateral_friction = 1.0", "lateral_friction = 0.8"))
    assert (
        load_model_set(f).with_engine("mujoco").model_set_hash != tuned.with_engine("mujoco").model_set_hash
    )
    f.write_text(text.replace("solref_time_s = 0.005", f"solref_time_s = {MUJOCO_DEFAULTS.solref_time_s}"))
    assert (
        load_model_set(f).with_engine("mujoco").model_set_hash == paper.with_engine("mujoco").model_set_hash
    )
    # the hash of the content: pybullet's is the content's own, MuJoCo's adds the engine and its parameters
    content = json.loads(paper.canonical_json)
    assert engine_hash(content, "pybullet") == paper.model_set_hash
    assert engine_hash(content, "mujoco", MUJOCO_DEFAULTS) == paper.with_engine("mujoco").model_set_hash


@pytest.mark.parametrize(
    "text, match",
    [
        ("solref_time = 0.005\n", r"\[mujoco\]: unknown key 'solref_time'"),
        ("solref_time_s = -1\n", r"\[mujoco\]: solref_time_s must be a finite number > 0"),
        ('cone = "square"\n', r"\[mujoco\]: cone must be one of elliptic, pyramidal"),
        ("solimp = [0.9, 0.95]\n", r"\[mujoco\]: solimp must be five numbers"),
    ],
)
def test_a_bad_mujoco_table_is_one_line(tmp_path, text, match):
    with pytest.raises(ModelSetError, match=match) as err:
        load_model_set(set_with_table(tmp_path, "mujoco", text))
    assert "\n" not in str(err.value)


@dataclass(frozen=True)
class _PybulletOnly(Modifier):
    """A modifier only pybullet can express (a test double: not registered)."""

    TABLE: ClassVar[str] = "pybullet_only"
    ENGINES: ClassVar[tuple[str, ...]] = ("pybullet",)

    def canonical(self) -> dict:
        return {}


def test_a_modifier_the_engine_cannot_express_is_refused_in_one_line():
    ms = replace(load_model_set(), modifiers=(_PybulletOnly(),))
    assert ms.with_engine("pybullet") is ms
    with pytest.raises(EngineError) as err:
        ms.with_engine("mujoco")
    assert str(err.value) == (
        "model set 'paper': the mujoco engine cannot express [pybullet_only] (_PybulletOnly; it runs in pybullet); "
        "use --engine pybullet or drop [pybullet_only]"
    )


def test_the_wings_own_soft_contact_is_pybullet_only(tmp_path):
    text = (
        Path(load_model_set("paper").source)
        .read_text()
        .replace(
            "solver_iterations = 20",
            "solver_iterations = 20\nwing_stiffness_n_m = 2000.0\nwing_damping_n_s_m = 20.0",
        )
    )
    f = tmp_path / "wings.toml"
    f.write_text(text)
    ms = load_model_set(f)
    with pytest.raises(
        EngineError, match=r"cannot express \[contact\] wing_stiffness_n_m and wing_damping_n_s_m"
    ):
        ms.with_engine("mujoco")


def test_a_trial_reports_its_engine_and_its_sets_hash_in_it():
    from sim.trial import run_trial

    r = run_trial(74.0, 30.0, phase=0.7, cv=0.0, rng=1, duration_s=0.2)
    assert r.engine == "pybullet" and r.model_set_hash == load_model_set().model_set_hash
    assert r.to_dict()["engine"] == "pybullet"
    assert np.isfinite(r.cpu_s)
