"""Compliant wings (sim/compliance.py): values and stability refused in one line, the model-set table, and the
physics: the wings give under load by about load / k, so a softer spring deflects more and a stiff one behaves
like the rigid servo; with an integral time the servo takes a steady load over and the sag goes."""

import numpy as np
import pytest

from sim.compliance import BodyTorsion, Compliance, ComplianceError, LegBend, LegCompliance, check_stability
from sim.model_set import ModelSetError, load_model_set
from sim.trial import run_trial
from tests.conftest import set_with_table


@pytest.mark.parametrize(
    "k, c, match",
    [(0.0, 0.0, "must be > 0"), (1.0, -1.0, ">= 0"), (float("nan"), 0.0, "finite"), (True, 0.0, "finite")],
)
def test_bad_values_are_refused(k, c, match):
    with pytest.raises(ComplianceError, match=match):
        Compliance(k, c)


@pytest.mark.parametrize("ti, match", [(0.0, "must be > 0"), (-1.0, "must be > 0"), (float("inf"), "finite")])
def test_bad_integral_times_are_refused(ti, match):
    with pytest.raises(ComplianceError, match=match):
        Compliance(0.2, 0.005, ti)


def test_stability_bound():
    check_stability(Compliance(1.0, 0.01), 4.7e-5, 1e-3)  # sqrt(k/I) T = 0.15
    with pytest.raises(ComplianceError, match=r"give k <= 11\.8"):
        check_stability(Compliance(1000.0), 4.7e-5, 1e-3)
    with pytest.raises(ComplianceError, match="wing_damping"):
        check_stability(Compliance(1.0, 0.1), 4.7e-5, 1e-3)  # c T / I = 2.1
    check_stability(Compliance(0.2, 0.005, 0.01), 4.7e-5, 1e-3)
    with pytest.raises(ComplianceError, match=r"wing_integral_time_s 0\.001 is too short.*at least 0\.002 s"):
        check_stability(Compliance(0.2, 0.005, 0.001), 4.7e-5, 1e-3)


def _held_spring_amplitude(k, c, inertia, period, periods):
    """An oscillator whose force -k x - c v is computed at each period's start and held through it, integrated
    exactly within the period: its amplitude after ``periods`` periods from x = 1."""
    x, v = 1.0, 0.0
    for _ in range(periods):
        a = -(k * x + c * v) / inertia
        x, v = x + v * period + a * period**2 / 2, v + a * period
    return float(np.hypot(x, v / np.sqrt(k / inertia)))


def test_a_held_spring_gains_energy_below_the_damping_the_check_asks():
    """The criterion c >= k T / 2 of check_spring is where the held update turns from losing energy to gaining
    it, and the growth rate below it is (k T / 2 - c) / (2 I) as its docstring says."""
    k, inertia, period = 4.0, 4.7e-5, 1e-3
    c_min = k * period / 2
    assert _held_spring_amplitude(k, 1.05 * c_min, inertia, period, 2000) < 1.0
    grown = _held_spring_amplitude(k, 0.95 * c_min, inertia, period, 2000)
    assert grown > 1.0
    assert _held_spring_amplitude(k, 0.5 * c_min, inertia, period, 400) == pytest.approx(
        np.exp((c_min - 0.5 * c_min) / (2 * inertia) * 0.4), rel=0.1
    )
    check_stability(Compliance(k, 1.05 * c_min), inertia, period)
    with pytest.raises(
        ComplianceError, match=r"gains energy.*give c >= 0\.002 N m s/rad or k <= 3\.8 N m/rad"
    ):
        check_stability(Compliance(k, 0.95 * c_min), inertia, period)
    with pytest.raises(ComplianceError, match=r"gains energy.*give c >= 0\.002 N m s/rad$"):
        check_stability(Compliance(k, 0.0), inertia, period)


def test_a_spring_that_gains_energy_is_refused_before_the_trial(tmp_path):
    """4 N·m/rad with 0.001 N·m·s/rad on the wings spun the lab robot's body over in its first opening before the
    check (docs/physical/time-to-right.md); now the trial is refused in one line."""
    ms = load_model_set(
        set_with_table(
            tmp_path, "compliance", "wing_stiffness_n_m_rad = 4.0\nwing_damping_n_m_s_rad = 0.001\n"
        )
    )
    with pytest.raises(
        ComplianceError, match=r"wing_stiffness_n_m_rad 4 with wing_damping_n_m_s_rad 0\.001 gains"
    ):
        run_trial(75.0, 0.0, phase=0.5, cv=0.0, rng=1, duration_s=0.5, model_set=ms)


