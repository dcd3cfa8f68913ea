"""The simulation against the physical robot's recorded trials: the referee.

For each physical cell (wing command 60/75/90° simulated at its measured plateau, leg amplitude 0/15/30/45°)
:func:`validation_specs` makes ``trials`` simulated trials, by default with random first-attempt phases (each
trial draws phi_1 uniformly from its seed), or all at one given phase: the lab's protocol starts the leg 0.2 s
(the servo log's 10 Hz resolution) before every trial's first opening, so on the robot phi_1 is the same in every
trial (:mod:`landscape.analysis.physical.response`); the model set's own actuation and the given noise Cv on the closed
holds; they run through the ordinary sweep machinery (:func:`sim.sweep.run_sweep`, a resumable store).
:func:`compare` then puts simulated beside physical:

- per cell: success fractions with Wilson 95 % intervals, and whether each fraction lies inside the other's
  interval ("agree"); median time to right from the first wing opening, ± standard deviation, where both right;
- per wing command: the per-attempt success rate by the lab's rule (the first five openings of each trial; an
  attempt succeeds when the robot rights during it) against the lab's recorded counts (``robot_attempts.mat``,
  which pool every leg amplitude, so a wing command is compared only when all its cells ran);
- the side the robot rolls over to: the fraction of righting events with positive roll, against the robot's;
- the log-likelihood of the physical outcomes of a set of cells under the simulated success probabilities
  (each shrunk to ``(k + 0.5) / (n + 1)``), the objective a calibration maximises.

Cells with leg amplitude 15° or 45° are the *held-out* cells of the calibration protocol (fit on 0° and 30°);
every summary reports the fit cells, the held-out cells and all cells separately.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from geometry.errors import UsageError
from landscape.analysis.physical.attempts import LAB_ATTEMPTS_PER_TRIAL, AttemptCount, recorded_attempt_counts
from landscape.analysis.physical.cells import lateralisation
from landscape.analysis.physical.outcome import PhysicalTrial, physical_trials
from landscape.analysis.physical.recording import WING_COMMANDS_DEG, measured_plateaus_deg
from landscape.analysis.trials import fisher_p, wilson_interval

HELD_OUT_LEGS_DEG = (15.0, 45.0)
"""Leg amplitudes of the held-out cells (fit on 0 and 30 degrees, report 15 and 45 on their own)."""
DEFAULT_TRIALS = 10
DEFAULT_CV = 0.05
"""The physical comparison's noise, Cv (sigma / Tl)."""
PHASE_SEED = 0x9E37
"""Mixed into the seed of each cell's phase draws, so that the phases do not depend on the trial seeds."""


class ValidationError(UsageError):
    """Bad input to a validation (unknown cell, no trials)."""


def split_of(theta_l_deg: float) -> str:
    """'held-out' for the held-out leg amplitudes, else 'fit'."""
    return "held-out" if any(abs(theta_l_deg - h) < 1e-9 for h in HELD_OUT_LEGS_DEG) else "fit"


def parse_cells(text: str | None, available: Iterable[tuple[float, float]]) -> list[tuple[float, float]]:
    """Cells ``'60:15,75:0'`` (wing command : leg amplitude, degrees); None or '' gives every available cell.

    Examples
    --------
    >>> parse_cells("60:15, 90:0", [(60.0, 15.0), (90.0, 0.0), (75.0, 30.0)])
    [(60.0, 15.0), (90.0, 0.0)]
    """
    avail = sorted(set(available))
    if not text:
        return avail
    out = []
    for part in text.split(","):
        try:
            w, leg = (float(x) for x in part.strip().split(":"))
        except ValueError:
            raise ValidationError(
                f"--cells item {part.strip()!r} is not WING:LEG; give e.g. --cells 60:15,75:0"
            ) from None
        if (w, leg) not in avail:
            have = ", ".join(f"{a:g}:{b:g}" for a, b in avail)
            raise ValidationError(
                f"--cells {w:g}:{leg:g} is not a recorded cell; the recorded cells are {have}"
            )
        if (w, leg) not in out:
            out.append((w, leg))
    return out


