"""Analyses of trial rows (landscape/analysis.py) against closed forms and synthetic data."""

import math

import numpy as np
import pytest
from scipy import stats

from landscape.analysis import trials as an


def _row(**kw):
    base = dict(
        status="ok",
        attempts=0,
        theta_w_deg=74.0,
        theta_l_deg=30.0,
        cv=0.0,
        phase=0.7,
        wing_period_s=2.0,
        leg_period_s=0.8,
        duration_s=10.0,
        seed=1,
        success=False,
        time_to_right_s=None,
        attempt=None,
        mode=None,
        attempt_starts_s=[],
        robot_hash="h",
    )
    base.update(kw)
    return base


@pytest.mark.parametrize("k,n", [(0, 40), (1, 40), (20, 40), (39, 40), (40, 40), (3, 7)])
def test_wilson_interval_bounds_are_the_roots_of_the_score_equation(k, n):
    """The Wilson bounds are the two roots q of (p - q)^2 = z^2 q (1 - q) / n (p = k/n): each bound is checked
    against that equation, not against the closed form the code evaluates, and no clamping is assumed."""
    lo, hi = an.wilson_interval(k, n)
    z = stats.norm.ppf(0.975)
    p = k / n
    # the quadratic (1 + z^2/n) q^2 - (2p + z^2/n) q + p^2 = 0 has roots q1 + q2 = (2p + z^2/n) / (1 + z^2/n)
    # and q1 q2 = p^2 / (1 + z^2/n); both lie in [0, 1]
    assert lo < hi
    for q in (lo, hi):
        assert (p - q) ** 2 == pytest.approx(z**2 * q * (1 - q) / n, abs=1e-12)
    assert lo + hi == pytest.approx((2 * p + z**2 / n) / (1 + z**2 / n), abs=1e-12)
    assert lo * hi == pytest.approx(p**2 / (1 + z**2 / n), abs=1e-12)


def test_wilson_interval_known_values():
    """0 of 40 and 40 of 40 (z = 1.959964): the far bound is z^2 / (n + z^2) from the edge, 0.08762."""
    z2 = stats.norm.ppf(0.975) ** 2
    assert an.wilson_interval(0, 40) == pytest.approx((0.0, z2 / (40 + z2)), abs=1e-12)
    assert an.wilson_interval(40, 40) == pytest.approx((40 / (40 + z2), 1.0), abs=1e-12)
    assert z2 / (40 + z2) == pytest.approx(0.08762, abs=1e-5)


def test_probability_table_groups_by_setting_and_ignores_other_protocols_and_divergence():
    rows = [
        _row(success=True, time_to_right_s=1.0, attempt=1, mode="roll"),
        _row(success=True, time_to_right_s=3.0, attempt=2, mode="somersault"),
        _row(),
        _row(status="diverged", success=None),
        _row(attempts=1, success=True, time_to_right_s=1.0),  # single attempt: not a multi-attempt trial
        _row(cv=0.1, success=True, time_to_right_s=2.0, attempt=1, mode="roll"),
    ]
    cells = an.probability_table(rows)
    assert [(c.cv, c.n, c.successes) for c in cells] == [(0.0, 3, 2), (0.1, 1, 1)]
    c = cells[0]
    assert c.p == pytest.approx(2 / 3) and c.mean_time_to_right_s == 2.0 and c.mean_attempt == 1.5
    assert c.roll_fraction == 0.5 and (c.ci_low, c.ci_high) == an.wilson_interval(2, 3)


def _map(good: set[float], *, delay=0.8, theta_w=74.0, tl_s=0.8):
    rows = [
        _row(
            attempts=1,
            theta_w_deg=theta_w,
            leg_period_s=tl_s,
            phase=ph,
            success=ph in good,
            time_to_right_s=(ph * tl_s + delay) if ph in good else None,
            attempt_starts_s=[ph * tl_s],
        )
        for ph in np.round(np.arange(0, 1, 0.05), 2)
    ]
    return an.phase_maps(rows)[(theta_w, tl_s)]


def test_phase_map_lookup_uses_the_nearest_phase_on_the_circle():
    pm = _map({0.0, 0.2})
    assert pm.lookup(30.0, 0.98)[0] and pm.lookup(30.0, 0.21) == (True, pytest.approx(0.8))
    assert not pm.lookup(30.0, 0.5)[0]
    assert pm.good_phases(30.0).tolist() == [0.0, 0.2]
    with pytest.raises(KeyError, match="theta_l 40"):
        pm.lookup(40.0, 0.1)


