"""Predicting the first righting attempt of multi-attempt trials (the source paper's Fig. 8), from the phase alone
and from the phase and the state each attempt starts from (edge layer: joins trials, traces and the phase map).

Three predictors of the same thing, the first attempt that rights (or none):

- **phase map** (the paper's, :func:`landscape.analysis.trials.predict_trials`, kept as it is): attempt k rights
  when its phase is good in the single-attempt map, built from attempts that start from rest.
- **from rest at each opening**: attempt k rights when a single attempt from rest (the robot still on its back,
  the leg starting at t = 0) at attempt k's own phase and the robot's own heading on the ground when attempt k
  opens rights; the phase map evaluated exactly where each attempt falls rather than at the nearest of its
  grid's phases, with the heading besides. The heading matters only because pybullet's friction directions are
  fixed in the world (:mod:`sim.world`; with ``[contact] friction_axes = "body"`` it is always 0): turning a
  trial by 90 degrees never changes it, by 5 degrees it changes a quarter of the single attempts
  (``benchmarks/studies/heading.py``), and a failed attempt leaves the robot turned by 15 degrees (median).
- **state**: an online nearest-neighbour predictor. At each opening it knows the body's state then, as a trace
  records it (:func:`opening_states`: roll and pitch, the body's angular velocity and the rotational kinetic
  energy about the CoM, besides the phase and the phase map's verdict), and predicts whether this attempt rights
  by its ``K_NEIGHBOURS`` nearest attempts (features standardised on the attempts it is fitted on, majority vote)
  among the attempts of the trials it was fitted on and the single-attempt trials from rest; the predicted first
  righting attempt is the first predicted to right.

Scoring is held out. The phase map and the single attempts from rest are simulations of their own, never
scored; the second predictor takes from a scored trial only what it knows when an attempt opens (its phase and
heading), never an outcome. The state
predictor (:func:`held_out_state_predictions`) is fitted per (Tw, Tl) setting on the other settings' trials only,
so no scored trial (nor any attempt of it) is in the data its predictor was fitted on.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Sequence
from dataclasses import asdict, dataclass

import numpy as np
from numpy.typing import NDArray

from landscape.analysis.trials import PhaseMap, rights_in_time, wilson_interval

K_NEIGHBOURS = 5
"""Attempts the state predictor's vote takes."""
FROM_REST_ROUND = (9, 6)
"""Decimals a single attempt from rest is keyed by: its phase and its heading (degrees); attempts that open
closer than that share one run."""
FEATURES = ("cos_phase", "sin_phase", "map_good", "roll_deg", "pitch_deg", "omega_x", "omega_y", "ke_rot_mj")
"""What the state predictor knows of an attempt at its opening."""


@dataclass(frozen=True)
class OpeningState:
    """The body's state when an attempt opens, and the attempt's outcome.

    Attributes
    ----------
    key : str
        The trial it belongs to (its setting and seed).
    wing_period_s, leg_period_s : float
        The trial's Tw and Tl, s.
    attempt : int
        1-based.
    phase : float
        The leg's phase at the opening, a fraction of Tl.
    roll_deg, pitch_deg : float
        Body roll and pitch at the last trace sample before the opening, degrees.
    omega_x, omega_y, omega_z : float
        The body's angular velocity then (body frame), rad/s.
    ke_rot_mj : float
        Rotational kinetic energy about the CoM then, mJ.
    success : bool
        The attempt righted the body.
    heading_deg : float
        The robot's heading on the ground then (:attr:`sim.trial.Trace.heading_deg`), degrees.
    start_s : float
        When the attempt opened, s from the start of actuation.
    """

    key: str
    wing_period_s: float
    leg_period_s: float
    attempt: int
    phase: float
    roll_deg: float
    pitch_deg: float
    omega_x: float
    omega_y: float
    omega_z: float
    ke_rot_mj: float
    success: bool
    heading_deg: float = 0.0
    start_s: float = math.nan

    def as_dict(self) -> dict:
        return asdict(self)


def trial_key(row: dict) -> str:
    """A stable name of a stored trial: its setting, model set and seed.

    Examples
    --------
    >>> trial_key(dict(theta_w_deg=72.0, theta_l_deg=30.0, wing_period_s=2.0, leg_period_s=0.8, phase=0.25,
    ...                cv=0.0, duration_s=10.0, dt_s=5e-4, seed=7, model_set="paper", robot_hash="ab"))
    'ab/paper/72/30/Tw2/Tl0.8/phi0.25/cv0/10s/dt0.0005/seed7'
    """
    return (
        f"{row['robot_hash']}/{row.get('model_set') or 'paper'}/{row['theta_w_deg']:g}/{row['theta_l_deg']:g}/"
        f"Tw{row['wing_period_s']:g}/Tl{row['leg_period_s']:g}/phi{row['phase']:g}/cv{row['cv']:g}/"
        f"{row['duration_s']:g}s/dt{row['dt_s']:g}/seed{row['seed']}"
    )