def cell_phases(theta_w_cmd_deg: float, theta_l_deg: float, trials: int, seed: int) -> list[float]:
    """The random first-attempt phases of one cell's trials (uniform on [0, 1), rounded to 1e-6 so that a
    store keyed by phase resumes exactly)."""
    key = [int(seed), PHASE_SEED, int(round(theta_w_cmd_deg * 1000)), int(round(theta_l_deg * 1000))]
    rng = np.random.default_rng(key)
    return [round(float(x), 6) % 1.0 for x in rng.random(int(trials))]


def simulates_commands(model_set: str | Path) -> bool:
    """Whether a model set's wing angle is the servo *command* (a measured actuation profile, which carries the
    measured plateau of each servo itself) rather than the wing angle reached (an idealised profile, simulated
    at the measured plateau)."""
    from sim.model_set import load_model_set

    return load_model_set(model_set).profile == "measured"


def validation_specs(
    cells: Sequence[tuple[float, float]],
    plateaus_deg: dict[float, float],
    *,
    trials: int = DEFAULT_TRIALS,
    cv: float = DEFAULT_CV,
    seed: int = 0,
    robot: str | Path | None = None,
    model_set: str | Path = "paper",
    duration_s: float | None = None,
    dt_s: float | None = None,
    joint_map=None,
    phase: float | Mapping[tuple[float, float], float] | None = None,
    engine: str = "pybullet",
):
    """The simulated trials of the cells, in ``engine``: ``trials`` random phases each (or ``trials`` seeds at the one first-attempt
    ``phase`` in [0, 1), or at each cell's own phase from a mapping ``{(wing command, leg): phase}``, cells it lacks,
    e.g. the leg still, at ``landscape.analysis.physical.response.PROTOCOL_PHASE``), at the cell's measured plateau (or at its
    command for a set with a measured actuation profile, :func:`simulates_commands`).

    Returns a list of :class:`sim.sweep.TrialSpec` for :func:`sim.sweep.run_sweep`.
    """
    from sim.sweep import sweep_specs
    from sim.trial import DEFAULT_DURATION_S

    if int(trials) < 1:
        raise ValidationError(f"--trials must be at least 1; got {trials}")
    if not cells:
        raise ValidationError("no cells to simulate; give --cells WING:LEG,... from the recorded cells")
    if isinstance(phase, Mapping):
        from landscape.analysis.physical.response import PROTOCOL_PHASE

        per_cell = {(float(w), float(leg)): float(p) for (w, leg), p in phase.items()}
        phases = {c: per_cell.get((float(c[0]), float(c[1])), PROTOCOL_PHASE) for c in cells}
    else:
        phases = {c: phase for c in cells}
    for p in set(phases.values()) - {None}:
        if not (np.isfinite(p) and 0.0 <= p < 1.0):
            raise ValidationError(f"--phase must be a first-attempt phase in [0, 1); got {p!r}")
    specs = []
    commanded = simulates_commands(model_set)
    for w, leg in cells:
        fixed = phases[(w, leg)] is not None
        specs += sweep_specs(
            [w if commanded else plateaus_deg.get(w, w)],
            [leg],
            [cv],
            phase=[float(phases[(w, leg)])] if fixed else cell_phases(w, leg, trials, seed),
            trials=int(trials) if fixed else 1,
            duration_s=DEFAULT_DURATION_S if duration_s is None else duration_s,
            dt_s=dt_s,
            robot=robot,
            base_seed=seed,
            joint_map=joint_map,
            model_set=model_set,
            engine=engine,
        )
    return specs


