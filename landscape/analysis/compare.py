"""Two trial databases side by side, setting by setting: do two engines (or two model sets, or two time steps) give
the same self-righting probabilities and the same single-attempt outcomes?

Multi-attempt settings (``attempts == 0``, one row per trial) are compared by Fisher's exact test of their success
counts: a setting is *consistent* when p >= :data:`CONSISTENT_P`, that is when the trials cannot tell the two
probabilities apart (a perfect match passes in about 95 % of settings). Single attempts without noise are
deterministic, so the same setting (theta_w, theta_l, phi_1, Tw, Tl, heading) is compared outcome for outcome.

Rows are those of :meth:`sim.store.TrialStore.rows`; :func:`source` says what each database holds (engines, model
sets and their hashes) so a comparison names what it compares.
"""

from __future__ import annotations

from collections import Counter, defaultdict
from collections.abc import Iterable
from dataclasses import dataclass

from .trials import CONSISTENT_P, fisher_p, probability_table

__all__ = [
    "MIN_TRIALS",
    "CellPair",
    "SingleAttemptPairs",
    "compare_probabilities",
    "compare_single_attempts",
    "source",
]

MIN_TRIALS = 20
"""Trials each database must hold of a multi-attempt setting for Fisher's test of it (one trial against one cannot
tell two probabilities apart; the paper's sweep has 40)."""


@dataclass(frozen=True)
class CellPair:
    """One multi-attempt setting in both databases.

    Attributes
    ----------
    theta_w_deg, theta_l_deg, cv, phase, wing_period_s, leg_period_s : float
        The setting (phase = phi_1).
    k_a, n_a, k_b, n_b : int
        Successes and trials in the first and the second database.
    fisher_p : float
        Two-sided p of Fisher's exact test of k_a of n_a against k_b of n_b.
    """

    theta_w_deg: float
    theta_l_deg: float
    cv: float
    phase: float
    wing_period_s: float
    leg_period_s: float
    k_a: int
    n_a: int
    k_b: int
    n_b: int
    fisher_p: float

    @property
    def consistent(self) -> bool:
        """Whether Fisher's test cannot tell the two probabilities apart (p >= :data:`CONSISTENT_P`)."""
        return self.fisher_p >= CONSISTENT_P


def compare_probabilities(
    rows_a: Iterable[dict], rows_b: Iterable[dict], *, min_trials: int = 1
) -> tuple[list[CellPair], int]:
    """The multi-attempt settings both databases hold with at least ``min_trials`` trials in each, each with
    Fisher's exact test of its success counts, and how many settings both hold with fewer (not tested).

    Examples
    --------
    >>> row = dict(status="ok", attempts=0, theta_w_deg=74.0, theta_l_deg=30.0, cv=0.1, phase=0.7,
    ...            wing_period_s=2.0, leg_period_s=0.8, success=True, time_to_right_s=2.5, attempt=2, mode="roll")
    >>> a = [row] * 9 + [{**row, "success": False}]
    >>> b = [row] * 2 + [{**row, "success": False}] * 8
    >>> cells, fewer = compare_probabilities(a, b)
    >>> c = cells[0]
    >>> (c.k_a, c.n_a, c.k_b, c.n_b), round(c.fisher_p, 4), c.consistent, fewer
    ((9, 10, 2, 10), 0.0055, False, 0)
    >>> compare_probabilities(a, b, min_trials=MIN_TRIALS)
    ([], 1)
    """
    table_b = {_key(c): c for c in probability_table(rows_b)}
    out, fewer = [], 0
    for c in probability_table(rows_a):
        d = table_b.get(_key(c))
        if d is None:
            continue
        if min(c.n, d.n) < min_trials:
            fewer += 1
            continue
        out.append(
            CellPair(
                *_key(c), c.successes, c.n, d.successes, d.n, fisher_p(c.successes, c.n, d.successes, d.n)
            )
        )
    return out, fewer


def _key(c) -> tuple[float, ...]:
    return (c.theta_w_deg, c.theta_l_deg, c.cv, c.phase, c.wing_period_s, c.leg_period_s)


@dataclass(frozen=True)
class SingleAttemptPairs:
    """Noise-free single attempts of the same setting in both databases.

    Attributes
    ----------
    n : int
        Settings in both.
    same : int
        Of those, how many ended the same way (both righted or both failed).
    righted_a, righted_b : int
        How many righted in each.
    differ : tuple of tuple
        (theta_w_deg, theta_l_deg, phase, wing_period_s, leg_period_s, heading_deg, success_a) of each setting that
        ended differently.
    """

    n: int
    same: int
    righted_a: int
    righted_b: int
    differ: tuple[tuple, ...]


def compare_single_attempts(rows_a: Iterable[dict], rows_b: Iterable[dict]) -> SingleAttemptPairs:
    """Outcome for outcome, the noise-free single attempts (``attempts == 1``, Cv 0) both databases hold; a setting
    stored several times counts by its first row.

    Examples
    --------
    >>> row = dict(status="ok", attempts=1, cv=0.0, theta_w_deg=72.0, theta_l_deg=30.0, phase=0.25,
    ...            wing_period_s=2.0, leg_period_s=0.8, heading_deg=0.0, success=True)
    >>> a = [row, {**row, "phase": 0.5}]
    >>> s = compare_single_attempts(a, [row, {**row, "phase": 0.5, "success": False}])
    >>> s.n, s.same, s.righted_a, s.righted_b, s.differ
    (2, 1, 2, 1, ((72.0, 30.0, 0.5, 2.0, 0.8, 0.0, True),))
    """
    a, b = _singles(rows_a), _singles(rows_b)
    both = sorted(set(a) & set(b))
    differ = tuple((*k, a[k]) for k in both if a[k] != b[k])
    return SingleAttemptPairs(
        len(both), len(both) - len(differ), sum(a[k] for k in both), sum(b[k] for k in both), differ
    )


def _singles(rows: Iterable[dict]) -> dict[tuple, bool]:
    out: dict[tuple, bool] = {}
    for r in rows:
        if r["status"] == "ok" and r["attempts"] == 1 and r["cv"] == 0.0:
            key = (
                r["theta_w_deg"],
                r["theta_l_deg"],
                r["phase"],
                r["wing_period_s"],
                r["leg_period_s"],
                float(r.get("heading_deg") or 0.0),
            )
            out.setdefault(key, bool(r["success"]))
    return out


def source(rows: Iterable[dict]) -> str:
    """What a database holds, in one line: its trials by engine, model set and hash.

    Examples
    --------
    >>> source([dict(engine="mujoco", model_set="paper", model_set_hash="21b75935aaa2cfa3")] * 3)
    '3 trials: mujoco, paper (21b75935aaa2cfa3)'
    """
    counts = Counter(
        (r.get("engine") or "pybullet", r.get("model_set"), r.get("model_set_hash")) for r in rows
    )
    total = sum(counts.values())
    parts = defaultdict(list)
    for (engine, name, h), n in sorted(
        counts.items(), key=lambda kv: (kv[0][0], str(kv[0][1]), str(kv[0][2]))
    ):
        parts[engine].append(f"{name} ({h})" + (f" x {n}" if len(counts) > 1 else ""))
    return f"{total} trials: " + "; ".join(f"{e}, {', '.join(p)}" for e, p in parts.items())