def opening_states(result, key: str, *, inertia_kg_m2: NDArray[np.float64]) -> list[OpeningState]:
    """The :class:`OpeningState` of every attempt of a trial run with a trace (:class:`sim.trial.TrialResult`)
    up to the one that righted; ``inertia_kg_m2`` (3, 3): the body's inertia about its CoM with the wings closed,
    body frame."""
    from landscape.analysis.energy import rotational_shares_j

    tr = result.trace
    out = []
    for k, (t0, ph) in enumerate(zip(result.attempt_starts_s, result.phases, strict=True)):
        i = int(np.searchsorted(tr.t_s, t0, side="right")) - 1
        if i < 0:
            i = 0
        w = tr.omega_body_rad_s[i]
        success = bool(result.success and result.attempt == k + 1)
        out.append(
            OpeningState(
                key,
                0.0,
                0.0,
                k + 1,
                float(ph),
                float(tr.roll_deg[i]),
                float(tr.pitch_deg[i]),
                float(w[0]),
                float(w[1]),
                float(w[2]),
                float(rotational_shares_j(w, inertia_kg_m2).sum()) * 1e3,
                success,
                float(tr.heading_deg[i]),
                float(t0),
            )
        )
        if success:
            break
    return out


def _features(states: Sequence[OpeningState], maps: dict[float, PhaseMap], theta_l_deg: float) -> NDArray:
    rows = []
    for s in states:
        pm = maps.get(s.leg_period_s)
        good = float(pm.lookup(theta_l_deg, s.phase)[0]) if pm is not None else 0.5
        a = 2.0 * math.pi * s.phase
        rows.append(
            [math.cos(a), math.sin(a), good, s.roll_deg, s.pitch_deg, s.omega_x, s.omega_y, s.ke_rot_mj]
        )
    return np.asarray(rows, dtype=np.float64).reshape(-1, len(FEATURES))


@dataclass(frozen=True)
class StatePredictor:
    """The state predictor fitted on attempts (module docstring).

    Attributes
    ----------
    x : ndarray of shape (n, F)
        The fitted attempts' standardised features (:data:`FEATURES`).
    y : ndarray of shape (n,) of bool
        Their outcomes.
    mean, scale : ndarray of shape (F,)
        The standardisation.
    maps : dict of float to PhaseMap
        Single-attempt phase maps by Tl.
    theta_l_deg : float
    k : int
    """

    x: NDArray[np.float64]
    y: NDArray[np.bool_]
    mean: NDArray[np.float64]
    scale: NDArray[np.float64]
    maps: dict
    theta_l_deg: float
    k: int = K_NEIGHBOURS

    def rights(self, states: Sequence[OpeningState]) -> NDArray[np.bool_]:
        """Whether each attempt is predicted to right (majority of its ``k`` nearest fitted attempts)."""
        f = (_features(states, self.maps, self.theta_l_deg) - self.mean) / self.scale
        d = ((f[:, None, :] - self.x[None, :, :]) ** 2).sum(axis=2)
        near = np.argsort(d, axis=1, kind="stable")[:, : self.k]
        return self.y[near].mean(axis=1) > 0.5


def fit_state_predictor(
    states: Sequence[OpeningState], maps: dict[float, PhaseMap], theta_l_deg: float, *, k: int = K_NEIGHBOURS
) -> StatePredictor:
    """Fit the state predictor on attempts (``states``) with the phase maps by Tl (``maps``).

    Raises
    ------
    ValueError
        If ``states`` is empty.
    """
    if not states:
        raise ValueError("the state predictor needs attempts to be fitted on; got none")
    f = _features(states, maps, theta_l_deg)
    mean = f.mean(axis=0)
    scale = f.std(axis=0)
    scale = np.where(scale > 0, scale, 1.0)
    y = np.array([s.success for s in states], dtype=bool)
    return StatePredictor((f - mean) / scale, y, mean, scale, maps, float(theta_l_deg), int(k))


def first_predicted(predictor: StatePredictor, states: Sequence[OpeningState]) -> int | None:
    """The first attempt the predictor says rights, among a trial's attempts in order; None if none does.

    A trial's recorded attempts end with the one that righted, so a trial predicted to go on past it is
    predicted wrong whatever comes later."""
    if not states:
        return None
    good = predictor.rights(states)
    hit = np.flatnonzero(good)
    return int(states[hit[0]].attempt) if len(hit) else None