# ------------------------------------------------------------------------------------------------- comparison
@dataclass(frozen=True)
class CellComparison:
    """Simulated against physical at one cell.

    Attributes
    ----------
    theta_w_cmd_deg, theta_w_sim_deg, theta_l_deg : float
        Wing command, the wing angle simulated (the measured plateau), leg amplitude.
    split : {"fit", "held-out"}
    phys_n, phys_k, sim_n, sim_k : int
    phys_p, phys_low, phys_high, sim_p, sim_low, sim_high : float
        Success fractions and Wilson 95 % intervals.
    agree : bool
        Each fraction inside the other's interval.
    phys_ttr_median_s, phys_ttr_sd_s, sim_ttr_median_s, sim_ttr_sd_s : float
        Time to right from the first wing opening over the successes (nan without; sd nan below two).
    fisher_p : float
        Two-sided p-value of Fisher's exact test that both fractions share one success probability
        (:func:`fisher_p`); nan in a ``validation.json`` written before it was stored.
    """

    theta_w_cmd_deg: float
    theta_w_sim_deg: float
    theta_l_deg: float
    split: str
    phys_n: int
    phys_k: int
    phys_p: float
    phys_low: float
    phys_high: float
    sim_n: int
    sim_k: int
    sim_p: float
    sim_low: float
    sim_high: float
    agree: bool
    phys_ttr_median_s: float
    phys_ttr_sd_s: float
    sim_ttr_median_s: float
    sim_ttr_sd_s: float
    fisher_p: float = math.nan

    CSV_COLUMNS = (
        "theta_w_cmd_deg",
        "theta_w_sim_deg",
        "theta_l_deg",
        "split",
        "phys_n",
        "phys_k",
        "phys_p",
        "phys_low",
        "phys_high",
        "sim_n",
        "sim_k",
        "sim_p",
        "sim_low",
        "sim_high",
        "agree",
        "phys_ttr_median_s",
        "phys_ttr_sd_s",
        "sim_ttr_median_s",
        "sim_ttr_sd_s",
        "fisher_p",
    )


@dataclass(frozen=True)
class AttemptComparison:
    """Per-attempt success rate at one wing command, simulated against the lab's record."""

    theta_w_cmd_deg: float
    physical: AttemptCount
    simulated: AttemptCount
    agree: bool


@dataclass(frozen=True)
class SideComparison:
    """Fraction of righting events to positive roll, simulated against the physical robot's."""

    phys_positive: int
    phys_events: int
    phys_low: float
    phys_high: float
    sim_positive: int
    sim_events: int
    sim_low: float
    sim_high: float
    sim_inside_phys: bool


@dataclass(frozen=True)
class Validation:
    """Everything :func:`compare` measures; ``agree_counts`` per split: (cells agreeing, cells)."""

    model_set: str
    model_set_hash: str
    cells: tuple[CellComparison, ...]
    attempts: tuple[AttemptComparison, ...]
    side: SideComparison
    agree_counts: dict = field(default_factory=dict)
    log_likelihood: dict = field(default_factory=dict)
    robot_attempts: int | None = None
    late_rightings: tuple = ()
    imu_mount_deg: float = 0.0


def fractions_agree(k1: int, n1: int, k2: int, n2: int) -> bool:
    """The referee's rule: k1 of n1 and k2 of n2 agree when each fraction lies inside the other's
    Wilson 95 % interval; a fraction of 100 % (or 0 %) therefore agrees only with another of 100 % (or 0 %).

    Examples
    --------
    >>> fractions_agree(5, 5, 19, 20), fractions_agree(5, 5, 10, 10), fractions_agree(4, 5, 7, 10)
    (False, True, True)
    """
    lo1, hi1 = wilson_interval(k1, n1)
    lo2, hi2 = wilson_interval(k2, n2)
    p1, p2 = k1 / n1, k2 / n2
    return bool(lo2 <= p1 <= hi2 and lo1 <= p2 <= hi1)


def _median_sd(values: Sequence[float]) -> tuple[float, float]:
    v = [x for x in values if math.isfinite(x)]
    med = float(np.median(v)) if v else math.nan
    return med, float(np.std(v, ddof=1)) if len(v) >= 2 else math.nan