def test_prediction_without_noise_follows_the_phase_advance_tw_over_tl():
    pm = _map({0.2})  # only phase 0.2 rights; Tw/Tl = 2.5 makes phases alternate 0.7, 0.2, 0.7, ...
    starts, phases = an.attempt_sequence(74.0, 30.0, phase=0.7, cv=0.0, seed=0, duration_s=10.0)
    assert phases.round(9).tolist() == [0.7, 0.2, 0.7, 0.2, 0.7]
    assert an.predict_attempt(pm, 30.0, starts, phases, 10.0) == 2
    # an attempt that cannot finish righting before the end does not count
    assert an.predict_attempt(pm, 30.0, starts, phases, starts[1] + 0.8 + an.UPRIGHT_HOLD_S - 0.01) is None
    assert an.predict_attempt(_map({0.45}), 30.0, starts, phases, 10.0) is None  # never visits 0.45


def test_predict_trials_scores_agreement_per_setting():
    maps = {(74.0, 0.8): _map({0.2})}
    rows = [
        _row(phase=0.7, success=True, attempt=2, time_to_right_s=3.0),  # predicted 2: correct
        _row(phase=0.2, success=True, attempt=2, time_to_right_s=3.0),  # predicted 1: wrong
        _row(phase=0.45, success=False),
    ]  # never visits a good phase: predicted None, correct
    pred = an.predict_trials(rows, maps)
    assert [p.predicted_attempt for p in pred] == [2, 1, None]
    acc = an.prediction_accuracy(pred)
    assert len(acc) == 1 and acc[0].correct == 2 and acc[0].n == 3
    assert acc[0].simulated_p == pytest.approx(2 / 3) and acc[0].predicted_p == pytest.approx(2 / 3)


@pytest.mark.parametrize(
    "tw,tl,n", [(2.0, 0.8, 2), (2.0, 0.6, 3), (2.5, 1.2, 12), (3.0, 1.0, 1), (2.5, 1.4, 14)]
)
def test_distinct_phases_is_lcm_over_tw(tw, tl, n):
    assert an.distinct_phases(tw, tl) == n
    starts = np.arange(4 * n) * tw
    assert len(set(np.round((starts % tl) / tl, 6) % 1.0)) == n


def test_attempt_sequence_is_the_simulations_own():
    pytest.importorskip("pybullet")
    from sim.actuation import Actuation
    from sim.trial import run_trial

    act = Actuation(74.0, 20.0, wing_period_s=2.5, leg_period_s=1.0)
    r = run_trial(74.0, 20.0, phase=0.35, cv=0.25, rng=11, duration_s=6.0, dt_s=1e-3, actuation=act)
    starts, phases = an.attempt_sequence(
        74.0, 20.0, phase=0.35, cv=0.25, seed=11, duration_s=6.0, wing_period_s=2.5, leg_period_s=1.0
    )
    n = len(r.attempt_starts_s)
    assert n >= 2 and np.allclose(starts[:n], r.attempt_starts_s) and np.allclose(phases[:n], r.phases)


def test_upright_hold_is_the_time_the_simulation_needs_after_righting():
    """predict_attempt counts an attempt only if righting plus the upright hold fits in the trial. Check that rule
    against the simulation itself: a trial that ends just before time_to_right_s + UPRIGHT_HOLD_S is not a success,
    one that ends just after is (built-in robot, a setting that rights on its first attempt)."""
    pytest.importorskip("pybullet")
    from sim.trial import run_trial

    kw = dict(phase=0.7, cv=0.0, rng=1, dt_s=1e-3)
    done = run_trial(80.0, 50.0, duration_s=4.0, **kw)
    assert done.success and done.attempt == 1
    t_right = done.time_to_right_s
    assert not run_trial(80.0, 50.0, duration_s=t_right + an.UPRIGHT_HOLD_S - 0.02, **kw).success
    assert run_trial(80.0, 50.0, duration_s=t_right + an.UPRIGHT_HOLD_S + 0.02, **kw).success


def test_spearman_bootstrap():
    x = np.arange(12.0)
    rho, lo, hi, p = an.spearman_bootstrap(x, x**3)
    assert (rho, lo, hi) == pytest.approx((1.0, 1.0, 1.0)) and p < 1e-6
    rng = np.random.default_rng(0)
    a, b = rng.normal(size=60), rng.normal(size=60)
    rho, lo, hi, _ = an.spearman_bootstrap(a, b)
    assert lo < rho < hi and lo < 0 < hi
    assert rho == pytest.approx(stats.spearmanr(a, b).statistic)
    assert math.isnan(an.spearman_bootstrap([1, 2], [3, 4])[0])