def map_states(rows: Iterable[dict], theta_w_deg: float, theta_l_deg: float) -> list[OpeningState]:
    """The single-attempt trials at (theta_w, theta_l), no noise, as attempts from rest (the state the map
    assumes: still, at the rest orientation; roll, pitch and rates 0)."""
    out = []
    for r in rows:
        if (
            r["status"] == "ok"
            and r["attempts"] == 1
            and r["cv"] == 0.0
            and (r["theta_w_deg"], r["theta_l_deg"]) == (theta_w_deg, theta_l_deg)
        ):
            out.append(
                OpeningState(
                    f"map/{r['leg_period_s']:g}/{r['phase']:g}",
                    float(r["wing_period_s"]),
                    float(r["leg_period_s"]),
                    1,
                    float(r["phase"]),
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    0.0,
                    bool(r["success"]),
                )
            )
    return out


def from_rest_key(state: OpeningState) -> tuple[float, float]:
    """The (phase, heading) of the single attempt from rest that stands for an attempt (:data:`FROM_REST_ROUND`)."""
    phase = round(state.phase % 1.0, FROM_REST_ROUND[0]) % 1.0
    return phase, round(state.heading_deg, FROM_REST_ROUND[1]) + 0.0  # + 0.0: never -0.0


def first_predicted_from_rest(
    states: Sequence[OpeningState],
    from_rest: Callable[[OpeningState], tuple[bool, float]],
    duration_s: float,
) -> int | None:
    """The first of a trial's attempts (in order) whose single attempt from rest rights in time to be upright
    for good before ``duration_s`` (the phase map's rule, :func:`landscape.analysis.trials.predict_attempt`);
    None if none does. ``from_rest(state)`` gives (rights, time from the opening to upright, s) and is called in
    order only until one rights in time, so a caller that runs the attempts runs no more than needed.

    Examples
    --------
    >>> st = [OpeningState("t", 2.0, 0.8, k + 1, ph, 0, 0, 0, 0, 0, 0, False, 0.0, 2.0 * k)
    ...       for k, ph in enumerate([0.1, 0.6, 0.1])]
    >>> first_predicted_from_rest(st, lambda s: (s.phase > 0.5, 1.2), 10.0)
    2
    >>> first_predicted_from_rest(st, lambda s: (s.phase > 0.5, 1.2), 3.4)  # 2 + 1.2 + 0.3 s > 3.4 s
    """
    for s in states:
        good, delay = from_rest(s)
        if rights_in_time(good, s.start_s, delay, duration_s):
            return int(s.attempt)
    return None


@dataclass(frozen=True)
class PredictorScore:
    """A predictor's accuracy at the first righting attempt.

    Attributes
    ----------
    name : str
    trials, correct : int
    accuracy : float
    ci95 : (float, float)
        Wilson 95 % interval of the accuracy.
    held_out : bool
        Scored on trials it was not fitted on.
    """

    name: str
    trials: int
    correct: int
    accuracy: float
    ci95: tuple[float, float]
    held_out: bool

    def as_json(self) -> dict:
        return {
            "name": self.name,
            "trials": self.trials,
            "correct": self.correct,
            "accuracy": self.accuracy,
            "ci95": list(self.ci95),
            "held_out": self.held_out,
        }


def score(name: str, correct: Sequence[bool], *, held_out: bool) -> PredictorScore:
    """A :class:`PredictorScore` of per-trial verdicts.

    Examples
    --------
    >>> s = score("x", [True] * 9 + [False], held_out=True)
    >>> s.correct, s.accuracy, [round(v, 3) for v in s.ci95]
    (9, 0.9, [0.596, 0.982])
    """
    n, k = len(correct), int(sum(bool(c) for c in correct))
    return PredictorScore(name, n, k, k / n if n else math.nan, wilson_interval(k, n), held_out)


def held_out_state_predictions(
    trials: Sequence[tuple[dict, list[OpeningState]]],
    maps: dict[float, PhaseMap],
    map_attempts: Sequence[OpeningState],
    theta_l_deg: float,
    *,
    k: int = K_NEIGHBOURS,
) -> list[tuple[dict, int | None]]:
    """Each trial's predicted first righting attempt by a state predictor fitted on the other (Tw, Tl) settings'
    trials (and the single-attempt trials from rest, ``map_attempts``) only.

    Parameters
    ----------
    trials : sequence of (row, states)
        Each stored trial's row and its attempts' :class:`OpeningState` (with Tw and Tl set).
    """
    settings = sorted({(r["wing_period_s"], r["leg_period_s"]) for r, _ in trials})
    out = []
    for s in settings:
        fit = [st for r, sts in trials if (r["wing_period_s"], r["leg_period_s"]) != s for st in sts]
        pred = fit_state_predictor([*fit, *map_attempts], maps, theta_l_deg, k=k)
        for r, sts in trials:
            if (r["wing_period_s"], r["leg_period_s"]) == s:
                out.append((r, first_predicted(pred, sts)))
    return out
