"""The prediction section: the first righting attempt of multi-attempt trials predicted from the phase map, and
from the phase and the state each attempt starts from."""

from __future__ import annotations

import math
import sys
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
            "rest and at 20 phases; a later attempt opens where the failed ones left the robot, nearly still, and at "
            "a phase between the map's (below)."
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
            + ". The second predictor runs, for each attempt, a single attempt from rest at that attempt's own "
            f"phase and the robot's heading when it opens ({res.from_rest_runs} single attempts): the phase map "
            "evaluated where each attempt falls instead of at the nearest of its phases. The heading matters only "
            "to a pybullet set whose friction directions are fixed in the world ([contact] friction_axes = "
            '"world"); by default they turn with the robot, and MuJoCo\'s elliptic cone has none, so no single '
            "attempt depends on it (benchmarks/studies/heading.py). The state predictor (landscape.analysis.prediction) is fitted on the other "
            "settings' trials for each setting it predicts. Both read each attempt's opening state from the "
            f"trials rerun with a trace ({res.reproduced} of {res.reruns} reproduce their stored outcome)."
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
    from_rest_runs, from_rest_new_runs : int
        Single attempts from rest the second predictor used, and how many were run now.
    from_rest_path : Path
        Their file (resumable like ``states_path``).
    """

    scores: list
    setting: tuple[float, float]
    pairs: int
    reruns: int
    reproduced: int
    new_runs: int
    states_path: Path
    per_trial: list
    from_rest_runs: int = 0
    from_rest_new_runs: int = 0
    from_rest_path: Path | None = None


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


class FromRest:
    """Single attempts from rest at the phases and headings attempts open at, run on demand and kept in a
    JSON-lines file (resumable; :func:`landscape.analysis.prediction.first_predicted_from_rest`).

    Each is the scored trial's own row run again with ``attempts=1`` at the attempt's phase (and the robot
    turned to the attempt's heading), so it shares the trial's model set, robot, time step and Tw, and nothing
    of its outcome. The study's trials are noise-free, so attempts of different trials at the same phase and
    heading share one run.
    """

    def __init__(self, path: Path, robot: str | Path | None, *, progress: bool):
        from tqdm import tqdm

        self.path, self.robot = path, robot
        self.done = _read_jsonl(path)
        self.new_runs = 0
        self.used: set[str] = set()
        self._rb = None
        self._bar = tqdm(
            desc="single attempts from rest",
            unit="attempt",
            file=sys.stderr,
            disable=None if progress else True,
        )

    def rights(self, row: dict, state) -> tuple[bool, float]:
        """(rights, time from the opening to upright in s, nan if not) of the single attempt standing for
        ``state``, an attempt of the stored trial ``row``."""
        import json

        from landscape.analysis import prediction as pr

        phase, heading = pr.from_rest_key(state)
        single = {**row, "phase": phase, "attempts": 1, "seed": 0}  # noise-free: the seed draws nothing
        key = f"{pr.trial_key(single)}/heading{heading:.{pr.FROM_REST_ROUND[1]}f}"
        d = self.done.get(key)
        if d is None:
            if self._rb is None:
                self._rb = trials_robot([row], self.robot)
            res = rerun_trial(single, robot_urdf=self._rb.source, heading_deg=heading, trace=False)
            d = {
                "key": key,
                "success": bool(res.success),
                "delay_s": res.time_to_right_s - res.attempt_starts_s[0] if res.success else None,
            }
            self.path.parent.mkdir(parents=True, exist_ok=True)
            with open(self.path, "a") as f:
                f.write(json.dumps(d) + "\n")
            self.done[key] = d
            self.new_runs += 1
            self._bar.update()
        self.used.add(key)
        return bool(d["success"]), math.nan if d["delay_s"] is None else float(d["delay_s"])

    def close(self) -> None:
        self._bar.close()


def prediction_scores(
    rows: list[dict],
    db: Path,
    *,
    states_path: str | Path | None = None,
    robot: str | Path | None = None,
    progress: bool = True,
    from_rest_path: str | Path | None = None,
) -> PredictionScores:
    """The paper's phase-map prediction and the state predictor (:mod:`landscape.analysis.prediction`) on the
    prediction study's trials, both held out, with Wilson 95 % intervals.

    The state predictor needs each trial's opening states: every study trial is rerun with a trace (as stored:
    :func:`landscape.analysis.reruns.rerun_trial`, checked against its stored outcome) and its states appended to ``states_path``
    (default: beside the database, ``DB.opening-states.jsonl``); trials already there are not run again, so an
    interrupted run resumes. The predictor from rest runs the single attempts it needs (:class:`FromRest`) into
    ``from_rest_path`` (default ``DB.from-rest.jsonl``), resumably too.

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
    fpath = Path(from_rest_path) if from_rest_path is not None else Path(f"{db}.from-rest.jsonl")
    runner = FromRest(fpath, robot, progress=progress)
    states_of = {pr.trial_key(r): sts for r, sts in pairs}
    state_ok, rest_ok = [], []
    try:
        for r, predicted in state_pred:
            stored = r["attempt"] if r["success"] else None
            b = base[(r["wing_period_s"], r["leg_period_s"], r["phase"])]
            by_rest = pr.first_predicted_from_rest(
                states_of[pr.trial_key(r)], lambda st, r=r: runner.rights(r, st), float(r["duration_s"])
            )
            base_ok.append(b.correct)
            rest_ok.append(by_rest == stored)
            state_ok.append(predicted == stored)
            per.append(
                {
                    "wing_period_s": r["wing_period_s"],
                    "leg_period_s": r["leg_period_s"],
                    "phase": r["phase"],
                    "simulated_attempt": stored,
                    "phase_map_attempt": b.predicted_attempt,
                    "from_rest_attempt": by_rest,
                    "state_attempt": predicted,
                }
            )
    finally:
        runner.close()
    reproduced = sum(bool(done[pr.trial_key(r)]["reproduced"]) for r in trials)
    return PredictionScores(
        [
            pr.score("phase map", base_ok, held_out=True),
            pr.score("from rest at each opening", rest_ok, held_out=True),
            pr.score("state", state_ok, held_out=True),
        ],
        study,
        len({(r["wing_period_s"], r["leg_period_s"]) for r in trials}),
        len(trials),
        reproduced,
        len(todo),
        path,
        per,
        len(runner.used),
        runner.new_runs,
        fpath,
    )