def test_logistic_fit_recovers_known_parameters():
    rng = np.random.default_rng(1)
    e = np.repeat(np.linspace(0.0, 8.0, 9), 1)
    n = np.full(len(e), 4000)
    true = 1 / (1 + np.exp(-(3.0 - 1.0 * e)))
    k = rng.binomial(n, true)
    f = an.logistic_fit(e, k, n)
    assert f.converged and not f.separated
    assert f.a == pytest.approx(3.0, abs=0.1) and f.b == pytest.approx(-1.0, abs=0.03)
    assert f.e50_mj == pytest.approx(3.0, abs=0.05)
    sep = an.logistic_fit([1.0, 2.0, 3.0, 4.0], [10, 10, 0, 0], [10, 10, 10, 10])
    assert sep.separated and 2.0 < sep.e50_mj < 3.0 and np.isfinite(sep.b)


def test_barrier_outcome_correlates_per_cv():
    cells = []
    barriers = {}
    for i, (w, leg) in enumerate([(70, 20), (70, 30), (72, 20), (72, 30), (74, 20), (74, 30)]):
        barriers[(float(w), float(leg))] = (1e-3 * (6 - i), 1e-3 * (6.5 - i))
        for cv in (0.0, 0.1):
            k = min(40, 6 * i + (2 if cv else 0))
            lo, hi = an.wilson_interval(k, 40)
            cells.append(
                an.ProbabilityCell(
                    float(w), float(leg), cv, 0.7, 2.0, 0.8, 40, k, k / 40, lo, hi, 5.0 - 0.5 * i, 1.0, 1.0
                )
            )
    res = an.barrier_outcome(cells, barriers, n_boot=200)
    assert [r.cv for r in res] == [0.0, 0.1]
    for r in res:
        assert r.rho == pytest.approx(-1.0) and r.rho_grid == pytest.approx(-1.0)
        assert r.rho_time == pytest.approx(1.0)
        assert r.fit.b < 0 and np.allclose(r.exact_mj, [6, 5, 4, 3, 2, 1])


def test_logistic_fit_solves_the_score_equations():
    """At the maximum the score equations hold: sum(n p - k) = 0 and sum((n p - k) E) = 0 (up to the tiny ridge),
    checked independently of the fitting method; and `converged` reports it (BFGS flagged 'precision loss' here
    with newer scipy although the estimates were right)."""
    rng = np.random.default_rng(7)
    e = np.linspace(2.0, 9.0, 8)
    n = np.full(len(e), 40)
    k = rng.binomial(n, 1 / (1 + np.exp(-(6.0 - 1.1 * e))))
    f = an.logistic_fit(e, k, n)
    p = f.p(e)
    assert f.converged
    assert abs(np.sum(n * p - k)) < 1e-6
    ridge_term = (
        2 * an.RIDGE * f.b * e.std() ** 2
    )  # d/db of the penalty on the standardised slope, per unit E
    assert abs(np.sum((n * p - k) * e) + ridge_term) < 1e-5


def test_landscape_barriers_pose_each_wing_joint_as_given():
    """With a model set's wing joints the barrier is compute's with those joints; without, the plain one."""
    from geometry.robots import load_robot
    from landscape.computation import compute
    from sim.model_set import load_model_set

    robot = load_robot(None)
    joints = load_model_set("physical").wing_joints_deg(robot.joint_map.wing, 75.0)
    got = an.landscape_barriers(robot, [(75.0, 30.0)], wing_joints_deg={75.0: joints})
    want = compute(robot, theta_w_deg=75.0, theta_l_deg=30.0, wing_joints_deg=joints)
    assert got[(75.0, 30.0)][0] == pytest.approx(want.barrier.righting.barrier_j, abs=1e-12)
    plain = an.landscape_barriers(robot, [(75.0, 30.0)])
    assert plain[(75.0, 30.0)][0] == pytest.approx(
        compute(robot, theta_w_deg=75.0, theta_l_deg=30.0).barrier.righting.barrier_j, abs=1e-12
    )
    assert plain[(75.0, 30.0)][0] != pytest.approx(got[(75.0, 30.0)][0], abs=1e-9)
    g = got[(75.0, 30.0)][2]  # the exact barrier's gradient, as compute's
    assert g.com_j_per_m.tolist() == want.gradient["righting"].com_j_per_m.tolist()
