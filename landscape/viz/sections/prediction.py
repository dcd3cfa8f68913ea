"""The prediction section: the first righting attempt of multi-attempt trials predicted from the phase map, and
from the phase and the state each attempt starts from."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass
from pathlib import Path

import numpy as np

from geometry.errors import UsageError
from landscape.analysis import trials as an
from landscape.analysis.reruns import reproduces, rerun_trial
from landscape.viz.report import Figure, Section, Table
from landscape.viz.sections.data import (
    PAPER_PERIODS,
    PHASE_MAP_SWEEP,
    PHASE_MAP_TL_SWEEP,
    PREDICTION_SWEEP,
    trials_robot,
    write_csv,
)


def section_prediction(
    rows: list[dict],
    out: Path,
    db: Path,
    *,
    states_path: str | Path | None = None,
    robot: str | Path | None = None,
    progress: bool = True,
    headings: int | None = None,
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
    write_csv(out / "prediction_trials.csv", [{**asdict(p), "correct": p.correct} for p in pred])
    csv_path = write_csv(out / "prediction_accuracy.csv", [asdict(c) for c in clean + noisy])
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
            "Misses: " + "; ".join(f"{k} {v}" for k, v in miss.items()) + ". The map's attempts start from "
            "rest at heading 0; a later attempt starts where the failed ones left the robot, nearly still but "
            "turned on the ground, and in the simulation the heading changes the outcome (below)."
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
            res = prediction_scores(
                rows, db, states_path=states_path, robot=robot, progress=progress, headings=headings
            )
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
            + f". The phase and heading map knows each attempt's phase and the robot's heading on the ground when it "
            f"opens: it is the phase map's {res.heading_runs // max(res.headings, 1)} single attempts run at "
            f"{res.headings} headings over 90° ({res.heading_runs} attempts). pybullet's friction directions are "
            "fixed in the world, so in the simulation the outcome depends on the heading modulo 90°, and a failed "
            "attempt leaves the robot turned; a physical robot on an isotropic floor would not care "
            "(benchmarks/studies/heading.py measures it). The state predictor (landscape.analysis.prediction) is "
            "fitted on the other settings' trials for each setting it predicts. Both read each attempt's opening "
            f"state from the trials rerun with a trace ({res.reproduced} of {res.reruns} reproduce their stored "
            "outcome)."
        )
        tables.append(
            Table(
                "Both predictors, held out (Wilson 95 %)",
                write_csv(
                    out / "prediction_scores.csv",
                    [{**x.as_json(), "ci95": f"{x.ci95[0]:.4f}-{x.ci95[1]:.4f}"} for x in res.scores],
                ),
            )
        )
        write_csv(out / "prediction_state_trials.csv", res.per_trial)
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
    heading_runs, heading_new_runs : int
        Single attempts in the phase and heading map, and how many were run now.
    headings : int
        Headings per mapped phase.
    heading_path : Path
        The file of the heading map's single attempts (resumable like ``states_path``).
    """

    scores: list
    setting: tuple[float, float]
    pairs: int
    reruns: int
    reproduced: int
    new_runs: int
    states_path: Path
    per_trial: list
    heading_runs: int = 0
    heading_new_runs: int = 0
    headings: int = 0
    heading_path: Path | None = None


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


def _read_jsonl(path: Path) -> dict[str, dict]:
    """The objects of a resumable JSON-lines file by their ``key`` (a line cut short by an interruption is
    skipped, so what it held is run again)."""
    import json

    done = {}
    if path.is_file():
        for line in path.read_text().splitlines():
            try:
                d = json.loads(line)
            except json.JSONDecodeError:
                continue
            if isinstance(d, dict) and "key" in d:
                done[d["key"]] = d
    return done


def _read_states(path: Path) -> dict[str, dict]:
    """The opening states file's trials; a trial written before states carried the heading is run again."""
    return {
        k: d
        for k, d in _read_jsonl(path).items()
        if "states" in d and all("heading_deg" in st for st in d["states"])
    }