def sim_time_to_right_s(row: dict) -> float:
    """A stored trial's time to right from its first wing opening, s (nan if it did not right)."""
    if not row.get("success") or row.get("time_to_right_s") is None:
        return math.nan
    starts = row.get("attempt_starts_s") or [0.0]
    return float(row["time_to_right_s"]) - float(starts[0])


def sim_attempts(row: dict, *, max_attempts: int = LAB_ATTEMPTS_PER_TRIAL) -> tuple[int, int]:
    """(successes, attempts) of one stored trial by the lab's rule: its first ``max_attempts`` openings; the
    righting attempt is the last one counted.

    Examples
    --------
    >>> sim_attempts({"success": True, "attempt": 2, "attempt_starts_s": [0.5, 2.5, 4.5]})
    (1, 2)
    >>> sim_attempts({"success": False, "attempt": None, "attempt_starts_s": [0.5, 2.5, 4.5, 6.5, 8.5, 9.9]})
    (0, 5)
    """
    if row.get("success") and row.get("attempt") and int(row["attempt"]) <= max_attempts:
        return 1, int(row["attempt"])
    return 0, min(len(row.get("attempt_starts_s") or []), max_attempts)


def log_likelihood(pairs: Iterable[tuple[int, int, int, int]]) -> float:
    """Log-likelihood of physical outcomes ``(k_phys, n_phys)`` under simulated probabilities from
    ``(k_sim, n_sim)`` shrunk to ``(k + 0.5) / (n + 1)`` (never 0 or 1), summed over cells.

    Examples
    --------
    >>> round(log_likelihood([(5, 5, 10, 10)]), 4)  # p = 10.5 / 11
    -0.2326
    """
    total = 0.0
    for kp, np_, ks, ns in pairs:
        p = (ks + 0.5) / (ns + 1.0)
        total += kp * math.log(p) + (np_ - kp) * math.log(1.0 - p)
    return total


