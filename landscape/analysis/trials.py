"""Analyses that join trials and landscapes (edge layer): self-righting probability, single-attempt phase maps,
phase-based prediction of multi-attempt outcomes, phase evolution, and barrier against outcome.

Every function takes trial rows as :meth:`sim.store.TrialStore.rows` returns them (dicts keyed by
``sim.store.COLUMNS``) and returns plain arrays, dicts or frozen dataclasses; the figures are in
:mod:`landscape.viz.analysis_plots` and the commands in :mod:`landscape.cli.analyze`.

Protocols in one database are told apart by their parameters:

- *multi-attempt* trials (``attempts == 0``): the robot keeps trying until it rights or ``duration_s`` ends;
- *single-attempt* trials (``attempts == 1``): one wing opening at ``t_1 = phi_1 Tl``, the trial ends ``Tw``
  later. Without noise their outcome against ``phi_1`` and ``theta_l`` is the phase map (the source paper's
  Fig. 7).

Prediction (the paper's Fig. 8): attempt k opens at ``t_k`` with phase ``phi_k = (t_k mod Tl) / Tl``. Without
noise ``phi_{k+1} = phi_k + Tw / Tl (mod 1)``; with noise the closed hold gets ``delta_k ~ N(0, (Cv Tl)^2)``.
The opening times are drawn by :func:`sim.actuation.attempt_starts_s` from the trial's own seed, so the
prediction sees the same noise as the simulation. The predicted attempt is the first whose phase is good in the
single-attempt map (nearest mapped phase on the circle, success in at least half the map's trials) and that
leaves time to right: ``t_k + d(phi_k) + hold <= duration``, where ``d`` is the map's mean time from opening
to upright and ``hold`` the outcome rule's 0.3 s.
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from fractions import Fraction

import numpy as np
from numpy.typing import NDArray
from scipy import stats

from landscape.grid import DEFAULT_STEP_DEG
from sim.actuation import PAPER_LEG_PERIOD_S, PAPER_WING_PERIOD_S, Actuation, attempt_phases, attempt_starts_s
from sim.trial import UPRIGHT_HOLD_S

Z95 = 1.959963984540054


def wilson_interval(k: int, n: int, z: float = Z95) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion ``k / n``.

    Examples
    --------
    >>> [round(x, 4) for x in wilson_interval(0, 40)]
    [0.0, 0.0876]
    >>> [round(x, 4) for x in wilson_interval(20, 40)]
    [0.352, 0.648]
    """
    if n <= 0:
        return math.nan, math.nan
    p = k / n
    c = (p + z * z / (2 * n)) / (1 + z * z / n)
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    lo, hi = (0.0 if k == 0 else max(0.0, c - h)), (1.0 if k == n else min(1.0, c + h))
    return min(lo, p), max(hi, p)  # the estimate lies inside, also under rounding


CONSISTENT_P = 0.05
"""A cell is *consistent* (two sets of trials, such as recorded and simulated, cannot tell the two success
probabilities apart) when Fisher's exact test gives p >= this."""


def fisher_p(k1: int, n1: int, k2: int, n2: int) -> float:
    """Two-sided p-value of Fisher's exact test of k1 of n1 against k2 of n2 successes (one shared probability).

    Unlike the Wilson rule (:func:`landscape.analysis.physical.validation.fractions_agree`), a perfect model passes it in at least 95 % of cells
    whatever the robot's probability; the Wilson rule needs a simulation that rights every trial to agree with
    a cell the robot righted 5 of 5 (``benchmarks/physical/referee_power.py``).

    Examples
    --------
    >>> round(fisher_p(5, 5, 17, 20), 3), round(fisher_p(0, 5, 10, 10), 4)
    (1.0, 0.0003)
    """
    from scipy.stats import fisher_exact

    return float(fisher_exact([[k1, n1 - k1], [k2, n2 - k2]]).pvalue)