def test_model_set_table(tmp_path):
    ms = load_model_set(
        set_with_table(
            tmp_path, "compliance", "wing_stiffness_n_m_rad = 0.9\nwing_damping_n_m_s_rad = 0.005\n"
        )
    )
    assert ms.compliance == Compliance(0.9, 0.005)
    assert (
        ms.model_set_hash != load_model_set("paper").model_set_hash
        and load_model_set("paper").compliance is None
    )
    with pytest.raises(ModelSetError, match="unknown key"):
        load_model_set(set_with_table(tmp_path, "compliance", "wing_stifness_n_m_rad = 1.0\n"))
    with pytest.raises(ModelSetError, match="wing_stiffness_n_m_rad"):
        load_model_set(set_with_table(tmp_path, "compliance", "wing_stiffness_n_m_rad = -1.0\n"))
    pi = load_model_set(
        set_with_table(
            tmp_path,
            "compliance",
            "wing_stiffness_n_m_rad = 0.9\nwing_damping_n_m_s_rad = 0.005\nwing_integral_time_s = 0.3\n",
        )
    )
    assert pi.compliance == Compliance(0.9, 0.005, 0.3)
    assert pi.model_set_hash != ms.model_set_hash  # the integral enters the hash; sets without it keep theirs
    with pytest.raises(ModelSetError, match="wing_integral_time_s must be > 0"):
        load_model_set(
            set_with_table(tmp_path, "compliance", "wing_stiffness_n_m_rad = 0.9\nwing_integral_time_s = 0\n")
        )


@pytest.mark.parametrize(
    "cls, k, c", [(BodyTorsion, 0.05, 0.002), (LegCompliance, 0.08, 0.001), (LegBend, 0.135, 0.00055)]
)
def test_a_spring_table_in_a_model_set(tmp_path, cls, k, c):
    """``[body_torsion]``, ``[leg_compliance]``, ``[leg_bend]``: one reader; the table enters the hash, its
    damping is optional, and a wrong key, a missing stiffness or a stiffness <= 0 is refused naming the table."""
    table = cls.TABLE
    ms = load_model_set(
        set_with_table(tmp_path, table, f"stiffness_n_m_rad = {k}\ndamping_n_m_s_rad = {c}\n")
    )
    paper = load_model_set("paper")
    assert getattr(ms, table) == cls(k, c) and getattr(paper, table) is None
    assert ms.model_set_hash != paper.model_set_hash
    assert getattr(
        load_model_set(set_with_table(tmp_path, table, "stiffness_n_m_rad = 0.1\n")), table
    ) == cls(0.1)
    with pytest.raises(ModelSetError, match=rf"\[{table}\].*unknown key"):
        load_model_set(set_with_table(tmp_path, table, "stifness_n_m_rad = 0.1\n"))
    with pytest.raises(ModelSetError, match=rf"\[{table}\].*missing key 'stiffness_n_m_rad'"):
        load_model_set(set_with_table(tmp_path, table, "damping_n_m_s_rad = 0.1\n"))
    with pytest.raises(ModelSetError, match=rf"\[{table}\].*must be > 0"):
        load_model_set(set_with_table(tmp_path, table, "stiffness_n_m_rad = -1.0\n"))


def _hold(comp, duration=2.0):
    """Median body pitch and wing-command minus measured wing angle 0.5-0.95 s after the first opening."""
    r = run_trial(75.0, 0.0, phase=0.5, cv=0.0, rng=1, duration_s=duration, trace=True, compliance=comp)
    tr, s0 = r.trace, r.attempt_starts_s[0]
    m = (tr.t_s > s0 + 0.5) & (tr.t_s < s0 + 0.95)
    return float(np.median(tr.pitch_deg[m])), float(np.median(tr.wing_cmd_deg[m] - tr.wing_deg[m])), r


def test_softer_wings_give_more_and_stiff_ones_act_rigid():
    rigid_pitch, rigid_sag, _ = _hold(None)
    sags = {k: _hold(Compliance(k, 0.005))[1] for k in (0.3, 0.9, 3.0)}
    assert abs(rigid_sag) < 0.1
    assert sags[0.3] > sags[0.9] > sags[3.0] > 0  # the load closes the wings, more on a softer spring
    # about load / k: the sag times k stays within a factor of 3 over a tenfold change of k
    loads = [k * s for k, s in sags.items()]
    assert max(loads) / min(loads) < 3.0
    stiff_pitch, _, _ = _hold(Compliance(3.0, 0.005))
    assert abs(stiff_pitch - rigid_pitch) < 1.0


def test_an_integrating_servo_takes_the_steady_load_over():
    """A soft spring (0.3 N m/rad) sags under the held body and lets it lean 2.5 deg less far over than the rigid
    servo; the same spring with an integral time of 0.3 s has taken most of the load over by the hold (0.5-0.95 s
    after the opening starts): less than half the sag and less than half the lean. Not all of it: the wing tips
    are held by friction on the ground, so the joints cannot always turn back to the command."""
    rigid_pitch, _, _ = _hold(None)
    spring_pitch, spring_sag, _ = _hold(Compliance(0.3, 0.005))
    pi_pitch, pi_sag, _ = _hold(Compliance(0.3, 0.005, 0.3))
    assert spring_sag > 2.0 and rigid_pitch - spring_pitch > 2.0
    assert abs(pi_sag) < 0.5 * spring_sag
    assert abs(pi_pitch - rigid_pitch) < 0.5 * (rigid_pitch - spring_pitch)