def heading_maps(
    rows: list[dict],
    study: tuple[float, float],
    leg_periods: list[float],
    db: Path,
    *,
    headings: int,
    path: Path,
    robot: str | Path | None,
    progress: bool,
) -> tuple[dict, int, int]:
    """The phase and heading maps (:class:`landscape.analysis.prediction.HeadingMap`) of the study's (theta_w,
    theta_l) at each Tl: every stored single-attempt trial of the phase map run again at each heading of
    :func:`~landscape.analysis.prediction.heading_grid` but 0 (the stored trial itself), appended to ``path`` as
    it runs (an interrupted run resumes). Returns the maps by Tl, the attempts in them and how many ran now."""
    import json
    import sys

    from tqdm import tqdm

    from landscape.analysis import prediction as pr

    grid = pr.heading_grid(headings)
    singles = [
        r
        for r in rows
        if r["status"] == "ok"
        and r["attempts"] == 1
        and r["cv"] == 0.0
        and (r["theta_w_deg"], r["theta_l_deg"]) == study
        and r["leg_period_s"] in leg_periods
    ]
    singles.sort(key=lambda r: (r["leg_period_s"], r["phase"], r["trial"], r["seed"]))
    by_cell: dict[tuple, dict] = {}
    for r in singles:
        by_cell.setdefault((r["leg_period_s"], r["phase"]), r)
    done = _read_jsonl(path)
    jobs = [(r, float(h)) for r in by_cell.values() for h in grid if h != 0.0]
    todo = [(r, h) for r, h in jobs if f"{pr.trial_key(r)}/heading{h:g}" not in done]
    if todo:
        rb = trials_robot([r for r, _ in todo], robot)
        path.parent.mkdir(parents=True, exist_ok=True)
        with open(path, "a") as f:
            for r, h in tqdm(
                todo, desc="heading map", unit="attempt", file=sys.stderr, disable=None if progress else True
            ):
                res = rerun_trial(r, robot_urdf=rb.source, heading_deg=h, trace=False)
                d = {
                    "key": f"{pr.trial_key(r)}/heading{h:g}",
                    "success": bool(res.success),
                    "delay_s": res.time_to_right_s - res.attempt_starts_s[0] if res.success else None,
                }
                f.write(json.dumps(d) + "\n")
                f.flush()
                done[d["key"]] = d
    maps: dict[float, list] = {}
    for (tl, phase), r in by_cell.items():
        delay0 = r["time_to_right_s"] - r["attempt_starts_s"][0] if r["success"] else math.nan
        runs = maps.setdefault(tl, [])
        runs.append((phase, 0.0, bool(r["success"]), delay0))
        for h in grid[1:]:
            d = done[f"{pr.trial_key(r)}/heading{float(h):g}"]
            runs.append((phase, float(h), d["success"], math.nan if d["delay_s"] is None else d["delay_s"]))
    return (
        {tl: pr.HeadingMap.from_runs(tl, runs) for tl, runs in maps.items()},
        len(by_cell) * len(grid),
        len(todo),
    )


def prediction_scores(
    rows: list[dict],
    db: Path,
    *,
    states_path: str | Path | None = None,
    robot: str | Path | None = None,
    progress: bool = True,
    headings: int | None = None,
    heading_path: str | Path | None = None,
) -> PredictionScores:
    """The paper's phase-map prediction and the state predictor (:mod:`landscape.analysis.prediction`) on the
    prediction study's trials, both held out, with Wilson 95 % intervals.

    The state predictor needs each trial's opening states: every study trial is rerun with a trace (as stored:
    :func:`landscape.analysis.reruns.rerun_trial`, checked against its stored outcome) and its states appended to ``states_path``
    (default: beside the database, ``DB.opening-states.jsonl``); trials already there are not run again, so an
    interrupted run resumes. The phase and heading map runs the phase map's single attempts at ``headings``
    headings (default :data:`landscape.analysis.prediction.DEFAULT_HEADINGS`) into ``heading_path`` (default
    ``DB.heading-map.jsonl``), resumably too (:func:`heading_maps`).

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
        rb = trials_robot(todo, robot)
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
                d = {"key": key, "reproduced": reproduces(r, res), "states": [st.as_dict() for st in states]}
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
    n_head = pr.DEFAULT_HEADINGS if headings is None else int(headings)
    hpath = Path(heading_path) if heading_path is not None else Path(f"{db}.heading-map.jsonl")
    hmaps, h_runs, h_new = heading_maps(
        rows,
        study,
        sorted({r["leg_period_s"] for r in trials}),
        db,
        headings=n_head,
        path=hpath,
        robot=robot,
        progress=progress,
    )
    states_of = {pr.trial_key(r): sts for r, sts in pairs}
    state_ok, head_ok = [], []
    for r, predicted in state_pred:
        stored = r["attempt"] if r["success"] else None
        b = base[(r["wing_period_s"], r["leg_period_s"], r["phase"])]
        by_heading = pr.first_predicted_by_heading(
            hmaps[r["leg_period_s"]], states_of[pr.trial_key(r)], float(r["duration_s"])
        )
        base_ok.append(b.correct)
        head_ok.append(by_heading == stored)
        state_ok.append(predicted == stored)
        per.append(
            {
                "wing_period_s": r["wing_period_s"],
                "leg_period_s": r["leg_period_s"],
                "phase": r["phase"],
                "simulated_attempt": stored,
                "phase_map_attempt": b.predicted_attempt,
                "heading_map_attempt": by_heading,
                "state_attempt": predicted,
            }
        )
    reproduced = sum(bool(done[pr.trial_key(r)]["reproduced"]) for r in trials)
    return PredictionScores(
        [
            pr.score("phase map", base_ok, held_out=True),
            pr.score("phase and heading map", head_ok, held_out=True),
            pr.score("state", state_ok, held_out=True),
        ],
        study,
        len({(r["wing_period_s"], r["leg_period_s"]) for r in trials}),
        len(trials),
        reproduced,
        len(todo),
        path,
        per,
        h_runs,
        h_new,
        n_head,
        hpath,
    )
