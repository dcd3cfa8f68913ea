"""What every section reads: the trial rows of a database, the sweep commands that produce them, the paper's
settings they cover, the robot (and model set) they ran on, and the CSV files the sections write."""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from geometry.errors import UsageError
from landscape.analysis import trials as an

PREDICTION_SWEEP = (
    "landscape sweep --theta-w 72 --theta-l 30 --cv 0 --phase 0:0.95:0.05 --trials 1 "
    "--wing-period 2,2.5,3 --leg-period 0.6,0.8,1,1.2,1.4 --db {db}"
)
PHASE_MAP_SWEEP = (
    "landscape sweep --theta-w 70,72,74,76 --theta-l 20,30,40,50 --cv 0 --phase 0:0.95:0.05 "
    "--trials 1 --attempts 1 --db {db}"
)
PHASE_MAP_TL_SWEEP = (
    "landscape sweep --theta-w 72 --theta-l 30 --cv 0 --phase 0:0.95:0.05 --trials 1 "
    "--attempts 1 --leg-period 0.6,1,1.2,1.4 --db {db}"
)
PAPER_SWEEP = "landscape sweep --db {db}"
PAPER_PERIODS = (an.PAPER_WING_PERIOD_S, an.PAPER_LEG_PERIOD_S)


def write_csv(path: Path, rows: list[dict]) -> Path:
    """Write dict rows as CSV (floats to 6 significant digits, None as empty; an empty file without rows)."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="") as f:
        if not rows:
            f.write("")
            return path
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow(
                {k: (f"{v:.6g}" if isinstance(v, float) else ("" if v is None else v)) for k, v in r.items()}
            )
    return path


def load_rows(db: Path) -> list[dict]:
    """Every trial of a database of one robot (one-line errors for a missing or foreign file, or mixed robots)."""
    from sim.store import read_rows

    if not Path(db).is_file():
        raise UsageError(f"database '{db}' not found; run `landscape sweep --db {db}` first")
    rows = read_rows(db)  # reads without writing: a read-only or older store is analysed as it is
    hashes = sorted({r["robot_hash"] for r in rows})
    if len(hashes) > 1:
        raise UsageError(
            f"'{db}' holds trials of {len(hashes)} robots ({', '.join(hashes)}); the analyses "
            "compare settings of one robot: sweep each robot into its own database"
        )
    return rows


@dataclass(frozen=True)
class PaperCells:
    """The probability cells of the paper protocol's multi-attempt trials, of one trial protocol and one phi_1.

    ``cells`` is empty when there are none; ``missing`` then says why and what to run. ``duration_s`` and
    ``dt_s`` are the protocol kept; ``other_protocol_trials`` counts trials of other durations, time steps, model
    sets or engines, which are never pooled with them.
    """

    cells: list
    phase: float | None
    duration_s: float | None = None
    dt_s: float | None = None
    other_protocol_trials: int = 0
    missing: str = ""
    model_set: str = "paper"
    engine: str = "pybullet"

    @property
    def protocol_text(self) -> str:
        return (
            f"{self.duration_s:g} s trials, dt {self.dt_s:g} s"
            + (f", model {self.model_set}" if self.model_set != "paper" else "")
            + (f", engine {self.engine}" if self.engine != "pybullet" else "")
        )


def paper_cells(rows: list[dict], phase: float | None, db) -> PaperCells:
    """Probability cells of the paper protocol (Tw 2 s, Tl 0.8 s, no attempt limit) at one phi_1 (default: the
    one with most trials), of the trial protocol (duration, time step) with most trials."""
    paper = [
        r
        for r in rows
        if r["status"] == "ok"
        and r["attempts"] == 0
        and (r["wing_period_s"], r["leg_period_s"]) == PAPER_PERIODS
    ]
    if not paper:
        return PaperCells(
            [],
            None,
            missing="no multi-attempt trials of the paper's protocol (Tw 2 s, Tl 0.8 s); "
            f"run `{PAPER_SWEEP.format(db=db)}`",
        )

    def protocol(r: dict) -> tuple:
        return r["duration_s"], r["dt_s"], r.get("model_set") or "paper", r.get("engine") or "pybullet"

    protocols: dict[tuple, int] = {}
    for r in paper:
        protocols[protocol(r)] = protocols.get(protocol(r), 0) + 1
    chosen = max(protocols, key=lambda k: (protocols[k], k))
    duration_s, dt_s, model_set, engine = chosen
    kept = [r for r in paper if protocol(r) == chosen]
    cells = an.probability_table(kept)
    counts: dict[float, int] = {}
    for c in cells:
        counts[c.phase] = counts.get(c.phase, 0) + c.n
    if phase is None:
        phase = max(counts, key=lambda k: (counts[k], -k))
    elif phase not in counts:
        have = ", ".join(f"{x:g}" for x in sorted(counts))
        return PaperCells(
            [],
            phase,
            duration_s,
            dt_s,
            len(paper) - len(kept),
            missing=f"no multi-attempt trials at φ1 = {phase:g}; the database has φ1 = {have}",
        )
    at_phase = [c for c in cells if c.phase == phase]
    # a setting swept over phi_1 with one trial each (the prediction sweep) is not a probability estimate
    several = [c for c in at_phase if c.n > 1]
    if not several:
        return PaperCells(
            [],
            phase,
            duration_s,
            dt_s,
            len(paper) - len(kept),
            missing=f"the {len(at_phase)} settings at φ1 = {phase:g} have one trial each "
            f"({sum(c.n for c in at_phase)} trials): a probability needs several; sweep again "
            f"with --trials 2 or more (`{PAPER_SWEEP.format(db=db)} --trials 2 ...`)",
        )
    return PaperCells(
        several, phase, duration_s, dt_s, len(paper) - len(kept), model_set=model_set, engine=engine
    )


def trials_wing_joints(rows: list[dict], robot, theta_w_deg: set[float]):
    """The robot as the trials' model set models it (its CoM moved by the set's ``[mass]`` offset, if any), the
    wing joints the set holds at each theta_w (``{w: joints or None}``) and a sentence saying how the barriers
    pose the wings: each servo at its plateau for a shipped set with a measured actuation that still hashes as
    stored; every joint at theta_w otherwise."""
    from sim.model_set import ModelSetError, load_model_set

    sets = {(r.get("model_set") or "paper", r.get("model_set_hash") or "") for r in rows}
    if len(sets) != 1:
        return robot, None, "Wings posed with every joint at θw (the trials mix model sets)."
    name, stored = next(iter(sets))
    try:
        ms = load_model_set(name)
    except ModelSetError:
        return robot, None, f"Wings posed with every joint at θw (model set {name} is not a shipped set)."
    if ms.measured is None and not ms.com_offset_y_mm:
        return robot, None, f"Wings posed with every joint at θw (model set {name}, idealised)."
    if stored and ms.model_set_hash != stored:
        return (
            robot,
            None,
            f"Wings posed with every joint at θw (model set {name} changed since the trials ran).",
        )
    robot = ms.robot_for(robot)
    moved = f"; CoM moved {ms.com_offset_y_mm:+g} mm along y" if ms.com_offset_y_mm else ""
    if ms.measured is None:
        return robot, None, f"Wings posed with every joint at θw (model set {name}, idealised{moved})."
    joints = ms.wing_joints_by_theta_w(robot.joint_map.wing, sorted(theta_w_deg))
    return (
        robot,
        joints,
        f"Each wing servo posed at its measured plateau (model set {name}{moved}), as the trials ran.",
    )


def trials_robot(rows: list[dict], robot: str | Path | None = None):
    """The robot the trials ran on, for its landscapes: ``robot`` (a URDF) if given, else the stored URDF path if
    it still hashes the same, else the built-in robot if the trials ran on it; the hash must match either way."""
    from geometry import Robot
    from geometry.builtin import load_builtin_robot

    hashes = {r["robot_hash"] for r in rows}
    if robot is not None:
        cand = Robot.from_urdf(Path(robot))
        if hashes and cand.description_hash not in hashes:
            raise UsageError(
                f"--robot {robot} (hash {cand.description_hash}) is not the robot of the trials "
                f"({', '.join(sorted(hashes))}); give the URDF the sweep ran on"
            )
        return cand
    for path, h in sorted({(r["robot"], r["robot_hash"]) for r in rows if r.get("robot")}):
        if Path(path).is_file():
            cand = Robot.from_urdf(Path(path))
            if cand.description_hash == h:
                return cand
    builtin = load_builtin_robot()
    if not hashes or builtin.description_hash in hashes:
        return builtin
    raise UsageError(
        f"the trials' robot file ({sorted({r['robot'] for r in rows})[0]}) is missing or "
        "changed; give the URDF the sweep ran on with --robot FILE.urdf"
    )


def mixed_cell(cells: list) -> an.ProbabilityCell:
    """The setting whose trials disagree most: most trials of the minority outcome per trial, then most trials."""
    return max(
        cells,
        key=lambda c: (min(c.successes, c.n - c.successes) / c.n, c.n, -c.cv, c.theta_w_deg, c.theta_l_deg),
    )


def both_outcomes_first(rows: list[dict], n: int) -> list[dict]:
    """Up to ``n`` rows in trial order, alternating righted and not righted while both last."""
    won = sorted((r for r in rows if r["success"]), key=lambda r: r["trial"])
    lost = sorted((r for r in rows if not r["success"]), key=lambda r: r["trial"])
    out = []
    while len(out) < n and (won or lost):
        for group in (won, lost):
            if group and len(out) < n:
                out.append(group.pop(0))
    return sorted(out, key=lambda r: r["trial"])


def study_setting(
    rows: list[dict], maps: dict, leg_period_s: float = an.PAPER_LEG_PERIOD_S
) -> tuple[float, float] | None:
    """(theta_w, theta_l) of the prediction study: the mapped setting with the most multi-attempt (Tw, Tl) pairs
    at Cv 0, else the setting mapped at leg period ``leg_period_s`` whose single-attempt outcomes are the most
    mixed; None if nothing is mapped."""
    pairs: dict[tuple[float, float], set] = {}
    for r in rows:
        if r["status"] == "ok" and r["attempts"] == 0 and r["cv"] == 0.0:
            pairs.setdefault((r["theta_w_deg"], r["theta_l_deg"]), set()).add(
                (r["wing_period_s"], r["leg_period_s"])
            )
    mapped = {(w, float(tl)) for (w, _), m in maps.items() for tl in m.theta_l_deg}
    cands = [k for k in pairs if k in mapped]
    if cands:
        return max(cands, key=lambda k: (len(pairs[k]), k))
    best, score = None, -1.0
    for (w, tl_s), m in sorted(maps.items()):
        if not math.isclose(tl_s, leg_period_s):
            continue
        for i, tl in enumerate(m.theta_l_deg):
            frac = float(np.nanmean(m.success[i] >= 0.5))
            if min(frac, 1 - frac) > score:
                best, score = (w, float(tl)), min(frac, 1 - frac)
    return best