def _ok(rows: Iterable[dict]) -> list[dict]:
    return [r for r in rows if r["status"] == "ok"]


def _mean(xs: Sequence[float]) -> float:
    return float(np.mean(xs)) if len(xs) else math.nan


# ---------------------------------------------------------------------------------------------- probability
@dataclass(frozen=True)
class ProbabilityCell:
    """Self-righting probability of one setting of multi-attempt trials.

    Attributes
    ----------
    theta_w_deg, theta_l_deg, cv, phase, wing_period_s, leg_period_s : float
        The setting (phase = phi_1).
    n, successes : int
    p, ci_low, ci_high : float
        Success fraction and its Wilson 95 % interval.
    mean_time_to_right_s : float
        Mean time to right over the successes, s (nan without successes).
    mean_attempt : float
        Mean succeeding attempt over the successes.
    roll_fraction : float
        Fraction of the successes that rolled (the rest somersaulted).
    """

    theta_w_deg: float
    theta_l_deg: float
    cv: float
    phase: float
    wing_period_s: float
    leg_period_s: float
    n: int
    successes: int
    p: float
    ci_low: float
    ci_high: float
    mean_time_to_right_s: float
    mean_attempt: float
    roll_fraction: float


def probability_table(rows: Iterable[dict]) -> list[ProbabilityCell]:
    """Success fraction with Wilson intervals per (theta_w, theta_l, Cv, phi_1, Tw, Tl) of multi-attempt trials.

    Examples
    --------
    >>> row = dict(status="ok", attempts=0, theta_w_deg=74.0, theta_l_deg=30.0, cv=0.1, phase=0.7,
    ...            wing_period_s=2.0, leg_period_s=0.8, success=True, time_to_right_s=2.5, attempt=2, mode="roll")
    >>> c = probability_table([row, {**row, "success": False, "time_to_right_s": None}])[0]
    >>> c.n, c.successes, c.p, c.mean_time_to_right_s
    (2, 1, 0.5, 2.5)
    """
    groups: dict[tuple, list[dict]] = defaultdict(list)
    for r in _ok(rows):
        if r["attempts"] == 0:
            groups[
                (
                    r["theta_w_deg"],
                    r["theta_l_deg"],
                    r["cv"],
                    r["phase"],
                    r["wing_period_s"],
                    r["leg_period_s"],
                )
            ].append(r)
    out = []
    for key in sorted(groups):
        g = groups[key]
        wins = [r for r in g if r["success"]]
        lo, hi = wilson_interval(len(wins), len(g))
        out.append(
            ProbabilityCell(
                *key,
                len(g),
                len(wins),
                len(wins) / len(g),
                lo,
                hi,
                _mean([r["time_to_right_s"] for r in wins]),
                _mean([r["attempt"] for r in wins]),
                _mean([r["mode"] == "roll" for r in wins]),
            )
        )
    return out


