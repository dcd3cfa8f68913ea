import numpy as np
import pytest

from sim.actuation import Actuation, attempt_phases, attempt_starts_s, leg_profile_deg, wing_profile_deg


@pytest.mark.parametrize("theta_w", [70.0, 76.0, 90.0])
def test_wing_profile_closed_form(theta_w):
    act = Actuation(theta_w, 30.0)
    t1 = 0.56
    t_open, t_close0, t_closed = theta_w / 300.0, 1.05, 1.05 + theta_w / 250.0
    t = t1 + np.array(
        [-0.01, 0.0, t_open / 2, t_open, t_open + 0.1, t_close0, (t_close0 + t_closed) / 2, t_closed, 1.99]
    )
    a, w = wing_profile_deg(t, [t1], act)
    assert a == pytest.approx([0, 0, theta_w / 2, theta_w, theta_w, theta_w, theta_w / 2, 0, 0], abs=1e-9)
    assert w[[2, 6]].tolist() == [300.0, -250.0]
    assert act.wing_closed_s == pytest.approx(t_closed)
    assert act.wing_hold_s == pytest.approx(2.0 - t_closed)


def test_wing_speed_is_derivative():
    act = Actuation(74.0, 40.0)
    t = np.linspace(0.0, 6.0, 60001)
    starts = [0.3, 2.3, 4.1]
    a, w = wing_profile_deg(t, starts, act)
    mid = 0.5 * (w[1:] + w[:-1])
    assert np.abs(np.diff(a) / np.diff(t) - mid).max() < 300.0  # only at the kinks
    smooth = np.abs(np.diff(a) / np.diff(t) - mid) < 1e-6
    assert smooth.mean() > 0.999


def test_leg_profile_closed_form():
    act = Actuation(74.0, 40.0)
    rate = 2 * 40.0 / 0.15
    t = np.array([0.0, 0.075, 0.2, 0.325, 0.4, 0.475, 0.6, 0.725, 0.8, 0.8 + 0.0375])
    a, w = leg_profile_deg(t, act)
    assert a == pytest.approx([0, 40, 40, 40, 0, -40, -40, -40, 0, 20], abs=1e-9)
    a, w = leg_profile_deg([0.01, 0.2, 0.41, 0.6, 0.79], act)
    assert w.tolist() == pytest.approx([rate, 0.0, -rate, 0.0, rate])
    # periodic with Tl, odd about Tl/2
    tt = np.linspace(0, 0.8, 101)
    assert leg_profile_deg(tt + 0.8 * 7, act)[0] == pytest.approx(leg_profile_deg(tt, act)[0], abs=1e-9)
    assert leg_profile_deg(tt + 0.4, act)[0] == pytest.approx(-leg_profile_deg(tt, act)[0], abs=1e-9)


def test_attempt_starts_without_noise_repeat_every_tw():
    act = Actuation(76.0, 30.0)
    s = attempt_starts_s(act, phase=0.7, cv=0.0, rng=np.random.default_rng(0), duration_s=10.0)
    assert s == pytest.approx([0.56, 2.56, 4.56, 6.56, 8.56])
    assert attempt_phases(s, act) == pytest.approx([0.7, 0.2, 0.7, 0.2, 0.7])


def test_attempt_starts_noise_is_gaussian_hold():
    act = Actuation(76.0, 30.0)
    cv = 0.1
    s = attempt_starts_s(act, phase=0.0, cv=cv, rng=np.random.default_rng(3), duration_s=20000.0)
    gaps = np.diff(s) - act.wing_period_s
    ref = np.random.default_rng(3).normal(0.0, cv * 0.8, size=len(gaps))
    assert gaps == pytest.approx(ref, abs=1e-9)  # one deviate per hold, in order (no clipping at this Cv)
    assert gaps.std() == pytest.approx(0.08, rel=0.05)


def test_negative_hold_is_clipped_at_zero():
    act = Actuation(76.0, 30.0)
    s = attempt_starts_s(act, phase=0.0, cv=2.0, rng=np.random.default_rng(5), duration_s=2000.0)
    gaps = np.diff(s)
    assert gaps.min() == pytest.approx(act.wing_closed_s)  # the wings reopen the moment they are closed
    assert (gaps >= act.wing_closed_s - 1e-12).all()
    a, _ = wing_profile_deg(s[1:] - 1e-9, s, act)
    assert np.abs(a).max() < 1e-6  # closed before every opening


def test_same_seed_extends_same_sequence():
    act = Actuation(74.0, 30.0)
    short = attempt_starts_s(act, phase=0.3, cv=0.2, rng=np.random.default_rng(9), duration_s=6.0)
    long = attempt_starts_s(act, phase=0.3, cv=0.2, rng=np.random.default_rng(9), duration_s=20.0)
    assert long[: len(short)] == pytest.approx(short)


@pytest.mark.parametrize(
    "kw, match",
    [
        (dict(theta_w_deg=-1.0, theta_l_deg=30.0), "theta_w_deg"),
        (dict(theta_w_deg=70.0, theta_l_deg=float("nan")), "theta_l_deg"),
        (dict(theta_w_deg=70.0, theta_l_deg=30.0, leg_cross_s=0.5), "half the leg period"),
        (dict(theta_w_deg=70.0, theta_l_deg=30.0, wing_period_s=1.0), "longer than wing_period_s"),
    ],
)
def test_bad_actuation(kw, match):
    with pytest.raises(ValueError, match=match):
        Actuation(**kw)
