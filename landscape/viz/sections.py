"""The report's sections: the source paper's analyses of a trial database, each written as CSV tables and
PNG/SVG figures (edge layer; ``landscape analyze …`` and ``landscape report`` call these).

Each ``section_*`` function reads trial rows, writes its files into ``out`` and returns a
:class:`landscape.viz.report.Section`; a section whose trials are missing says which command produces them.
"""

from __future__ import annotations

import csv
import math
import platform
import time
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from geometry.errors import UsageError
from landscape.analysis import trials as an
from landscape.viz.report import Figure, Section, Table, write_report

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


def _write_csv(path: Path, rows: list[dict]) -> Path:
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
    ``dt_s`` are the protocol kept; ``other_protocol_trials`` counts trials of other durations or time steps,
    which are never pooled with them.
    """

    cells: list
    phase: float | None
    duration_s: float | None = None
    dt_s: float | None = None
    other_protocol_trials: int = 0
    missing: str = ""
    model_set: str = "paper"

    @property
    def protocol_text(self) -> str:
        return f"{self.duration_s:g} s trials, dt {self.dt_s:g} s" + (
            f", model {self.model_set}" if self.model_set != "paper" else ""
        )


def _paper_cells(rows: list[dict], phase: float | None, db) -> PaperCells:
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
        return r["duration_s"], r["dt_s"], r.get("model_set") or "paper"

    protocols: dict[tuple, int] = {}
    for r in paper:
        protocols[protocol(r)] = protocols.get(protocol(r), 0) + 1
    chosen = max(protocols, key=lambda k: (protocols[k], k))
    duration_s, dt_s, model_set = chosen
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
    return PaperCells(several, phase, duration_s, dt_s, len(paper) - len(kept), model_set=model_set)


# ---------------------------------------------------------------------------------------------- sections
def _mixed_sentence(cells: list[an.ProbabilityCell]) -> str:
    """What the data say about repeatability: how many settings righted in some trials and not in others."""
    mixed = sum(0 < c.successes < c.n for c in cells)
    return (
        f"{mixed} of {len(cells)} settings righted in some of their trials and not in others (same setting, "
        "different seeds), so a setting's outcome is a probability, estimated over its trials; the brackets "
        "are Wilson 95 % intervals."
    )


def section_probability(rows: list[dict], out: Path, db: Path, *, phase: float | None = None) -> Section:
    """Fig. 6 analogue: P(self-right) over theta_w x theta_l per Cv, n and Wilson 95 % intervals."""
    from landscape.viz.analysis_plots import plot_probability

    title = "Self-righting probability over θw × θl for each noise level Cv"
    pc = _paper_cells(rows, phase, db)
    cells, phase = pc.cells, pc.phase
    if not cells:
        return Section("probability", title, missing=pc.missing)
    csv_path = _write_csv(out / "probability.csv", [asdict(c) for c in cells])
    png = plot_probability(
        cells,
        out / "probability.png",
        title=f"Self-righting probability (φ1 = {phase:g}, {pc.protocol_text})",
    )
    n = sum(c.n for c in cells)
    wins = sum(c.successes for c in cells)
    by_cv = {}
    for c in cells:
        k, m = by_cv.get(c.cv, (0, 0))
        by_cv[c.cv] = (k + c.successes, m + c.n)
    paras = (
        f"{n} trials ({len(cells)} settings, φ1 = {phase:g}, {pc.protocol_text}): {wins} righted "
        f"({wins / n * 100:.1f} %)."
        + (
            f" {pc.other_protocol_trials} trials of other durations, time steps or model sets are not pooled with "
            "them."
            if pc.other_protocol_trials
            else ""
        ),
        "Overall by Cv: "
        + "; ".join(
            f"Cv {cv * 100:g} %: {k}/{m} = {k / m * 100:.1f} %" for cv, (k, m) in sorted(by_cv.items())
        )
        + ".",
        _mixed_sentence(cells),
    )
    return Section(
        "probability",
        title,
        paras,
        (Figure(png, "Self-righting probability per Cv", png.with_suffix(".svg")),),
        (Table("Probability per setting", csv_path),),
    )


def section_phase_map(rows: list[dict], out: Path, db: Path, *, leg_period_s: float = 0.8) -> Section:
    """Fig. 7 analogue: single-attempt outcome against phase and theta_l, per theta_w, no noise."""
    from landscape.viz.analysis_plots import plot_phase_maps

    title = "Single-attempt phase map"
    maps = an.phase_maps(rows)
    sel = [m for (_, tl), m in maps.items() if math.isclose(tl, leg_period_s)]
    if not sel:
        return Section(
            "phase-map",
            title,
            missing="no single-attempt trials without noise at Tl = "
            f"{leg_period_s:g} s; run `{PHASE_MAP_SWEEP.format(db=db)}`",
        )
    recs = []
    for m in maps.values():
        for i, tl in enumerate(m.theta_l_deg):
            for j, ph in enumerate(m.phases):
                if m.n[i, j]:
                    recs.append(
                        {
                            "theta_w_deg": m.theta_w_deg,
                            "leg_period_s": m.leg_period_s,
                            "theta_l_deg": tl,
                            "phase": ph,
                            "n": int(m.n[i, j]),
                            "success": float(m.success[i, j]),
                            "delay_s": float(m.delay_s[i, j]),
                        }
                    )
    csv_path = _write_csv(out / "phase_map.csv", recs)
    png = plot_phase_maps(
        sel,
        out / "phase_map.png",
        title=f"Outcome of one attempt against its phase (Tl = {leg_period_s:g} s, no noise)",
    )
    paras = [
        "Each cell is one single-attempt trial: the wings open once at phase φ of the leg cycle and the trial "
        "ends one wing period later. Green: the robot righted."
    ]
    for m in sel:
        for i, tl in enumerate(m.theta_l_deg):
            good = m.good_phases(tl)
            paras.append(
                f"θw {m.theta_w_deg:g}°, θl {tl:g}°: {len(good)}/{int((m.n[i] > 0).sum())} phases right"
                + (f" (φ {', '.join(f'{g * 100:.0f}' for g in good)} %)" if 0 < len(good) < 8 else "")
            )
    return Section(
        "phase-map",
        title,
        tuple(paras),
        (Figure(png, "Single-attempt phase map", png.with_suffix(".svg")),),
        (Table("Single-attempt outcomes (all Tl)", csv_path),),
    )


def section_prediction(
    rows: list[dict],
    out: Path,
    db: Path,
    *,
    states_path: str | Path | None = None,
    robot: str | Path | None = None,
    progress: bool = True,
) -> Section:
    """Fig. 8 analogue: phase-based prediction of the first righting attempt against simulation, and beside it
    the prediction that also knows the state each attempt starts from (:func:`prediction_scores`, both held out;
    its opening states in ``states_path``), written to ``out/prediction_scores.csv``."""
    from landscape.viz.analysis_plots import plot_prediction

    title = "Phase-based prediction of multi-attempt outcomes"
    maps = an.phase_maps(rows)
    pred = an.predict_trials(rows, maps)
    # without noise, trials that differ only in their seed are the same trial: count each phi_1 once
    seen: set[tuple] = set()
    uniq = []
    for p in pred:
        key = (p.theta_w_deg, p.theta_l_deg, p.wing_period_s, p.leg_period_s, p.phase)
        if p.cv == 0.0 and key in seen:
            continue
        if p.cv == 0.0:
            seen.add(key)
        uniq.append(p)
    pred = uniq
    acc = an.prediction_accuracy(pred)
    clean = [c for c in acc if c.cv == 0.0 and c.n >= 3]
    # the (theta_w, theta_l) with the most (Tw, Tl) cells is the prediction study; the others are paper-sweep cells
    if clean:
        counts: dict[tuple, int] = {}
        for c in clean:
            counts[(c.theta_w_deg, c.theta_l_deg)] = counts.get((c.theta_w_deg, c.theta_l_deg), 0) + 1
        study = max(counts, key=counts.get)
        clean = [c for c in clean if (c.theta_w_deg, c.theta_l_deg) == study]
    noisy = [c for c in acc if c.cv > 0.0 and (c.wing_period_s, c.leg_period_s) == PAPER_PERIODS]
    if not clean and not noisy:
        return Section(
            "prediction",
            title,
            missing="no multi-attempt trials with a matching single-attempt phase map; "
            f"run `{PHASE_MAP_TL_SWEEP.format(db=db)}` and `{PREDICTION_SWEEP.format(db=db)}` (and "
            f"`{PHASE_MAP_SWEEP.format(db=db)}` for the noisy comparison)",
        )
    _write_csv(out / "prediction_trials.csv", [{**asdict(p), "correct": p.correct} for p in pred])
    csv_path = _write_csv(out / "prediction_accuracy.csv", [asdict(c) for c in clean + noisy])
    png = plot_prediction(
        clean, noisy, out / "prediction.png", title="Phase-based prediction against simulation"
    )
    paras = [
        "Prediction: attempt k opens at the time the actuation draws from the trial's own seed; its phase is "
        "looked up in the single-attempt map of the same θw, θl and Tl (nearest mapped phase); the first good "
        "phase that leaves time to right before the trial ends is the predicted attempt. Correct = same first "
        "righting attempt as the simulation, or both never."
    ]
    if clean:
        study_pred = [
            p
            for p in pred
            if p.cv == 0.0
            and (p.theta_w_deg, p.theta_l_deg) == study
            and any((c.wing_period_s, c.leg_period_s) == (p.wing_period_s, p.leg_period_s) for c in clean)
        ]
        miss = {
            "the simulation rights later than predicted": 0,
            "earlier than predicted": 0,
            "predicted to right, never does": 0,
            "predicted never, rights": 0,
        }
        for p in study_pred:
            s_, p_ = p.simulated_attempt, p.predicted_attempt
            if s_ == p_:
                continue
            key = (
                "predicted to right, never does"
                if s_ is None
                else "predicted never, rights"
                if p_ is None
                else "the simulation rights later than predicted"
                if s_ > p_
                else "earlier than predicted"
            )
            miss[key] += 1
        a = np.array([c.accuracy for c in clean])
        sd = a.std(ddof=1) if len(a) > 1 else 0.0
        paras.append(
            f"Without noise, θw {study[0]:g}°, θl {study[1]:g}°, {len(clean)} (Tw, Tl) pairs × "
            f"{clean[0].n} phases φ1: accuracy {a.mean() * 100:.0f} ± {sd * 100:.0f} % (mean ± s.d. over the "
            f"pairs; the paper: 91 ± 6 %). Range {a.min() * 100:.0f}–{a.max() * 100:.0f} %."
        )
        paras.append(
            "Misses: " + "; ".join(f"{k} {v}" for k, v in miss.items()) + ". The map assumes every attempt "
            "starts from rest; a failed attempt can leave the robot rocking, so a later attempt may right "
            "at a phase that fails from rest, or fail at one that rights from rest."
        )
    if noisy:
        n_tr = sum(c.n for c in noisy)
        k_tr = sum(c.correct for c in noisy)
        rmse = float(np.sqrt(np.mean([(c.simulated_p - c.predicted_p) ** 2 for c in noisy])))
        paras.append(
            f"With noise (paper sweep, Tw 2 s, Tl 0.8 s, {len(noisy)} settings, {n_tr} trials): the first "
            f"righting attempt is predicted in {k_tr}/{n_tr} trials ({k_tr / n_tr * 100:.0f} %); predicted "
            f"and simulated probability differ by {rmse:.2f} RMS."
        )
    tables = [Table("Accuracy per setting", csv_path)]
    res = None
    if clean:
        try:
            res = prediction_scores(rows, db, states_path=states_path, robot=robot, progress=progress)
        except UsageError as exc:  # e.g. the trials' robot file moved: the phase map's numbers still stand
            paras.append(f"The prediction that knows each attempt's state needs the trials rerun: {exc}")
    if res is not None:
        paras.append(
            f"Held out, θw {res.setting[0]:g}°, θl {res.setting[1]:g}°, {res.reruns} trials over {res.pairs} (Tw, Tl) "
            "settings: "
            + "; ".join(
                f"{x.name} {x.correct}/{x.trials} = {x.accuracy * 100:.1f} % (95 % [{x.ci95[0] * 100:.1f}, "
                f"{x.ci95[1] * 100:.1f}] %)"
                for x in res.scores
            )
            + f". The state predictor (landscape.analysis.prediction) is fitted on the other settings' trials for "
            f"each setting it predicts; it reads each attempt's opening state from the trials rerun with a trace "
            f"({res.reproduced} of {res.reruns} reproduce their stored outcome)."
        )
        tables.append(
            Table(
                "Both predictors, held out (Wilson 95 %)",
                _write_csv(
                    out / "prediction_scores.csv",
                    [{**x.as_json(), "ci95": f"{x.ci95[0]:.4f}-{x.ci95[1]:.4f}"} for x in res.scores],
                ),
            )
        )
        _write_csv(out / "prediction_state_trials.csv", res.per_trial)
    return Section(
        "prediction",
        title,
        tuple(paras),
        (Figure(png, "Prediction accuracy and predicted vs simulated probability", png.with_suffix(".svg")),),
        tuple(tables),
    )


@dataclass(frozen=True)
class PredictionScores:
    """Both predictors scored on the prediction study (:func:`prediction_scores`).

    Attributes
    ----------
    scores : list of PredictorScore
        The phase map's, then the state predictor's.
    setting : (float, float)
        The study's (theta_w, theta_l), degrees.
    pairs : int
        Its (Tw, Tl) settings.
    reruns, reproduced, new_runs : int
        Trials rerun with a trace (from the states file or now), how many reproduce their stored outcome, and
        how many were run now.
    states_path : Path
        The file of opening states (resumable: trials already in it are not run again).
    per_trial : list of dict
        Per trial: its setting, stored first righting attempt and each predictor's.
    """

    scores: list
    setting: tuple[float, float]
    pairs: int
    reruns: int
    reproduced: int
    new_runs: int
    states_path: Path
    per_trial: list


def _study_trials(rows: list[dict], maps: dict) -> tuple[tuple[float, float] | None, list[dict]]:
    """The prediction study: the noise-free multi-attempt trials of the mapped (theta_w, theta_l) with the most
    (Tw, Tl) settings that have a phase map, one trial per (Tw, Tl, phi_1) (without noise, seeds repeat it)."""
    cands: dict[tuple[float, float], set] = {}
    for r in rows:
        if r["status"] != "ok" or r["attempts"] != 0 or r["cv"] != 0.0:
            continue
        pm = maps.get((r["theta_w_deg"], r["leg_period_s"]))
        if pm is not None and np.isclose(pm.theta_l_deg, r["theta_l_deg"], rtol=0.0, atol=1e-9).any():
            cands.setdefault((r["theta_w_deg"], r["theta_l_deg"]), set()).add(
                (r["wing_period_s"], r["leg_period_s"])
            )
    if not cands:
        return None, []
    study = max(cands, key=lambda k: (len(cands[k]), k))
    seen, out = set(), []
    for r in sorted(rows, key=lambda r: (r["trial"], r["seed"])):
        if r["status"] != "ok" or r["attempts"] != 0 or r["cv"] != 0.0:
            continue
        if (r["theta_w_deg"], r["theta_l_deg"]) != study or (
            r["wing_period_s"],
            r["leg_period_s"],
        ) not in cands[study]:
            continue
        key = (r["wing_period_s"], r["leg_period_s"], r["phase"], r["duration_s"], r["dt_s"])
        if key not in seen:
            seen.add(key)
            out.append(r)
    return study, out


def _read_states(path: Path) -> dict[str, dict]:
    import json

    done = {}
    if path.is_file():
        for line in path.read_text().splitlines():
            try:
                d = json.loads(line)
            except json.JSONDecodeError:
                continue  # a line cut short by an interruption: that trial is run again
            if isinstance(d, dict) and "key" in d and "states" in d:
                done[d["key"]] = d
    return done


def prediction_scores(
    rows: list[dict],
    db: Path,
    *,
    states_path: str | Path | None = None,
    robot: str | Path | None = None,
    progress: bool = True,
) -> PredictionScores:
    """The paper's phase-map prediction and the state predictor (:mod:`landscape.analysis.prediction`) on the
    prediction study's trials, both held out, with Wilson 95 % intervals.

    The state predictor needs each trial's opening states: every study trial is rerun with a trace (as stored:
    :func:`rerun_trial`, checked against its stored outcome) and its states appended to ``states_path``
    (default: beside the database, ``DB.opening-states.jsonl``); trials already there are not run again, so an
    interrupted run resumes.

    Raises
    ------
    UsageError
        If the database holds no study (noise-free multi-attempt trials with a single-attempt phase map).
    """
    import json
    import sys

    from tqdm import tqdm

    from landscape.analysis import prediction as pr
    from landscape.analysis.energy import body_model
    from sim.model_set import load_model_set

    maps = an.phase_maps(rows)
    study, trials = _study_trials(rows, maps)
    if study is None:
        raise UsageError(
            "no noise-free multi-attempt trials with a matching single-attempt phase map; run "
            f"`{PHASE_MAP_TL_SWEEP.format(db=db)}`, its Tl 0.8 s column and `{PREDICTION_SWEEP.format(db=db)}`"
        )
    base = {
        (p.wing_period_s, p.leg_period_s, p.phase): p for p in an.predict_trials(trials, maps) if p.cv == 0.0
    }
    path = Path(states_path) if states_path is not None else Path(f"{db}.opening-states.jsonl")
    done = _read_states(path)
    todo = [r for r in trials if pr.trial_key(r) not in done]
    if todo:
        rb = _robot_of(todo, robot)
        inertia = {}
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(path, "a") as f:
            for r in tqdm(
                todo, desc="opening states", unit="trial", file=sys.stderr, disable=None if progress else True
            ):
                res = rerun_trial(r, robot_urdf=rb.source)
                name = r.get("model_set") or "paper"
                if name not in inertia:
                    inertia[name] = body_model(rb, load_model_set(name)).pose(0.0, 0.0).inertia_kg_m2
                key = pr.trial_key(r)
                states = pr.opening_states(res, key, inertia_kg_m2=inertia[name])
                d = {"key": key, "reproduced": _reproduces(r, res), "states": [st.as_dict() for st in states]}
                f.write(json.dumps(d) + "\n")
                f.flush()
                done[key] = d
    per, base_ok, pairs = [], [], []
    for r in trials:
        d = done[pr.trial_key(r)]
        states = [
            pr.OpeningState(**{**st, "wing_period_s": r["wing_period_s"], "leg_period_s": r["leg_period_s"]})
            for st in d["states"]
        ]
        pairs.append((r, states))
    map_pms = {tl: m for (w, tl), m in maps.items() if w == study[0]}
    map_attempts = pr.map_states(rows, *study)
    state_pred = pr.held_out_state_predictions(pairs, map_pms, map_attempts, study[1])
    state_ok = []
    for r, predicted in state_pred:
        stored = r["attempt"] if r["success"] else None
        b = base[(r["wing_period_s"], r["leg_period_s"], r["phase"])]
        base_ok.append(b.correct)
        state_ok.append(predicted == stored)
        per.append(
            {
                "wing_period_s": r["wing_period_s"],
                "leg_period_s": r["leg_period_s"],
                "phase": r["phase"],
                "simulated_attempt": stored,
                "phase_map_attempt": b.predicted_attempt,
                "state_attempt": predicted,
            }
        )
    reproduced = sum(bool(done[pr.trial_key(r)]["reproduced"]) for r in trials)
    return PredictionScores(
        [
            pr.score("phase map", base_ok, held_out=True),
            pr.score("state", state_ok, held_out=True),
        ],
        study,
        len({(r["wing_period_s"], r["leg_period_s"]) for r in trials}),
        len(trials),
        reproduced,
        len(todo),
        path,
        per,
    )


def _study_setting(
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


def section_evolution(
    rows: list[dict],
    out: Path,
    db: Path,
    *,
    theta_w_deg: float | None = None,
    theta_l_deg: float | None = None,
    phase: float | None = None,
    cv: float = 0.15,
    seed: int = 1,
    wing_period_s: float = 2.0,
    leg_period_s: float = 0.8,
    attempts: int = 12,
) -> Section:
    """Fig. 9 analogue: phases visited over attempts without and with noise, over the single-attempt map.

    ``theta_w_deg``, ``theta_l_deg`` None: the prediction study's setting found in the data (the mapped setting
    with the most multi-attempt (Tw, Tl) pairs at Cv 0, else the most mixed mapped setting). ``phase`` None: a
    mapped phase from which the noise-free sequence never meets a good phase, else the most common phi_1 of
    the multi-attempt trials at that setting, else the map's first phase. ``cv`` and ``seed`` drive the noisy
    sequence; ``attempts`` is how many attempts are drawn."""
    from landscape.viz.analysis_plots import plot_evolution

    title = "Phase evolution over attempts"
    maps = an.phase_maps(rows)
    if theta_w_deg is None or theta_l_deg is None:
        study = _study_setting(rows, maps, leg_period_s)
        if study is None:
            return Section(
                "evolution",
                title,
                missing=f"no single-attempt phase map at Tl {leg_period_s:g} s; run "
                f"`{PHASE_MAP_SWEEP.format(db=db)}`",
            )
        theta_w_deg = study[0] if theta_w_deg is None else theta_w_deg
        theta_l_deg = study[1] if theta_l_deg is None else theta_l_deg
    pm = maps.get((theta_w_deg, leg_period_s))
    if pm is None or not np.isclose(pm.theta_l_deg, theta_l_deg).any():
        return Section(
            "evolution",
            title,
            missing=f"no single-attempt phase map for θw {theta_w_deg:g}°, θl "
            f"{theta_l_deg:g}°, Tl {leg_period_s:g} s; run `{PHASE_MAP_SWEEP.format(db=db)}`",
        )
    n_distinct = an.distinct_phases(wing_period_s, leg_period_s)
    if phase is None:  # a start from which the noise-free sequence never meets a good phase, if there is one
        phase = next(
            (
                float(ph)
                for ph in pm.phases
                if not any(
                    pm.lookup(theta_l_deg, (ph + k * wing_period_s / leg_period_s) % 1.0)[0]
                    for k in range(n_distinct)
                )
            ),
            None,
        )
    if (
        phase is None
    ):  # every start meets a good phase: the trials' own phi_1 at this setting, else the map's first
        used = [
            r["phase"]
            for r in rows
            if r["status"] == "ok"
            and r["attempts"] == 0
            and (r["theta_w_deg"], r["theta_l_deg"]) == (theta_w_deg, theta_l_deg)
        ]
        phase = max(set(used), key=lambda ph: (used.count(ph), -ph)) if used else float(pm.phases[0])
    recs, seqs = [], []
    for label, c in (("no noise", 0.0), (f"Cv = {cv * 100:g} %, seed {seed}", cv)):
        duration = phase * leg_period_s + attempts * wing_period_s
        while (
            True
        ):  # noise can lengthen the holds: extend (same seed, same prefix) until there are enough attempts
            starts, phs = an.attempt_sequence(
                theta_w_deg,
                theta_l_deg,
                phase=phase,
                cv=c,
                seed=seed,
                duration_s=duration,
                wing_period_s=wing_period_s,
                leg_period_s=leg_period_s,
            )
            if len(starts) >= attempts:
                break
            duration *= 2.0
        starts, phs = starts[:attempts], phs[:attempts]
        good = [pm.lookup(theta_l_deg, float(p))[0] for p in phs]
        first = next((k + 1 for k, g in enumerate(good) if g), None)
        seqs.append(
            (f"{label}: {len(set(np.round(phs, 6)))} distinct phases in {len(phs)} attempts", phs, first)
        )
        recs += [
            {"noise_cv": c, "attempt": k + 1, "start_s": float(t), "phase": float(p), "good": bool(g)}
            for k, (t, p, g) in enumerate(zip(starts, phs, good, strict=True))
        ]
    csv_path = _write_csv(out / "evolution.csv", recs)
    png = plot_evolution(
        pm,
        theta_l_deg,
        seqs,
        out / "evolution.png",
        title=f"θw {theta_w_deg:g}°, θl {theta_l_deg:g}°, Tw {wing_period_s:g} s, Tl "
        f"{leg_period_s:g} s, φ1 = {phase:g}",
    )
    paras = (
        f"Without noise the phase advances by Tw/Tl = {wing_period_s / leg_period_s:g} (mod 1) per attempt and "
        f"visits LCM(Tw, Tl)/Tw = {n_distinct} distinct phases; a start whose phases are all bad never rights. "
        "With noise the phase wanders and eventually lands on a good one.",
        f"First good phase: no noise {seqs[0][2] or 'never'}; with noise attempt {seqs[1][2] or 'never'} "
        f"(within {attempts} attempts).",
    )
    return Section(
        "evolution",
        title,
        paras,
        (Figure(png, "Phases visited over attempts", png.with_suffix(".svg")),),
        (Table("Phases per attempt", csv_path),),
    )


def section_barrier(
    rows: list[dict],
    out: Path,
    db: Path,
    *,
    robot: str | Path | None = None,
    step_deg: float = 1.0,
    phase: float | None = None,
) -> Section:
    """Barrier against outcome: Spearman rho with bootstrap intervals and a logistic fit, per Cv."""
    from landscape.viz.analysis_plots import plot_barrier_outcome

    title = "Barrier against outcome"
    pc = _paper_cells(rows, phase, db)
    cells, phase = pc.cells, pc.phase
    if not cells:
        return Section("barrier", title, missing=pc.missing)
    used = [
        r for r in rows if r["attempts"] == 0 and (r["wing_period_s"], r["leg_period_s"]) == PAPER_PERIODS
    ]
    robot = _robot_of(used, robot)
    pairs = {(c.theta_w_deg, c.theta_l_deg) for c in cells}
    robot, joints, posed_by = _set_wing_joints(used, robot, {w for w, _ in pairs})
    barriers = an.landscape_barriers(robot, pairs, step_deg=step_deg, progress=True, wing_joints_deg=joints)
    res = an.barrier_outcome(cells, barriers)
    recs = []
    for r in res:
        for c, e, g in zip(r.cells, r.exact_mj, r.grid_mj, strict=True):
            recs.append(
                {
                    "theta_w_deg": c.theta_w_deg,
                    "theta_l_deg": c.theta_l_deg,
                    "cv": c.cv,
                    "n": c.n,
                    "successes": c.successes,
                    "p": c.p,
                    "ci_low": c.ci_low,
                    "ci_high": c.ci_high,
                    "exact_barrier_mj": float(e),
                    "grid_barrier_mj": float(g),
                    "mean_time_to_right_s": c.mean_time_to_right_s,
                }
            )
    stats = [
        {
            "cv": r.cv,
            "settings": len(r.cells),
            "spearman_rho": r.rho,
            "rho_ci_low": r.rho_low,
            "rho_ci_high": r.rho_high,
            "rho_p": r.rho_p,
            "rho_grid": r.rho_grid,
            "rho_time_to_right": r.rho_time,
            "rho_time_ci_low": r.rho_time_low,
            "rho_time_ci_high": r.rho_time_high,
            "logistic_a": r.fit.a,
            "logistic_b_per_mj": r.fit.b,
            "e50_mj": r.fit.e50_mj,
            "separated": r.fit.separated,
        }
        for r in res
    ]
    table = _write_csv(out / "barrier_outcome.csv", recs)
    stats_csv = _write_csv(out / "barrier_stats.csv", stats)
    png = plot_barrier_outcome(
        res, out / "barrier_outcome.png", title=f"Minimal righting barrier against outcome (φ1 = {phase:g})"
    )
    paras = [
        f"Barriers: exact (hull face–edge graph) and the 1° grid search, at θl on the +θl side, for "
        f"{len(barriers)} settings; outcomes: the paper-protocol trials at φ1 = {phase:g}. {posed_by}"
    ]
    for s in stats:
        paras.append(
            f"Cv {s['cv'] * 100:g} %: Spearman ρ(barrier, P) = {s['spearman_rho']:.2f} "
            f"[{s['rho_ci_low']:.2f}, {s['rho_ci_high']:.2f}] (p = {s['rho_p']:.2g}; grid barrier "
            f"{s['rho_grid']:.2f}); logistic E50 = {s['e50_mj']:.2f} mJ"
            + (" (outcomes separated by the barrier)" if s["separated"] else "")
            + "."
        )
    return Section(
        "barrier",
        title,
        tuple(paras),
        (Figure(png, "Barrier against outcome", png.with_suffix(".svg")),),
        (Table("Barrier and outcome per setting", table), Table("Statistics per Cv", stats_csv)),
    )


def _set_wing_joints(rows: list[dict], robot, theta_w_deg: set[float]):
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


def _robot_of(rows: list[dict], robot: str | Path | None = None):
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


TRAJECTORY_TRIALS = 8
"""How many trials of the chosen setting the trajectories section reruns with a trace, by default."""
RERUN_TTR_TOL_S = 1e-6
"""A rerun reproduces a stored time to right if they differ by at most this, s (far below any time step)."""


def _mixed_cell(cells: list) -> an.ProbabilityCell:
    """The setting whose trials disagree most: most trials of the minority outcome per trial, then most trials."""
    return max(
        cells,
        key=lambda c: (min(c.successes, c.n - c.successes) / c.n, c.n, -c.cv, c.theta_w_deg, c.theta_l_deg),
    )


def _both_outcomes_first(rows: list[dict], n: int) -> list[dict]:
    """Up to ``n`` rows in trial order, alternating righted and not righted while both last."""
    won = sorted((r for r in rows if r["success"]), key=lambda r: r["trial"])
    lost = sorted((r for r in rows if not r["success"]), key=lambda r: r["trial"])
    out = []
    while len(out) < n and (won or lost):
        for group in (won, lost):
            if group and len(out) < n:
                out.append(group.pop(0))
    return sorted(out, key=lambda r: r["trial"])


def rerun_trial(row: dict, *, robot_urdf: str | Path):
    """A stored trial run again with a trace, with every parameter of its row (as :func:`sim.sweep.run_spec` runs
    it): same seed, protocol, model set and robot.

    Raises
    ------
    UsageError
        If the row's model set cannot be loaded or has changed since the trial ran.
    """
    from sim.model_set import ModelSetError, load_model_set
    from sim.trial import run_trial

    name = row.get("model_set") or "paper"
    try:
        ms = load_model_set(name)
    except ModelSetError as exc:
        raise UsageError(f"cannot rerun trial {row['trial']}: {exc}") from None
    if row.get("model_set_hash") and ms.model_set_hash != row["model_set_hash"]:
        raise UsageError(
            f"cannot rerun trial {row['trial']}: model set {name} changed since it ran (hash "
            f"{ms.model_set_hash} != {row['model_set_hash']})"
        )
    act = ms.actuation(
        row["theta_w_deg"],
        row["theta_l_deg"],
        wing_period_s=row["wing_period_s"],
        leg_period_s=row["leg_period_s"],
    )
    return run_trial(
        row["theta_w_deg"],
        row["theta_l_deg"],
        phase=row["phase"],
        cv=row["cv"],
        rng=row["seed"],
        duration_s=row["duration_s"],
        dt_s=row["dt_s"],
        robot=robot_urdf,
        actuation=act,
        attempts=row["attempts"] or None,
        model_set=ms,
        trace=True,
    )


def _reproduces(row: dict, res) -> bool:
    if bool(row["success"]) != bool(res.success):
        return False
    if not res.success:
        return True
    return abs(float(row["time_to_right_s"]) - float(res.time_to_right_s)) <= RERUN_TTR_TOL_S


def _three_d_note() -> tuple[bool, str | None]:
    """Whether 3-D rendering runs here, and if not, the sentence that says why."""
    from landscape.viz import render as rd

    problem = rd.off_screen_problem()
    if problem is None:
        return True, None
    return False, f"3-D rendering is unavailable here ({problem}), so only the contour map is drawn."


def _trajectory_figures(files: list[Path], caption: str) -> tuple[Figure, ...]:
    """The contour map (PNG with its SVG) and, if drawn, the 3-D landscape of :func:`render_trajectories`."""
    figs = [Figure(files[0], f"{caption}: contour map", files[1])]
    if len(files) > 2:
        figs.append(Figure(files[2], f"{caption}: over the 3-D landscape"))
    return tuple(figs)


def section_trajectories(
    rows: list[dict],
    out: Path,
    db: Path,
    *,
    robot: str | Path | None = None,
    max_trials: int = TRAJECTORY_TRIALS,
    step_deg: float = 1.0,
) -> Section:
    """Trajectories of the sweep's trials at its most uncertain setting, drawn over that setting's landscape.

    The setting is the paper protocol's (Tw 2 s, Tl 0.8 s, no attempt limit, the φ1 and trial protocol with most
    trials) whose trials disagree most (largest minority outcome fraction, then most trials). Up to
    ``max_trials`` (default :data:`TRAJECTORY_TRIALS`) of its trials, both outcomes alternately, are rerun with a
    trace (:func:`rerun_trial`); each rerun is checked against the stored outcome and time to right. The paths
    are drawn by :func:`landscape.viz.trajectory.render_trajectories` on a ``step_deg`` grid, into
    ``out/trajectories``; without off-screen 3-D rendering, the contour map only.
    """
    from landscape.computation import compute
    from landscape.viz.trajectory import render_trajectories

    title = "Trajectories of simulated trials over the landscape"
    if max_trials < 1:
        raise UsageError(f"max_trials must be at least 1; got {max_trials}")
    pc = _paper_cells(rows, None, db)
    if not pc.cells:
        return Section("trajectories", title, missing=pc.missing)
    cell = _mixed_cell(pc.cells)
    at = [
        r
        for r in rows
        if r["status"] == "ok"
        and r["attempts"] == 0
        and (r["wing_period_s"], r["leg_period_s"]) == PAPER_PERIODS
        and (r["duration_s"], r["dt_s"], r.get("model_set") or "paper")
        == (pc.duration_s, pc.dt_s, pc.model_set)
        and (r["theta_w_deg"], r["theta_l_deg"], r["cv"], r["phase"])
        == (cell.theta_w_deg, cell.theta_l_deg, cell.cv, cell.phase)
    ]
    try:
        rb = _robot_of(at, robot)
    except UsageError as exc:
        return Section("trajectories", title, missing=str(exc))
    chosen = _both_outcomes_first(at, max_trials)
    results = [rerun_trial(r, robot_urdf=rb.source) for r in chosen]
    recs = []
    for r, res in zip(chosen, results, strict=True):
        recs.append(
            {
                "trial": r["trial"],
                "seed": r["seed"],
                "stored_success": int(bool(r["success"])),
                "rerun_success": int(res.success),
                "stored_time_to_right_s": r["time_to_right_s"],
                "rerun_time_to_right_s": res.time_to_right_s,
                "attempt": res.attempt,
                "mode": res.mode,
                "reproduced": int(_reproduces(r, res)),
            }
        )
    same = sum(x["reproduced"] for x in recs)
    csv_path = _write_csv(out / "trajectories.csv", recs)
    c = compute(rb, theta_w_deg=cell.theta_w_deg, theta_l_deg=cell.theta_l_deg, step_deg=step_deg)
    three_d, note = _three_d_note()
    files = render_trajectories(
        c,
        [np.column_stack([res.trace.pitch_deg, res.trace.roll_deg]) for res in results],
        [res.success for res in results],
        out / "trajectories",
        robot_name=rb.name,
        what="simulated",
        landscape_3d=three_d,
    )
    n_ok = sum(res.success for res in results)
    paras = [
        f"The setting closest to the boundary: θw {cell.theta_w_deg:g}°, θl {cell.theta_l_deg:g}°, Cv "
        f"{cell.cv * 100:g} %, φ1 = {cell.phase:g} ({pc.protocol_text}), where {cell.successes} of {cell.n} "
        f"trials righted, the most mixed outcomes of the {len(pc.cells)} settings of the paper protocol.",
        f"{len(results)} of its trials (trials {', '.join(str(r['trial']) for r in chosen)}; seeds in the table) "
        f"were run again with a trace: {n_ok} righted, {len(results) - n_ok} did not. "
        + (
            f"Every rerun reproduces its stored outcome (success and time to right within "
            f"{RERUN_TTR_TOL_S * 1e6:g} µs)."
            if same == len(recs)
            else f"Only {same} of {len(recs)} reruns reproduce their stored outcome (success and time to right "
            f"within {RERUN_TTR_TOL_S * 1e6:g} µs): the simulation here differs from the one that filled the "
            "database (package versions in the inputs table)."
        ),
        "Each path is the body's (pitch, roll) from the end of settling until the trial stopped, over the "
        f"landscape of the setting's pose (grid step {step_deg:g}°), with the minimal righting barrier's saddle "
        "and path.",
    ]
    if note:
        paras.append(note)
    return Section(
        "trajectories",
        title,
        tuple(paras),
        _trajectory_figures(
            files, f"{len(results)} simulated trials at θw {cell.theta_w_deg:g}°, θl {cell.theta_l_deg:g}°"
        ),
        (Table("Reruns against the stored outcomes", csv_path),),
    )


ENERGY_TRIALS = 8
"""How many multi-attempt trials the energy section reruns with a trace, by default."""


def energy_reruns(
    rows: list[dict], db, *, sample: int | None = None, robot: str | Path | None = None, progress: bool = True
):
    """Up to ``sample`` (default :data:`ENERGY_TRIALS`) multi-attempt trials of ``rows``, both outcomes
    alternately in trial order, rerun with a trace (:func:`rerun_trial`) and checked against their stored
    outcome.

    Returns
    -------
    groups : list of (BodyModel, list of Motion)
        The reruns' motions, one group per model set, each with the robot as its set poses it.
    records : list of dict
        Per rerun: trial, seed, stored and rerun outcome and time to right, ``reproduced``.

    Raises
    ------
    UsageError
        If ``rows`` is empty or holds no multi-attempt trial, or ``sample`` is below 1 or above their number.
    """
    import sys

    from tqdm import tqdm

    from landscape.analysis import energy as en
    from sim.model_set import load_model_set

    if not rows:
        raise UsageError(f"'{db}' holds no trials; run `{PAPER_SWEEP.format(db=db)}` first")
    multi = [r for r in rows if r["status"] == "ok" and r["attempts"] == 0]
    if not multi:
        raise UsageError(
            f"'{db}' holds no multi-attempt trials (attempts without limit), whose attempts the energy budget "
            f"measures; run `{PAPER_SWEEP.format(db=db)}`"
        )
    if sample is not None and not 1 <= sample <= len(multi):
        raise UsageError(
            f"a sample of {sample} trials is not within the {len(multi)} multi-attempt trials of '{db}'; ask for "
            f"1 to {len(multi)}"
        )
    chosen = _both_outcomes_first(multi, min(ENERGY_TRIALS if sample is None else sample, len(multi)))
    rb = _robot_of(chosen, robot)
    by_set: dict[str, list] = {}
    records = []
    for r in tqdm(chosen, desc="reruns", unit="trial", file=sys.stderr, disable=None if progress else True):
        res = rerun_trial(r, robot_urdf=rb.source)
        by_set.setdefault(r.get("model_set") or "paper", []).append(
            en.simulated_motion(res, trial=f"seed {r['seed']}")
        )
        records.append(
            {
                "trial": r["trial"],
                "seed": r["seed"],
                "model_set": r.get("model_set") or "paper",
                "stored_success": int(bool(r["success"])),
                "rerun_success": int(res.success),
                "stored_time_to_right_s": r["time_to_right_s"],
                "rerun_time_to_right_s": res.time_to_right_s,
                "reproduced": int(_reproduces(r, res)),
            }
        )
    groups = [(en.body_model(rb, load_model_set(name)), motions) for name, motions in by_set.items()]
    return groups, records


def energy_files(out: Path, groups, *, title: str, progress: bool = True):
    """The energy budget of each (BodyModel, motions) group (:func:`landscape.analysis.energy.energy_budget`,
    one barrier table per group), written as ``out/energy.csv`` (one row per attempt) and ``out/energy.png``
    (and .svg). Returns the attempt rows, the traces (as (motion, trace) pairs), the CSV and the PNG."""
    import sys

    from tqdm import tqdm

    from landscape.analysis import energy as en
    from landscape.viz.energy_plots import plot_energy_attempts

    rows, traces = [], []
    for body, motions in groups:
        with tqdm(
            desc="barrier table", unit="pose", file=sys.stderr, disable=None if progress else True
        ) as bar:
            _, ets, attempt_rows = en.energy_budget(motions, body, progress=bar.update)
        rows += attempt_rows
        traces += list(zip(motions, ets, strict=True))
    csv_path = _write_csv(out / "energy.csv", [r.row() for r in rows])
    png = plot_energy_attempts(rows, out / "energy.png", title=title)
    return rows, traces, csv_path, png


def energy_paragraphs(rows) -> list[str]:
    """One sentence per source: attempts, righted, and how often the margin's sign and the barrier alone match
    the outcome (Wilson 95 % intervals)."""
    from landscape.analysis import energy as en

    out = []
    for source in en.SOURCES:
        g = [r for r in rows if r.source == source]
        if not g:
            continue
        agree = en.sign_agreement(g)
        ratio = [r.ke_peak_mj / r.barrier_mj for r in g if math.isfinite(r.barrier_mj) and r.barrier_mj > 0]
        out.append(
            f"{source.capitalize()}: {len(g)} attempts of {len({r.trial for r in g})} trials, "
            f"{sum(r.success for r in g)} righted; peak kinetic energy in the barrier's direction over the barrier "
            f"median {np.median(ratio):.2g} (largest {max(ratio):.2g}). "
            + "; ".join(
                f"{a.name} matches the outcome in {a.correct}/{a.attempts} ({a.accuracy * 100:.0f} %, 95 % "
                f"[{a.ci_low * 100:.0f}, {a.ci_high * 100:.0f}] %)"
                for a in agree
            )
            + " (the barrier threshold is the best one on these same attempts)."
        )
    return out


ENERGY_METHOD = (
    "Per attempt, from the opening until the wings start closing or the body turns upright: kinetic energy of "
    "rotation about the CoM with the posed robot's inertia, split into body-axis shares (roll, pitch, yaw) that sum "
    "to it, plus the CoM's translation; the minimal righting barrier at the pose held (a barrier map over the poses "
    "visited, exact method, interpolated); the height above the basin's minimum. The margin is the largest value "
    "of kinetic energy in the barrier's direction plus height minus barrier; a positive margin says the attempt had "
    "the energy to cross. Simulated velocities come from the engine; recorded ones from the gyro (body frame: the "
    "IMU's mounting measured from the two rests), the CoM taken as rolling about the lowest hull point."
)


def section_energy(
    rows: list[dict],
    out: Path,
    db: Path,
    *,
    robot: str | Path | None = None,
    physical_dir: str | Path | None = None,
    sample: int | None = None,
    physical_set: str | None = None,
    progress: bool = True,
) -> Section:
    """The energy budget of up to ``sample`` (default :data:`ENERGY_TRIALS`) rerun multi-attempt trials
    (:func:`energy_reruns`) and, with ``physical_dir``, of the robot's recorded trials (model set
    ``physical_set``, default :data:`landscape.analysis.physical.motion.DEFAULT_PHYSICAL_SET`, on the lab robot of
    ``robot`` or the trials'), on one figure: ``out/energy.csv``, ``out/energy.png``, ``out/energy_reruns.csv``.
    A database without multi-attempt trials leaves the section missing (with the sweep to run)."""
    from landscape.analysis.physical.motion import DEFAULT_PHYSICAL_SET, recorded_motions
    from sim.model_set import load_model_set

    title = "Energy budget of the attempts"
    try:
        groups, records = energy_reruns(rows, db, sample=sample, robot=robot, progress=progress)
    except UsageError as exc:
        if sample is not None or physical_dir is None:
            return Section("energy", title, missing=str(exc))
        groups, records = [], []
    paras = [ENERGY_METHOD]
    tables = []
    if records:
        same = sum(x["reproduced"] for x in records)
        paras.append(
            f"{len(records)} multi-attempt trials rerun with a trace (seeds "
            f"{', '.join(str(x['seed']) for x in records)}): {same} of {len(records)} reproduce their stored outcome "
            f"(success and time to right within {RERUN_TTR_TOL_S * 1e6:g} µs)."
        )
        tables.append(
            Table("Reruns against the stored outcomes", _write_csv(out / "energy_reruns.csv", records))
        )
    if physical_dir is not None:
        ms = load_model_set(physical_set or DEFAULT_PHYSICAL_SET)
        rec = recorded_motions(physical_dir, _robot_of(rows, robot), ms)
        groups = [*groups, (rec.body, rec.motions)]
        paras.append(
            f"Recorded: {len(rec.motions)} trials of the robot, posed by model set {rec.model_set}, IMU mounting "
            f"{rec.mount_deg:.1f}°."
        )
    attempt_rows, _, csv_path, png = energy_files(
        out,
        groups,
        title="Peak kinetic energy in the barrier's direction against the barrier",
        progress=progress,
    )
    paras += energy_paragraphs(attempt_rows)
    return Section(
        "energy",
        title,
        tuple(paras),
        (
            Figure(
                png,
                "Peak kinetic energy in the barrier's direction against the barrier",
                png.with_suffix(".svg"),
            ),
        ),
        (Table("One row per attempt", csv_path), *tables),
    )


def section_physical(
    rows: list[dict],
    out: Path,
    db: Path,
    *,
    data_dir: str | Path,
    robot: str | Path | None = None,
    step_deg: float = 1.0,
) -> Section:
    """The physical robot's recorded attempts at each commanded wing angle, over the landscape at the measured wing
    plateau and theta_l 0 (as ``landscape render --physical`` draws them, into ``out/physical/wing_W``), and
    the physical trials' outcomes per (theta_w, theta_l) with Wilson intervals.

    The landscape is the robot of the trials (``robot``, else as :func:`_robot_of` finds it); a note says so when
    it is not the lab robot.

    Raises
    ------
    PhysicalDataError
        If ``data_dir`` is not the lab's data directory.
    """
    from landscape.analysis.physical.cells import PhysicalCell, physical_cells
    from landscape.analysis.physical.measured import WING_COMMANDS_DEG
    from landscape.analysis.physical.outcome import physical_trials
    from landscape.computation import compute
    from landscape.viz.trajectory import physical_poses, physical_robot_note, render_trajectories

    title = "The physical robot's attempts over the landscape"
    cells = physical_cells(physical_trials(data_dir))
    csv_path = _write_csv(
        out / "physical_cells.csv", [{k: getattr(c, k) for k in PhysicalCell.CSV_COLUMNS} for c in cells]
    )
    poses = physical_poses(data_dir, commands_deg=WING_COMMANDS_DEG, theta_l_deg=0.0)
    try:
        rb = _robot_of(rows, robot)
    except UsageError as exc:
        return Section("physical", title, missing=str(exc))
    three_d, note = _three_d_note()
    paras = [
        f"Every recorded attempt (one per wing opening, up to the one that righted) of the trials with the leg "
        f"still (θl 0°), per commanded wing angle, over {rb.name}'s landscape at the measured wing plateau "
        f"(grid step {step_deg:g}°)."
    ]
    paras += [n[0].upper() + n[1:] + "." for n in physical_robot_note(rb)]
    figures: list[Figure] = []
    for pose in poses:
        c = compute(rb, theta_w_deg=pose.theta_w_deg, theta_l_deg=0.0, step_deg=step_deg)
        files = render_trajectories(
            c,
            [np.column_stack([a.pitch_deg, a.roll_deg]) for a in pose.attempts],
            [a.righted for a in pose.attempts],
            out / "physical" / f"wing_{pose.theta_w_cmd_deg:g}",
            robot_name=rb.name,
            what="physical",
            landscape_3d=three_d,
        )
        n_ok = sum(a.righted for a in pose.attempts)
        paras.append(
            f"Wing command {pose.theta_w_cmd_deg:g}° (landscape at {pose.theta_w_deg:.1f}°"
            + ("" if pose.plateau_measured else ", the command: no measured plateau")
            + f"): {len(pose.attempts)} attempts of {len({a.name for a in pose.attempts})} trials, {n_ok} righted."
        )
        figures += _trajectory_figures(files, f"Physical attempts, wing command {pose.theta_w_cmd_deg:g}°")
    if note:
        paras.append(note)
    return Section(
        "physical",
        title,
        tuple(paras),
        tuple(figures),
        (Table("Physical trials per wing angle and leg amplitude (Wilson 95 % intervals)", csv_path),),
    )


def section_validation(
    out: Path, *, validations: list[str | Path], data_dir: str | Path | None = None
) -> Section:
    """The simulation against the physical robot: per model set (a ``landscape physical validate`` or
    ``calibrate`` output directory, or its ``validation.json``), success per cell with the fit and held-out
    cells apart, per-attempt rates, righting side and the time-to-right figure; with ``data_dir``, the resting
    pitch while the wings are held open, robot beside each set's robot model.

    Raises
    ------
    ValidationError
        If a file is not a ``validation.json``.
    """
    import json

    from landscape.analysis.physical.resting import resting_pitch_table
    from landscape.analysis.physical.validation import validation_from_json
    from landscape.viz.physical_plots import consistent_text, robot_rule_text, time_to_right_figure

    title = "The simulation against the physical robot"
    docs = []
    for v in validations:
        f = Path(v) / "validation.json" if Path(v).is_dir() else Path(v)
        if not f.is_file():
            from landscape.analysis.physical.validation import ValidationError

            raise ValidationError(
                f"--validation: {f} not found; give the --out directory of `landscape physical validate`"
            )
        docs.append(json.loads(f.read_text()))
    paras, figures, tables = [], [], []
    paras.append(
        "Simulated trials at each physical cell (the set's own actuation; first-attempt phases as each set names) "
        "beside the "
        "physical robot's recorded trials. A cell agrees when each success fraction lies inside the other's "
        "Wilson 95 % interval; cells with leg amplitude 15° or 45° are held out of any calibration and counted "
        "apart."
    )
    for k, doc in enumerate(docs):
        v = validation_from_json(doc)
        tag = f"{v.model_set} ({v.model_set_hash})"
        fit, held, every = v.agree_counts["fit"], v.agree_counts["held-out"], v.agree_counts["all"]
        s = v.side
        side = f"{s.sim_positive}/{s.sim_events}" if s.sim_events else "no righting events"
        paras.append(
            f"Model set {tag}, robot {Path(str(doc.get('robot', '?'))).name}, {doc.get('trials', '?')} trials a cell, "
            + (
                "random first-attempt phases"
                if doc.get("phase") is None
                else "first attempts at each cell's phase under the lab's protocol"
                if doc.get("phase") == "protocol"
                else f"first attempts at phase {doc['phase']}"
            )
            + f", Cv {doc.get('cv', '?')}: {every[0]} of {every[1]} cells agree ({fit[0]} of {fit[1]} fit cells, "
            f"{held[0]} of {held[1]} held-out cells); log-likelihood of the physical outcomes "
            f"{v.log_likelihood['all']:.1f}. Per-attempt rates agreeing: "
            f"{sum(a.agree for a in v.attempts)} of {len(v.attempts)} wing commands. Righting to + roll: "
            f"simulated {side}, physical {s.phys_positive}/{s.phys_events}."
            + "".join(f" {t[0].upper()}{t[1:]}." for t in (consistent_text(v), robot_rule_text(v)) if t)
        )
        d = out / "validation" / f"{k}_{v.model_set}"
        cells = _write_csv(d / "cells.csv", [{c: getattr(x, c) for c in x.CSV_COLUMNS} for x in v.cells])
        att = _write_csv(
            d / "attempts.csv",
            [
                {
                    "theta_w_cmd_deg": a.theta_w_cmd_deg,
                    "physical": f"{a.physical.successes}/{a.physical.attempts}",
                    "physical_low": a.physical.ci_low,
                    "physical_high": a.physical.ci_high,
                    "simulated": f"{a.simulated.successes}/{a.simulated.attempts}",
                    "simulated_low": a.simulated.ci_low,
                    "simulated_high": a.simulated.ci_high,
                    "agree": a.agree,
                }
                for a in v.attempts
            ],
        )
        tables += [
            Table(f"{tag}: success per cell, physical and simulated (Wilson 95 %)", cells),
            Table(f"{tag}: per-attempt success rate per wing command", att),
        ]
        png = time_to_right_figure(v, d / "time_to_right.png")
        figures.append(
            Figure(
                png,
                f"Time to right, physical and simulated ({tag}); hatched: held-out cells",
                png.with_suffix(".svg"),
            )
        )
    if data_dir is not None:
        from dataclasses import asdict

        from geometry.robots import load_robot
        from landscape.analysis.physical.hold import hold_pitch_frames, plateau_hold_deg
        from landscape.minima import metastable_orientation

        rows = resting_pitch_table(data_dir)
        commands = [x.theta_w_cmd_deg for x in rows]
        out_rows, frames = [], []
        robots = {str(doc.get("robot")) for doc in docs if doc.get("robot")}
        models = {}
        for r in sorted(robots):  # each robot's holds once: relative to its rest here, in frames below
            rb = load_robot(r)
            rest = metastable_orientation(rb, 0.0, 0.0)[0]
            hold = plateau_hold_deg(rb, data_dir, commands)
            models[rb.name] = [hold[c] - rest for c in commands]
            frames += [{"robot": rb.name} | asdict(x) for x in hold_pitch_frames(data_dir, hold, rest)]
        for i, x in enumerate(rows):
            row = {
                "wing_command_deg": x.theta_w_cmd_deg,
                "measured_plateau_deg": x.theta_w_measured_deg,
                "robot_median_pitch_deg": x.median_deg,
                "robot_q25_deg": x.q25_deg,
                "robot_q75_deg": x.q75_deg,
                "n": x.n,
            }
            for name, vals in models.items():
                row[f"model_{name}_deg"] = vals[i]
                row[f"model_{name}_minus_robot_deg"] = vals[i] - x.median_deg
            out_rows.append(row)
        tables.append(
            Table(
                "Resting pitch while the wings are held open (leg still): robot and model, relative to their rest "
                "before the first opening",
                _write_csv(out / "validation" / "resting_pitch.csv", out_rows),
            )
        )
        tables += _opening_tables(out, data_dir, frames)
        body_rows, mount = _body_frame_rows(data_dir, docs)
        if mount is not None:
            paras.append(
                f"The IMU's mounting, measured from the two rests every righted trial records (on its back before "
                f"the first opening, upright after righting; {mount.n} trials): {mount.mount_deg:.1f}° "
                f"[{mount.mount_q25_deg:.1f}, {mount.mount_q75_deg:.1f}]. In the body frame it gives, each set's "
                "hold (each wing servo at its own measured plateau) beside the robot's, first openings with the leg "
                "still: "
                + "; ".join(
                    f"{r['model_set']} {r['wing_command_deg']:g}° {r['model_minus_robot_deg']:+.1f}°"
                    for r in body_rows
                )
                + "."
            )
            tables.append(
                Table(
                    "Hold pitch of first openings (leg still) in the body frame (the IMU's reading minus the mounting "
                    "the two rests measure), robot beside each model set",
                    _write_csv(out / "validation" / "hold_body_frame.csv", body_rows),
                )
            )
    return Section("validation", title, tuple(paras), tuple(figures), tuple(tables))


def _body_frame_rows(data_dir, docs: list[dict]):
    """Per validated set (a shipped set, or a file set whose hash still matches) and wing command: the robot's
    hold in the body frame the two rests give and the set's own hold (its robot as the set models it), and the
    mounting (:class:`landscape.analysis.physical.mounting.RestMounting`; None when no validation names a robot)."""
    from geometry.robots import load_robot
    from landscape.analysis.physical.hold import hold_pitch_frames, per_servo_hold_deg, plateau_hold_deg
    from landscape.analysis.physical.mounting import mounting_from_rests
    from landscape.minima import metastable_orientation
    from sim.model_set import ModelSetError, load_model_set

    rows, mount, seen = [], None, set()
    for doc in docs:
        if not doc.get("robot"):
            continue
        try:
            ms = load_model_set(doc["model_set"])
        except ModelSetError:
            continue  # a file set given by path: its name alone does not find it again
        key = (ms.model_set_hash, doc["robot"])
        if ms.model_set_hash != doc.get("model_set_hash") or key in seen:
            continue  # another version of the set, or one already shown (validated twice, e.g. at two phases)
        seen.add(key)
        robot = ms.robot_for(load_robot(doc["robot"]))
        mount = mounting_from_rests(data_dir, robot) if mount is None else mount
        commands = (60.0, 75.0, 90.0)
        if ms.measured is not None:
            hold = per_servo_hold_deg(robot, ms.measured, commands)
        else:
            hold = plateau_hold_deg(robot, data_dir, commands)
        frames = hold_pitch_frames(data_dir, hold, metastable_orientation(robot, 0.0, 0.0)[0])
        for f in frames:
            body = f.recorded_deg - mount.mount_deg
            rows.append(
                {
                    "model_set": ms.name,
                    "wing_command_deg": f.theta_w_cmd_deg,
                    "robot_imu_deg": f.recorded_deg,
                    "imu_mount_deg": mount.mount_deg,
                    "robot_body_deg": body,
                    "model_deg": f.model_deg,
                    "model_minus_robot_deg": f.model_deg - body,
                }
            )
    return rows, mount


def _opening_tables(out: Path, data_dir, frames: list[dict]) -> list[Table]:
    """The hold pitch of first openings in the IMU's frame beside each robot model's (``frames``: rows of
    :func:`landscape.analysis.physical.hold.hold_pitch_frames` with their robot), and every recorded first opening."""
    from dataclasses import asdict

    from landscape.analysis.physical.lean import cell_lean, recorded_leans
    from landscape.analysis.physical.response import recorded_first_openings

    first = [
        {
            "trial": o.name,
            "wing_command_deg": o.theta_w_cmd_deg,
            "leg_deg": o.theta_l_deg,
            "leg_lead_s": o.leg_lead_s,
            "leg_swing_s": o.leg_swing_s,
            "leg_hold_roll_deg": o.leg_hold_roll_deg,
            "gyro_deviation_deg": o.gyro_deviation_deg,
        }
        | asdict(o.response)
        for o in recorded_first_openings(data_dir)
    ]
    leans = [asdict(cell_lean(*cell, h)) for cell, h in recorded_leans(data_dir).items()]
    return [
        Table(
            "Hold pitch of first openings (leg still) in the IMU's frame and relative to each trial's rest, beside "
            "the model's; the IMU's mounting fitted as one constant (residuals also with it fitted on the other "
            "commands)",
            _write_csv(out / "validation" / "hold_frames.csv", frames),
        ),
        Table(
            "First opening of every recorded trial: the leg command's lead, the body's roll while the leg is held "
            "and when it rolled fastest before the opening (the leg's swing), the pitch overshoot, the rise time and "
            "the lateral tilt asin(cos p sin r) of largest magnitude 0.2-0.6 s after the opening starts, the tilt "
            "when the wings start closing (0.95-1.05 s), when it rolled past a tilt of 45 deg and how far the "
            "recorded tilt strays from the gyro's",
            _write_csv(out / "validation" / "first_openings.csv", first),
        ),
        Table(
            "Every opening until the robot first rights, leg moving: the held body's median lateral tilt with the "
            "leg settled on + and on - (windows counted), and when the openings that roll over leave the level "
            "(the tilt last rising through 5 deg before passing 45 deg; median, s after the opening starts)",
            _write_csv(out / "validation" / "hold_leans.csv", leans),
        ),
    ]


#: the report's sections in page order; a new analysis is one ``section_*`` function and one entry here
SECTIONS = {
    "probability": section_probability,
    "phase map": section_phase_map,
    "prediction": section_prediction,
    "phase evolution": section_evolution,
    "barrier vs outcome": section_barrier,
    "trajectories": section_trajectories,
    "energy": section_energy,
}
#: sections that take the trials' robot (``robot=``)
_ROBOT_SECTIONS = {"barrier vs outcome", "trajectories", "energy"}
#: sections that also take the physical data directory (``physical_dir=``)
_PHYSICAL_SECTIONS = {"energy"}


def build_report(
    db: Path,
    out: Path,
    *,
    robot: str | Path | None = None,
    physical_dir: str | Path | None = None,
    validations: list[str | Path] = (),
) -> tuple[Path, list[Section]]:
    """Every section of :data:`SECTIONS` on the trials of ``db``, and one self-contained HTML page in ``out``;
    with ``physical_dir`` (the lab's data directory), also :func:`section_physical`; with ``validations``
    (``landscape physical validate`` outputs), also :func:`section_validation`.

    Returns
    -------
    page : Path
        The written ``index.html``.
    sections : list of Section
        As written (a section without data says which sweep produces it).
    """
    from importlib.metadata import PackageNotFoundError, version

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    rows = load_rows(db)
    timings: dict[str, float] = {}
    sections = []
    for name, fn in SECTIONS.items():
        t0 = time.perf_counter()
        kw = {"robot": robot} if name in _ROBOT_SECTIONS else {}
        if name in _PHYSICAL_SECTIONS:
            kw["physical_dir"] = physical_dir
        sections.append(fn(rows, out, db, **kw))
        timings[name] = time.perf_counter() - t0
    if physical_dir is not None:
        t0 = time.perf_counter()
        sections.append(section_physical(rows, out, db, data_dir=physical_dir, robot=robot))
        timings["physical robot"] = time.perf_counter() - t0
    if validations:
        t0 = time.perf_counter()
        sections.append(section_validation(out, validations=list(validations), data_dir=physical_dir))
        timings["validation"] = time.perf_counter() - t0
    ok = [r for r in rows if r["status"] == "ok"]
    inputs = {
        "database": str(Path(db).resolve()),
        "trials": str(len(rows)),
        "diverged": str(sum(r["status"] == "diverged" for r in rows)),
        "robots": ", ".join(sorted({f"{Path(r['robot']).name} ({r['robot_hash']})" for r in rows})),
        "time steps (s)": ", ".join(f"{x:g}" for x in sorted({r["dt_s"] for r in rows})),
        "trial CPU time (s)": f"{sum(r['cpu_s'] or 0.0 for r in ok):.0f}",
        **({"physical data": str(Path(physical_dir).resolve())} if physical_dir is not None else {}),
        "package versions in the database": ", ".join(sorted({str(r["version"]) for r in rows})),
    }
    versions = {"python": platform.python_version(), "platform": platform.platform()}
    for pkg in ("selfrighting-landscape", "numpy", "scipy", "numba", "pybullet", "matplotlib", "trimesh"):
        try:
            versions[pkg] = version(pkg)
        except PackageNotFoundError:  # a missing optional package is reported, not fatal
            versions[pkg] = "not installed"
    page = write_report(
        sections,
        out,
        title="Self-righting: barrier, coordination and randomness",
        inputs=inputs,
        versions=versions,
        timings_s=timings,
    )
    return page, sections