# ---------------------------------------------------------------------------------------------- phase map
@dataclass(frozen=True)
class PhaseMap:
    """Outcome of a single attempt against its phase and the leg amplitude, for one theta_w and Tl, no noise.

    Attributes
    ----------
    theta_w_deg, leg_period_s : float
    theta_l_deg : ndarray of shape (L,)
    phases : ndarray of shape (P,)
        phi_1 values in [0, 1), sorted.
    success : ndarray of shape (L, P)
        Success fraction (nan where no trial ran).
    delay_s : ndarray of shape (L, P)
        Mean time from the opening to becoming upright over the successes, s (nan without success).
    n : ndarray of shape (L, P) of int
    """

    theta_w_deg: float
    leg_period_s: float
    theta_l_deg: NDArray[np.float64]
    phases: NDArray[np.float64]
    success: NDArray[np.float64]
    delay_s: NDArray[np.float64]
    n: NDArray[np.int64]

    def lookup(self, theta_l_deg: float, phase: float) -> tuple[bool, float]:
        """(good, delay_s) at the nearest mapped phase on the circle; KeyError if theta_l is not mapped.

        A phase is good when the attempt succeeded in at least half the map's trials there.
        """
        i = np.flatnonzero(np.isclose(self.theta_l_deg, theta_l_deg, rtol=0.0, atol=1e-9))
        if not len(i):
            raise KeyError(f"theta_l {theta_l_deg:g} is not in the phase map of theta_w {self.theta_w_deg:g}")
        row = int(i[0])
        have = np.flatnonzero(self.n[row] > 0)
        d = np.abs((self.phases[have] - phase + 0.5) % 1.0 - 0.5)
        j = int(have[int(np.argmin(d))])
        good = bool(self.success[row, j] >= 0.5)
        return good, float(self.delay_s[row, j]) if good else math.nan

    def good_phases(self, theta_l_deg: float) -> NDArray[np.float64]:
        """Mapped phases where a single attempt succeeds (at least half the trials) at ``theta_l_deg``."""
        row = int(np.flatnonzero(np.isclose(self.theta_l_deg, theta_l_deg, rtol=0.0, atol=1e-9))[0])
        return self.phases[(self.n[row] > 0) & (self.success[row] >= 0.5)]


def phase_maps(rows: Iterable[dict]) -> dict[tuple[float, float], PhaseMap]:
    """Phase maps ``(theta_w, Tl) -> PhaseMap`` from the single-attempt trials (``attempts == 1``) without noise.

    Examples
    --------
    >>> row = dict(status="ok", attempts=1, cv=0.0, theta_w_deg=74.0, theta_l_deg=30.0, phase=0.25,
    ...            leg_period_s=0.8, success=True, time_to_right_s=0.9, attempt_starts_s=[0.2])
    >>> m = phase_maps([row, {**row, "phase": 0.5, "success": False, "attempt_starts_s": [0.4]}])[(74.0, 0.8)]
    >>> m.success.tolist(), m.lookup(30.0, 0.3), m.lookup(30.0, 0.45)[0]
    ([[1.0, 0.0]], (True, 0.7), False)
    """
    groups: dict[tuple[float, float], list[dict]] = defaultdict(list)
    for r in _ok(rows):
        if r["attempts"] == 1 and r["cv"] == 0.0:
            groups[(r["theta_w_deg"], r["leg_period_s"])].append(r)
    out = {}
    for key in sorted(groups):
        g = groups[key]
        tls = np.array(sorted({r["theta_l_deg"] for r in g}))
        phs = np.array(sorted({r["phase"] for r in g}))
        wins = np.zeros((len(tls), len(phs)))
        n = np.zeros((len(tls), len(phs)), dtype=np.int64)
        delay = np.zeros((len(tls), len(phs)))
        for r in g:
            i, j = int(np.searchsorted(tls, r["theta_l_deg"])), int(np.searchsorted(phs, r["phase"]))
            n[i, j] += 1
            if r["success"]:
                wins[i, j] += 1
                delay[i, j] += r["time_to_right_s"] - r["attempt_starts_s"][0]
        with np.errstate(invalid="ignore", divide="ignore"):
            out[key] = PhaseMap(
                key[0],
                key[1],
                tls,
                phs,
                np.where(n > 0, wins / n, np.nan),
                np.where(wins > 0, delay / np.maximum(wins, 1), np.nan),
                n,
            )
    return out