def compare(
    phys: Sequence[PhysicalTrial],
    rows: Sequence[dict],
    cells: Sequence[tuple[float, float]],
    plateaus_deg: dict[float, float],
    recorded_attempts: Sequence[AttemptCount] = (),
    *,
    commanded: bool = False,
    robot_attempts: int | None = None,
) -> Validation:
    """Simulated trial rows (one model set) against the physical trials, at ``cells``.

    A row belongs to a cell when its leg amplitude is the cell's and its wing angle the cell's plateau (or, with
    ``commanded``, the cell's wing command: a measured actuation profile).
    ``recorded_attempts`` (the lab's per-attempt record) gives the per-attempt comparison at the wing commands
    of ``cells``; without it that comparison is empty.
    ``robot_attempts``: count a robot trial as righted (and its time to right) only when it righted within its
    first that many openings, as the lab's per-attempt table counts its 10 s trials (``LAB_ATTEMPTS_PER_TRIAL``);
    the later rightings are listed in ``late_rightings`` as (wing command, leg, opening). None: every recorded
    opening. The side of the roll-overs always counts every recorded righting.
    """
    if robot_attempts is not None and (
        isinstance(robot_attempts, bool) or not isinstance(robot_attempts, int) or robot_attempts < 1
    ):
        raise ValidationError(f"robot_attempts must be a whole number >= 1 (or None); got {robot_attempts!r}")
    late = []
    sets = {(r.get("model_set"), r.get("model_set_hash")) for r in rows}
    if len(sets) > 1:
        raise ValidationError(
            f"the trials mix model sets {sorted(map(str, sets))}; validate one set at a time"
        )
    ms_name, ms_hash = next(iter(sets)) if sets else ("", "")
    out, by_split = [], {"fit": [], "held-out": []}
    sim_att: dict[float, list[int]] = {}
    sim_sides = []
    for w, leg in cells:
        ws = w if commanded else plateaus_deg.get(w, w)
        pt = [t for t in phys if t.theta_w_cmd_deg == w and t.theta_l_deg == leg]
        st = [r for r in rows if abs(r["theta_w_deg"] - ws) < 1e-9 and abs(r["theta_l_deg"] - leg) < 1e-9]
        st = [r for r in st if r.get("status") == "ok"]
        if not pt or not st:
            raise ValidationError(
                f"cell {w:g}:{leg:g} has {len(pt)} physical and {len(st)} simulated trials; both are needed"
            )
        if robot_attempts is not None:
            late += [(w, leg, t.attempts) for t in pt if t.success and t.attempts > robot_attempts]
            pt = [t if not t.success or t.attempts <= robot_attempts
                  else replace(t, success=False, time_to_right_s=math.nan) for t in pt]  # fmt: skip
        kp, n_p = sum(t.success for t in pt), len(pt)
        ks, n_s = sum(bool(r["success"]) for r in st), len(st)
        pl, ph = wilson_interval(kp, n_p)
        sl, sh = wilson_interval(ks, n_s)
        pm, psd = _median_sd([t.time_to_right_s for t in pt if t.success])
        sm, ssd = _median_sd([sim_time_to_right_s(r) for r in st])
        c = CellComparison(
            w, ws, leg, split_of(leg), n_p, kp, kp / n_p, pl, ph, n_s, ks, ks / n_s, sl, sh,
            fractions_agree(kp, n_p, ks, n_s), pm, psd, sm, ssd, fisher_p(kp, n_p, ks, n_s),
        )  # fmt: skip
        out.append(c)
        by_split[c.split].append(c)
        a = sim_att.setdefault(w, [0, 0])
        for r in st:
            k, n = sim_attempts(r)
            a[0] += k
            a[1] += n
            if r["success"] and r.get("side") is not None:
                sim_sides.append(int(r["side"]))
    attempts = []
    for rec in recorded_attempts:
        # the lab's record pools every leg amplitude of a wing command: compare only when all of them ran
        legs = {t.theta_l_deg for t in phys if t.theta_w_cmd_deg == rec.theta_w_cmd_deg}
        if rec.theta_w_cmd_deg not in sim_att or not legs <= {
            leg for w, leg in cells if w == rec.theta_w_cmd_deg
        }:
            continue
        k, n = sim_att[rec.theta_w_cmd_deg]
        lo, hi = wilson_interval(k, n)
        sim = AttemptCount(rec.theta_w_cmd_deg, plateaus_deg.get(rec.theta_w_cmd_deg, math.nan), n, k,
                           k / n if n else math.nan, lo, hi)  # fmt: skip
        ok = n > 0 and fractions_agree(rec.successes, rec.attempts, k, n)
        attempts.append(AttemptComparison(rec.theta_w_cmd_deg, rec, sim, ok))
    lat = lateralisation(t for t in phys if (t.theta_w_cmd_deg, t.theta_l_deg) in set(cells))
    n_lat = lat.positive + lat.negative
    pos = sum(s > 0 for s in sim_sides)
    sl, sh = wilson_interval(pos, len(sim_sides))
    pl, ph = wilson_interval(lat.positive, n_lat)
    side = SideComparison(
        lat.positive, n_lat, pl, ph, pos, len(sim_sides), sl, sh,
        bool(sim_sides) and n_lat > 0 and pl <= pos / len(sim_sides) <= ph,
    )  # fmt: skip
    groups = {"fit": by_split["fit"], "held-out": by_split["held-out"], "all": out}
    return Validation(
        ms_name or "",
        ms_hash or "",
        tuple(out),
        tuple(attempts),
        side,
        {k: (sum(c.agree for c in v), len(v)) for k, v in groups.items()},
        {k: log_likelihood((c.phys_k, c.phys_n, c.sim_k, c.sim_n) for c in v) for k, v in groups.items()},
        robot_attempts,
        tuple(late),
    )