def test_too_stiff_a_spring_is_refused_before_the_trial():
    with pytest.raises(ComplianceError, match="too stiff"):
        run_trial(75.0, 0.0, phase=0.5, cv=0.0, rng=1, duration_s=0.5, compliance=Compliance(1e4))


def test_a_set_refused_on_a_worker_is_one_line_of_bad_input(tmp_path, capsys):
    """The stability check runs on the worker that builds the world; its refusal reaches the user as the input
    error it is (exit 2, one line), not as an aborted sweep or a bug report."""
    from landscape.cli import main

    f = set_with_table(tmp_path, "compliance", "wing_stiffness_n_m_rad = 1000.0\n")
    args = ["sweep", "--theta-w", "74", "--theta-l", "30", "--cv", "0", "--trials", "1", "--duration", "0.5"]
    args += ["--model", str(f), "--db", str(tmp_path / "t.sqlite"), "--workers", "2", "--no-progress"]
    assert main(args) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "too stiff for the 1 ms servo period" in err[0]


@pytest.mark.parametrize("scale", [(), (1.0, 0.0), (1.0, float("nan")), (1.0, True), [1.0, 0.5]])
def test_bad_wing_scales_are_refused(scale):
    with pytest.raises(ComplianceError, match="wing_scale must be a list of numbers > 0"):
        Compliance(1.0, wing_scale=scale)


def test_wing_scale_needs_one_factor_per_wing_joint_and_its_stiffest_joint_decides_stability():
    comp = Compliance(6.0, 0.01, wing_scale=(1.0, 0.5, 1.0, 0.5))
    assert comp.joint_scales(4) == (1.0, 0.5, 1.0, 0.5)
    with pytest.raises(ComplianceError, match="wing_scale has 4 factors for the robot's 2 wing joints"):
        comp.joint_scales(2)
    check_stability(comp, 4.7e-5, 1e-3)  # 6 N m/rad is below the bound of 11.8
    with pytest.raises(ComplianceError, match="too stiff"):
        check_stability(Compliance(6.0, 0.01, wing_scale=(1.0, 2.5)), 4.7e-5, 1e-3)  # 15 is not


def test_model_set_wing_scale(tmp_path):
    base = "wing_stiffness_n_m_rad = 0.9\nwing_damping_n_m_s_rad = 0.005\n"
    plain = load_model_set(set_with_table(tmp_path, "compliance", base))
    scaled = load_model_set(set_with_table(tmp_path, "compliance", base + "wing_scale = [1, 0.6, 1, 0.6]\n"))
    assert scaled.compliance == Compliance(0.9, 0.005, wing_scale=(1.0, 0.6, 1.0, 0.6))
    assert scaled.model_set_hash != plain.model_set_hash and plain.compliance.wing_scale is None
    for bad in ("0.6", "[]", "[1, -0.6]", '["a"]'):
        with pytest.raises(ModelSetError, match="wing_scale"):
            load_model_set(set_with_table(tmp_path, "compliance", base + f"wing_scale = {bad}\n"))


def _hold_roll(comp) -> float:
    r = run_trial(75.0, 0.0, phase=0.5, cv=0.0, rng=1, duration_s=2.0, trace=True, compliance=comp)
    tr, s0 = r.trace, r.attempt_starts_s[0]
    m = (tr.t_s > s0 + 0.5) & (tr.t_s < s0 + 0.95)
    return float(np.median(tr.roll_deg[m]))


def test_a_softer_wing_on_one_side_leans_the_held_body_and_the_mirror_leans_it_back():
    """The wings alike hold the body level (leg still); one side's joints at 0.3 of the stiffness sag under the
    body more than the other's and roll the held body over to one side (a median roll of tens of degrees over
    the hold), the mirrored scale as far to the other."""
    level = _hold_roll(Compliance(0.9, 0.005))
    right = _hold_roll(Compliance(0.9, 0.005, wing_scale=(1.0, 0.3, 1.0, 0.3)))
    left = _hold_roll(Compliance(0.9, 0.005, wing_scale=(0.3, 1.0, 0.3, 1.0)))
    assert abs(level) < 0.5
    assert right > 10.0 and left < -10.0 and abs(right + left) < 1.0


def test_a_wing_scale_for_another_number_of_wing_joints_is_refused_before_the_trial():
    with pytest.raises(ComplianceError, match="wing_scale has 2 factors for the robot's 4 wing joints"):
        run_trial(
            75.0,
            0.0,
            phase=0.5,
            cv=0.0,
            rng=1,
            duration_s=0.5,
            compliance=Compliance(0.9, wing_scale=(1.0, 0.5)),
        )