# ---------------------------------------------------------------------------------------------- prediction
def attempt_sequence(
    theta_w_deg: float,
    theta_l_deg: float,
    *,
    phase: float,
    cv: float,
    seed: int,
    duration_s: float,
    wing_period_s: float = PAPER_WING_PERIOD_S,
    leg_period_s: float = PAPER_LEG_PERIOD_S,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """Opening times (s) and phases of every attempt of a trial, drawn exactly as :func:`sim.trial.run_trial`
    draws them from the trial's seed.

    Examples
    --------
    >>> t, ph = attempt_sequence(74.0, 30.0, phase=0.7, cv=0.0, seed=1, duration_s=10.0)
    >>> t.round(3).tolist(), ph.round(3).tolist()
    ([0.56, 2.56, 4.56, 6.56, 8.56], [0.7, 0.2, 0.7, 0.2, 0.7])
    """
    act = Actuation(theta_w_deg, theta_l_deg, wing_period_s=wing_period_s, leg_period_s=leg_period_s)
    starts = attempt_starts_s(act, phase=phase, cv=cv, rng=np.random.default_rng(seed), duration_s=duration_s)
    return starts, attempt_phases(starts, act)


def predict_attempt(
    pm: PhaseMap,
    theta_l_deg: float,
    starts_s: NDArray[np.float64],
    phases: NDArray[np.float64],
    duration_s: float,
) -> int | None:
    """1-based attempt at which the robot is predicted to right first, or None (not within ``duration_s``)."""
    for k, (t, ph) in enumerate(zip(starts_s, phases, strict=True)):
        good, delay = pm.lookup(theta_l_deg, float(ph))
        if rights_in_time(good, t, delay, duration_s):
            return k + 1
    return None


def rights_in_time(good: bool, start_s: float, delay_s: float, duration_s: float) -> bool:
    """Whether an attempt opening at ``start_s`` that rights ``delay_s`` later (``good``) is upright for good
    (``UPRIGHT_HOLD_S`` more) before the trial ends at ``duration_s``: the predictors' rule for an attempt to
    count.

    >>> rights_in_time(True, 8.0, 1.5, 10.0), rights_in_time(True, 8.0, 1.8, 10.0)
    (True, False)
    """
    return bool(good) and start_s + delay_s + UPRIGHT_HOLD_S <= duration_s + 1e-9


def distinct_phases(wing_period_s: float, leg_period_s: float) -> int:
    """Number of distinct phases visited without noise, ``LCM(Tw, Tl) / Tw`` (periods rounded to 1 ms).

    Examples
    --------
    >>> distinct_phases(2.0, 0.8), distinct_phases(2.5, 0.6), distinct_phases(3.0, 1.0)
    (2, 6, 1)
    """
    ratio = Fraction(round(wing_period_s * 1000), round(leg_period_s * 1000))  # Tw / Tl in lowest terms
    return ratio.denominator


@dataclass(frozen=True)
class PredictedTrial:
    """A multi-attempt trial and its phase-based prediction."""

    theta_w_deg: float
    theta_l_deg: float
    cv: float
    phase: float
    wing_period_s: float
    leg_period_s: float
    seed: int
    simulated_attempt: int | None
    predicted_attempt: int | None

    @property
    def correct(self) -> bool:
        return self.simulated_attempt == self.predicted_attempt


def predict_trials(rows: Iterable[dict], maps: dict[tuple[float, float], PhaseMap]) -> list[PredictedTrial]:
    """Prediction of every multi-attempt trial whose (theta_w, Tl, theta_l) has a phase map."""
    out = []
    for r in _ok(rows):
        if r["attempts"] != 0:
            continue
        pm = maps.get((r["theta_w_deg"], r["leg_period_s"]))
        if pm is None or not np.isclose(pm.theta_l_deg, r["theta_l_deg"], rtol=0.0, atol=1e-9).any():
            continue
        starts, phs = attempt_sequence(
            r["theta_w_deg"],
            r["theta_l_deg"],
            phase=r["phase"],
            cv=r["cv"],
            seed=r["seed"],
            duration_s=r["duration_s"],
            wing_period_s=r["wing_period_s"],
            leg_period_s=r["leg_period_s"],
        )
        out.append(
            PredictedTrial(
                r["theta_w_deg"],
                r["theta_l_deg"],
                r["cv"],
                r["phase"],
                r["wing_period_s"],
                r["leg_period_s"],
                r["seed"],
                r["attempt"] if r["success"] else None,
                predict_attempt(pm, r["theta_l_deg"], starts, phs, r["duration_s"]),
            )
        )
    return out


@dataclass(frozen=True)
class AccuracyCell:
    """Prediction accuracy of one (theta_w, theta_l, Tw, Tl, Cv) over its trials (the phi_1 values)."""

    theta_w_deg: float
    theta_l_deg: float
    wing_period_s: float
    leg_period_s: float
    cv: float
    n: int
    correct: int
    accuracy: float
    simulated_p: float
    predicted_p: float
    ci_low: float
    ci_high: float


def prediction_accuracy(pred: Iterable[PredictedTrial]) -> list[AccuracyCell]:
    """Accuracy (same first righting attempt, or both failing) and simulated/predicted success fractions per
    (theta_w, theta_l, Tw, Tl, Cv); the Wilson interval is of the simulated fraction."""
    groups: dict[tuple, list[PredictedTrial]] = defaultdict(list)
    for p in pred:
        groups[(p.theta_w_deg, p.theta_l_deg, p.wing_period_s, p.leg_period_s, p.cv)].append(p)
    out = []
    for key in sorted(groups):
        g = groups[key]
        k = sum(p.correct for p in g)
        sim_wins = sum(p.simulated_attempt is not None for p in g)
        lo, hi = wilson_interval(sim_wins, len(g))
        out.append(
            AccuracyCell(
                *key,
                len(g),
                k,
                k / len(g),
                sim_wins / len(g),
                sum(p.predicted_attempt is not None for p in g) / len(g),
                lo,
                hi,
            )
        )
    return out


# ---------------------------------------------------------------------------------------------- barrier vs outcome
def spearman_bootstrap(
    x: Sequence[float], y: Sequence[float], *, n_boot: int = 2000, seed: int = 0
) -> tuple[float, float, float, float]:
    """Spearman's rho, its percentile bootstrap 95 % interval (resampling the points) and its p-value.

    Examples
    --------
    >>> rho, lo, hi, p = spearman_bootstrap([1, 2, 3, 4, 5, 6], [6, 5, 4, 3, 1, 2])
    >>> round(rho, 3), hi <= 0.0
    (-0.943, True)
    """
    x, y = np.asarray(x, dtype=np.float64), np.asarray(y, dtype=np.float64)
    if len(x) < 3 or np.ptp(x) == 0 or np.ptp(y) == 0:
        return math.nan, math.nan, math.nan, math.nan
    res = stats.spearmanr(x, y)
    rng = np.random.default_rng(seed)
    boots = []
    for _ in range(n_boot):
        i = rng.integers(0, len(x), len(x))
        if np.ptp(x[i]) > 0 and np.ptp(y[i]) > 0:
            boots.append(stats.spearmanr(x[i], y[i]).statistic)
    lo, hi = np.percentile(boots, [2.5, 97.5]) if boots else (math.nan, math.nan)
    return float(res.statistic), float(lo), float(hi), float(res.pvalue)


@dataclass(frozen=True)
class LogisticFit:
    """P(success) = 1 / (1 + exp(-(a + b E))) with E the barrier in mJ, fitted by maximum likelihood to the
    binomial counts.

    Attributes
    ----------
    a, b : float
        Intercept and slope (per mJ).
    e50_mj : float
        Barrier at P = 0.5, mJ (``-a / b``).
    converged : bool
    separated : bool
        True when the successes and failures are separated by the barrier (no finite maximum: the fit stops at a
        large slope and ``e50_mj`` is the boundary between them).
    """

    a: float
    b: float
    e50_mj: float
    converged: bool
    separated: bool

    def p(self, e_mj: NDArray[np.float64] | float) -> NDArray[np.float64]:
        return 1.0 / (1.0 + np.exp(-(self.a + self.b * np.asarray(e_mj, dtype=np.float64))))


RIDGE = 1e-4
"""Penalty on the standardised slope of :func:`logistic_fit` (keeps it finite under perfect separation)."""
LOGISTIC_GTOL = 1e-9
"""Convergence of :func:`logistic_fit`: gradient norm per trial."""
LOGISTIC_MAX_ITER = 200


def logistic_fit(e_mj: Sequence[float], k: Sequence[int], n: Sequence[int]) -> LogisticFit:
    """Maximum-likelihood logistic regression of success counts ``k`` of ``n`` on the barrier ``e_mj``.

    The barrier is standardised for the fit; a small ridge penalty (:data:`RIDGE`) on the standardised slope keeps
    it finite when the outcomes are perfectly separated by the barrier. Newton's method (IRLS) with the exact
    Hessian; ``converged`` means the gradient norm fell below :data:`LOGISTIC_GTOL` per trial.

    Examples
    --------
    >>> f = logistic_fit([1.0, 2.0, 3.0, 4.0], [38, 30, 10, 2], [40, 40, 40, 40])
    >>> round(f.e50_mj, 2), f.b < 0
    (2.5, True)
    """
    x, k, n = (np.asarray(v, dtype=np.float64) for v in (e_mj, k, n))
    xm, xs = float(x.mean()), float(x.std()) or 1.0
    z = np.stack([np.ones_like(x), (x - xm) / xs], axis=1)
    ridge = np.diag([0.0, 2.0 * RIDGE])
    theta = np.zeros(2)
    converged = False
    for _ in range(LOGISTIC_MAX_ITER):
        # Newton's method on the penalised negative log-likelihood (IRLS): exact gradient and Hessian, so
        # convergence is judged by the gradient norm, not by a line search's bookkeeping
        p = 0.5 * (1.0 + np.tanh(0.5 * (z @ theta)))
        grad = z.T @ (n * p - k) + ridge @ theta
        if np.linalg.norm(grad) <= LOGISTIC_GTOL * max(1.0, float(n.sum())):
            converged = True
            break
        hess = (z * (n * p * (1.0 - p))[:, None]).T @ z + ridge
        theta = theta - np.linalg.solve(hess, grad)
    a_z, b_z = theta
    b = b_z / xs
    a = a_z - b * xm
    lo_fail = x[k < n]
    hi_win = x[k > 0]
    separated = bool(
        len(lo_fail) and len(hi_win) and (hi_win.max() < lo_fail.min() or lo_fail.max() < hi_win.min())
    )
    return LogisticFit(float(a), float(b), float(-a / b) if b != 0 else math.nan, converged, separated)


def landscape_barriers(
    robot,
    pairs: Iterable[tuple[float, float]],
    *,
    step_deg: float = DEFAULT_STEP_DEG,
    progress: bool = False,
    wing_joints_deg: dict[float, dict[str, float] | None] | None = None,
) -> dict[tuple[float, float], tuple[float, float, object]]:
    """Minimal righting barrier (J) per (theta_w, theta_l): (exact, grid at ``step_deg``, the exact barrier's
    :class:`~landscape.gradient.BarrierGradient`), nan (None) where none.

    The start minimum comes from one shared continuation (:func:`landscape.computation.sweep_starts`), as in
    ``landscape barrier-map``. ``wing_joints_deg``: per theta_w, each wing joint at its own angle (a model set's
    plateaus, :meth:`sim.model_set.ModelSet.wing_joints_deg`; None for every joint at theta_w), as in
    ``landscape barrier-map --model``.
    """
    from landscape.computation import compute, sweep_starts

    pairs = sorted(set(pairs))
    if not pairs:
        return {}
    joints_of = wing_joints_deg or {}
    shared = [(w, x) for w, x in pairs if not joints_of.get(w)]  # the others find their starts in compute
    starts = (
        sweep_starts(robot, sorted({w for w, _ in shared}), sorted({x for _, x in shared})) if shared else {}
    )
    out = {}
    it = pairs
    if progress:
        import sys

        from tqdm import tqdm

        it = tqdm(pairs, desc="barriers", unit="pose", file=sys.stderr, disable=None)
    for w, leg in it:
        vals, gradient = [], None
        joints = joints_of.get(w)
        for method in ("exact", "grid"):
            c = compute(
                robot,
                theta_w_deg=w,
                theta_l_deg=leg,
                step_deg=step_deg,
                start_deg=starts.get((w, leg)),
                method=method,
                wing_joints_deg=joints,
                gradients=method == "exact",
            )
            vals.append(math.nan if c.barrier.righting is None else c.barrier.righting.barrier_j)
            gradient = c.gradient.get("righting") if method == "exact" else gradient
        out[(w, leg)] = (vals[0], vals[1], gradient)
    return out


@dataclass(frozen=True)
class BarrierOutcome:
    """Barrier against outcome for one Cv over the (theta_w, theta_l) settings.

    Attributes
    ----------
    cv : float
    cells : list of ProbabilityCell
    exact_mj, grid_mj : ndarray of shape (N,)
        Exact and grid righting barriers of each cell, mJ.
    rho, rho_low, rho_high, rho_p : float
        Spearman's rho between exact barrier and success fraction, bootstrap 95 % interval, p-value.
    rho_time, rho_time_low, rho_time_high, rho_time_p : float
        The same between exact barrier and mean time to right (cells with successes).
    rho_grid : float
        Spearman's rho between grid barrier and success fraction.
    fit : LogisticFit
        P(success) on the exact barrier.
    """

    cv: float
    cells: list[ProbabilityCell]
    exact_mj: NDArray[np.float64]
    grid_mj: NDArray[np.float64]
    rho: float
    rho_low: float
    rho_high: float
    rho_p: float
    rho_time: float
    rho_time_low: float
    rho_time_high: float
    rho_time_p: float
    rho_grid: float
    fit: LogisticFit


def barrier_outcome(
    cells: Sequence[ProbabilityCell],
    barriers: dict[tuple[float, float], tuple[float, float]],
    *,
    n_boot: int = 2000,
) -> list[BarrierOutcome]:
    """Spearman correlations and logistic fits of outcome on barrier, one per Cv (cells must share Tw, Tl, phi_1)."""
    by_cv: dict[float, list[ProbabilityCell]] = defaultdict(list)
    for c in cells:
        if (c.theta_w_deg, c.theta_l_deg) in barriers:
            by_cv[c.cv].append(c)
    out = []
    for cv in sorted(by_cv):
        cs = by_cv[cv]
        ex = np.array([barriers[(c.theta_w_deg, c.theta_l_deg)][0] for c in cs]) * 1e3
        gr = np.array([barriers[(c.theta_w_deg, c.theta_l_deg)][1] for c in cs]) * 1e3
        p = np.array([c.p for c in cs])
        ok = np.isfinite(ex)
        rho = spearman_bootstrap(ex[ok], p[ok], n_boot=n_boot)
        t = np.array([c.mean_time_to_right_s for c in cs])
        okt = ok & np.isfinite(t)
        rho_t = spearman_bootstrap(ex[okt], t[okt], n_boot=n_boot)
        okg = np.isfinite(gr)
        rho_g = spearman_bootstrap(gr[okg], p[okg], n_boot=0)[0] if okg.sum() >= 3 else math.nan
        fit = logistic_fit(
            ex[ok],
            [c.successes for c, o in zip(cs, ok, strict=True) if o],
            [c.n for c, o in zip(cs, ok, strict=True) if o],
        )
        out.append(BarrierOutcome(cv, cs, ex, gr, *rho, *rho_t, rho_g, fit))
    return out