def validate(
    data_dir: str | Path,
    *,
    db: str | Path,
    robot: str | Path | None = None,
    model_set: str | Path = "paper",
    trials: int = DEFAULT_TRIALS,
    cv: float = DEFAULT_CV,
    seed: int = 0,
    cells: str | Sequence[tuple[float, float]] | None = None,
    duration_s: float | None = None,
    dt_s: float | None = None,
    joint_map=None,
    workers: int | None = None,
    scheduler: str | None = None,
    progress: bool = True,
    phase: float | Mapping[tuple[float, float], float] | None = None,
    robot_attempts: int | None = None,
    imu_mount_deg: float = 0.0,
    engine: str = "pybullet",
) -> tuple[Validation, object]:
    """Simulate the physical cells with a model set in ``engine`` (resuming ``db``) and compare:
    ``(Validation, SweepSummary)``.
    ``phase``: every trial's first attempt at this phase, or at each cell's (a mapping, e.g. the lab protocol's,
    :func:`landscape.analysis.physical.response.protocol_phases`); None: random phases (:func:`validation_specs`).
    ``robot_attempts``: count the robot's rightings within its first that many openings only (:func:`compare`).
    ``imu_mount_deg``: judge the robot's uprightness in a body frame pitched that much below its IMU's
    (:func:`landscape.analysis.physical.outcome.physical_trials`).

    Raises
    ------
    PhysicalDataError
        If ``data_dir`` is not the lab's data folder.
    ValidationError, ModelSetError, StoreError, TrialInputError
        For bad cells, trials, model set, store or trial settings.
    """
    from sim.store import KEY_COLUMNS, read_rows
    from sim.sweep import run_sweep

    phys = physical_trials(data_dir, imu_mount_deg=imu_mount_deg)
    plateaus = measured_plateaus_deg(data_dir)
    available = {(t.theta_w_cmd_deg, t.theta_l_deg) for t in phys}
    chosen = parse_cells(cells, available) if cells is None or isinstance(cells, str) else list(cells)
    specs = validation_specs(
        chosen, plateaus, trials=trials, cv=cv, seed=seed, robot=robot, model_set=model_set,
        duration_s=duration_s, dt_s=dt_s, joint_map=joint_map, phase=phase, engine=engine,
    )  # fmt: skip
    summary = run_sweep(specs, db=db, workers=workers, scheduler=scheduler, progress=progress)
    keys = {s.key() for s in specs}
    rows = [r for r in read_rows(db) if tuple(r[c] for c in KEY_COLUMNS) in keys]
    recorded = [a for a in recorded_attempt_counts(data_dir) if a.theta_w_cmd_deg in WING_COMMANDS_DEG]
    v = compare(
        phys, rows, chosen, plateaus, recorded, commanded=simulates_commands(model_set),
        robot_attempts=robot_attempts,
    )  # fmt: skip
    return replace(v, imu_mount_deg=float(imu_mount_deg)), summary


def validation_from_json(doc: dict) -> Validation:
    """A :class:`Validation` back from the ``validation.json`` that ``landscape physical validate`` writes (its
    extra keys, e.g. ``robot`` and ``trials``, are ignored).

    Raises
    ------
    ValidationError
        If ``doc`` is not such a file's content.
    """

    def nan(d: dict) -> dict:  # the JSON writer stores nan (no time to right, no interval) as null
        return {k: (math.nan if v is None else v) for k, v in d.items()}

    try:
        return Validation(
            doc["model_set"],
            doc["model_set_hash"],
            tuple(CellComparison(**nan(c)) for c in doc["cells"]),
            tuple(
                AttemptComparison(a["theta_w_cmd_deg"], AttemptCount(**nan(a["physical"])),
                                  AttemptCount(**nan(a["simulated"])),
                                  a["agree"])
                for a in doc["attempts"]
            ),
            SideComparison(**nan(doc["side"])),
            {k: tuple(v) for k, v in doc["agree_counts"].items()},
            dict(doc["log_likelihood"]),
            doc.get("robot_attempts"),
            tuple(tuple(x) for x in doc.get("late_rightings", ())),
            float(doc.get("imu_mount_deg", 0.0)),
        )  # fmt: skip
    except (KeyError, TypeError) as exc:
        raise ValidationError(
            f"not a validation.json of `landscape physical validate` ({type(exc).__name__}: {exc}); "
            "give the --out directory of that command"
        ) from None
