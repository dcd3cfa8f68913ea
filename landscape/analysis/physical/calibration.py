"""Calibrate a model set against the physical robot's outcomes, with held-out cells.

A calibration is a grid search: every combination of the ``--vary`` values (dotted keys of the model-set TOML,
e.g. ``contact.lateral_friction=0.5,0.75,1``) is written as a candidate set derived from a base set
(:func:`candidate_set`), each candidate is simulated on the *fit* cells only (by default leg amplitudes 0° and
30°) through :func:`landscape.analysis.physical.validation.validate`, and scored by the log-likelihood of the physical
outcomes under its simulated success probabilities. The best candidate is then validated on every cell, so the
held-out cells (15° and 45°), which took no part in the choice, are reported on their own. Each candidate has its
own trial store in the output directory: an interrupted calibration resumes where it stopped.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path

from geometry.errors import UsageError
from landscape.analysis.physical.validation import (
    DEFAULT_CV,
    HELD_OUT_LEGS_DEG,
    SideComparison,
    Validation,
    log_likelihood,
    simulates_commands,
    validate,
)


class CalibrationError(UsageError):
    """A bad ``--vary`` specification or calibration setting."""


Value = float | list[float]
"""One ``--vary`` value: a number, or a list for a key that takes one (``15/12/3``: one per wing command)."""


def format_value(v: Value) -> str:
    """A ``--vary`` value as written: ``0.5``, or a list as ``15/12/3``.

    Examples
    --------
    >>> format_value(0.5), format_value([15.0, 12.0, 3.0])
    ('0.5', '15/12/3')
    """
    return "/".join(f"{x:g}" for x in v) if isinstance(v, list) else f"{v:g}"


def parse_vary(items: Sequence[str], option: str = "--vary") -> dict[str, list[Value]]:
    """``['contact.lateral_friction=0.5,1', ...]`` -> ``{'contact.lateral_friction': [0.5, 1.0], ...}``;
    a value with slashes is a list (``actuation.wing_extra_deg=15/12/3,15/15/3``: two candidates, each with one
    value per wing command); ``option`` names the option in the error messages.

    Examples
    --------
    >>> parse_vary(["contact.lateral_friction=0.5,1"])
    {'contact.lateral_friction': [0.5, 1.0]}
    >>> parse_vary(["actuation.wing_extra_deg=15/12/3,15"])
    {'actuation.wing_extra_deg': [[15.0, 12.0, 3.0], 15.0]}
    """
    out: dict[str, list[Value]] = {}
    for item in items:
        key, sep, values = item.partition("=")
        key = key.strip()
        if not sep or "." not in key or not values.strip():
            raise CalibrationError(
                f"{option} {item!r} is not TABLE.KEY=V1,V2,...; give e.g. {option} contact.lateral_friction=0.5,1"
            )
        try:
            vals = [[float(x) for x in v.split("/")] if "/" in v else float(v) for v in values.split(",")]
        except ValueError:
            raise CalibrationError(
                f"{option} {item!r}: the values must be numbers, e.g. 0.5,1, or lists of numbers, e.g. 15/12/3"
            ) from None
        if not all(math.isfinite(x) for v in vals for x in (v if isinstance(v, list) else [v])):
            raise CalibrationError(f"{option} {item!r}: the values must be finite numbers")
        if key in out:
            raise CalibrationError(f"{option} {key} is given twice; list all its values in one {option}")
        out[key] = vals
    if not out:
        raise CalibrationError(f"nothing to calibrate; give at least one {option} TABLE.KEY=V1,V2,...")
    return out


def parse_with(items: Sequence[str], vary: Sequence[str]) -> dict[str, Value]:
    """``--with TABLE.KEY=V`` options (one value each) -> ``{key: value}``, the keys every ``--vary`` variant also
    sets; empty without items.

    Raises
    ------
    CalibrationError
        If a key has more than one value, or there are items but no ``--vary`` to apply them to.

    Examples
    --------
    >>> parse_with(["compliance.wing_damping_n_m_s_rad=0.001"], ["compliance.wing_stiffness_n_m_rad=0.5,1"])
    {'compliance.wing_damping_n_m_s_rad': 0.001}
    """
    if not items:
        return {}
    fixed = {}
    for key, values in parse_vary(items, "--with").items():
        if len(values) != 1:
            raise CalibrationError(f"--with {key} takes one value; vary it with --vary")
        fixed[key] = values[0]
    if not vary:
        raise CalibrationError("--with sets a key in the --vary variants; give at least one --vary")
    return fixed


def candidate_set(base: str | Path, overrides: dict[str, Value], name: str, path: str | Path):
    """Write the base model set with ``overrides`` (dotted keys that the base already has, or that any set may
    add: ``sim.model_set.OPTIONAL_KEYS``) as ``path`` under ``name`` and return it loaded (so it is validated
    like any set).

    Raises
    ------
    CalibrationError
        If a key is neither in the base set nor optional.
    ModelSetError
        If a value is out of the set's range.
    """
    import tomli_w

    from sim.model_set import OPTIONAL_KEYS, load_model_set, read_toml

    ms = load_model_set(base)
    data = read_toml(ms.source)
    for key, value in overrides.items():
        table, _, leaf = key.rpartition(".")
        node = data
        for part in table.split("."):
            if key in OPTIONAL_KEYS and isinstance(node, dict):  # an optional table the base may lack
                node = node.setdefault(part, {})
            else:
                node = node.get(part) if isinstance(node, dict) else None
        if not isinstance(node, dict) or (leaf not in node and key not in OPTIONAL_KEYS):
            raise CalibrationError(
                f"--vary {key}: the base set '{ms.name}' ({ms.source}) has no such key; vary a key it has, "
                f"e.g. contact.lateral_friction, or one a set may add ({', '.join(sorted(OPTIONAL_KEYS))})"
            )
        old = node.get(leaf)
        if isinstance(value, list):
            node[leaf] = [float(x) for x in value]
        else:
            node[leaf] = int(value) if isinstance(old, int) and float(value).is_integer() else float(value)
    changes = ", ".join(f"{k} = {format_value(v)}" for k, v in overrides.items())
    data["name"] = name
    data["description"] = f"calibration candidate: '{ms.name}' with {changes}"
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(tomli_w.dumps(data))
    return load_model_set(path)


def add_set_options(parser, default_models: str) -> None:
    """Add ``--models A,B``, ``--vary TABLE.KEY=V1,V2`` and ``--with TABLE.KEY=V`` (both repeatable; ``fixed``)
    to an :mod:`argparse` parser: the options :func:`sets_and_variants` reads, as the benchmarks that compare
    model sets and variants of the first take them.

    Examples
    --------
    >>> import argparse
    >>> ap = argparse.ArgumentParser()
    >>> add_set_options(ap, "physical-head")
    >>> a = ap.parse_args(["--vary", "contact.restitution=0.5,0.9"])
    >>> a.models, a.vary, a.fixed
    ('physical-head', ['contact.restitution=0.5,0.9'], [])
    """
    parser.add_argument("--models", default=default_models, help="model sets, comma-separated")
    parser.add_argument(
        "--vary", action="append", default=[], help="TABLE.KEY=V1,V2: variants of the first set"
    )
    parser.add_argument(
        "--with", dest="fixed", action="append", default=[], help="TABLE.KEY=V in every variant"
    )


def sets_and_variants(
    models: str, vary: Sequence[str], fixed: Sequence[str], directory: str | Path
) -> tuple[list[str], list[str]]:
    """The model sets of a ``--models A,B`` option followed by the first one's ``--vary``/``--with`` variants
    (:func:`variant_sets`, files in ``directory``): ``(names or paths to simulate, labels)``; every set is loaded
    first, so an unknown one is reported before any simulation.

    Raises
    ------
    CalibrationError
        If ``models`` names no set or a variant is malformed.
    ModelSetError
        If a set is unknown or a value out of range.
    """
    from sim.model_set import load_model_set

    names = [m for m in models.split(",") if m]
    if not names:
        raise CalibrationError("--models names no model set; give e.g. physical-head")
    labels = [load_model_set(m).name for m in names]
    for label, path in variant_sets(names[0], labels[0], vary, fixed, directory):
        names.append(path)
        labels.append(label)
    return names, labels


def variant_sets(
    base: str | Path, label: str, vary: Sequence[str], fixed: Sequence[str], directory: str | Path
) -> list[tuple[str, str]]:
    """The ``--vary TABLE.KEY=V1,V2`` variants of the set ``base`` (each value on its own, with every ``--with
    TABLE.KEY=V`` of ``fixed``), written as model-set files in ``directory``: ``[(label, path), ...]`` in the
    order of the keys and values, each labelled ``LABEL+WITH_KEY=V...+KEY=V``; empty without ``vary``.

    Raises
    ------
    CalibrationError
        If an option is malformed, ``fixed`` is given without ``vary``, or a key is neither in ``base`` nor
        optional.
    ModelSetError
        If a value is out of the set's range.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     out = variant_sets("paper", "paper", ["contact.lateral_friction=0.5,0.7"], [], tmp)
    >>> [name for name, _ in out]
    ['paper+contact.lateral_friction=0.5', 'paper+contact.lateral_friction=0.7']
    """
    with_values = parse_with(fixed, vary)
    tag = "".join(f"+{k}={format_value(v)}" for k, v in with_values.items())
    out = []
    for key, values in (parse_vary(vary) if vary else {}).items():
        for v in values:
            name = f"{label}{tag}+{key}={format_value(v)}"
            path = Path(directory) / f"v{len(out)}.toml"
            out.append((name, str(candidate_set(base, with_values | {key: v}, name, path).source)))
    return out


@dataclass(frozen=True)
class Candidate:
    """One candidate's score on the fit cells: the log-likelihood of the recorded outcomes and, when openings
    are scored, of the recorded first openings (``landscape.analysis.physical.response.opening_log_likelihood``; nan
    otherwise), and when the side is scored, of the side the robot's roll-overs on the fit cells went to under
    the candidate's simulated side fraction (nan otherwise), and when the time to right is scored, of the robot's
    median times to right under the candidate's (:func:`time_log_likelihood`; nan otherwise). Candidates rank by
    ``score``, their sum."""

    name: str
    overrides: dict
    model_set_hash: str
    log_likelihood: float
    agree: int
    cells: int
    opening_log_likelihood: float = math.nan
    side_log_likelihood: float = math.nan
    time_log_likelihood: float = math.nan

    CSV_COLUMNS = (
        "name", "overrides", "model_set_hash", "log_likelihood", "agree", "cells", "opening_log_likelihood",
        "side_log_likelihood", "time_log_likelihood",
    )  # fmt: skip

    @property
    def score(self) -> float:
        """The outcomes' log-likelihood plus the openings', the side's and the time to right's where they were
        scored."""
        extra = (self.opening_log_likelihood, self.side_log_likelihood, self.time_log_likelihood)
        return self.log_likelihood + sum(x for x in extra if math.isfinite(x))


@dataclass(frozen=True)
class Calibration:
    """A calibration's candidates (best first) and the best candidate's validation on every cell."""

    base: str
    fit_cells: tuple
    candidates: tuple[Candidate, ...]
    best_file: str
    validation: Validation
    engine: str = "pybullet"


def calibrate(
    data_dir: str | Path,
    *,
    out_dir: str | Path,
    vary: dict[str, list[Value]],
    base: str | Path = "physical",
    robot: str | Path | None = None,
    trials: int = 6,
    validate_trials: int = 10,
    cv: float = DEFAULT_CV,
    seed: int = 0,
    fit_legs_deg: Sequence[float] = (0.0, 30.0),
    duration_s: float | None = None,
    workers: int | None = None,
    progress: bool = True,
    on_candidate: Callable[[Candidate, int, int], None] | None = None,
    openings: bool = False,
    opening_phase: float | None = None,
    side: bool = False,
    phase: float | Mapping[tuple[float, float], float] | None = None,
    time_to_right: bool = False,
    engine: str = "pybullet",
) -> Calibration:
    """Grid-search ``vary`` on the fit cells, then validate the best candidate on every cell, every trial (the
    scored openings included) in ``engine``. Candidates rank by score, best first; equal scores keep the order of
    the ``vary`` combinations (the first is the best).

    ``trials`` simulated trials per fit cell and candidate; ``validate_trials`` per cell for the final
    validation. ``on_candidate(candidate, index, total)`` is called as each candidate finishes. With
    ``openings`` each candidate also simulates one first opening per fit cell at ``opening_phase`` (default:
    the protocol's, ``landscape.analysis.physical.response.PROTOCOL_PHASE``; no noise) and adds its log-likelihood under
    the cell's recorded first openings to the score: how the body moves, not only whether it rights. With
    ``side`` it adds the log-likelihood of the side of the robot's roll-overs on the fit cells (how many went to
    +roll, of how many) under the candidate's simulated fraction on the same cells (:func:`side_log_likelihood`).
    ``phase`` puts every simulated trial's first attempt at that phase, or at each cell's own (a mapping such as
    the lab protocol's, :func:`landscape.analysis.physical.response.protocol_phases`), in the candidates' trials and the best
    one's validation alike; None: random phases (:func:`landscape.analysis.physical.validation.validate`). With
    ``time_to_right`` it adds the log-likelihood of the robot's median time to right in each fit cell where both
    right under the candidate's (:func:`time_log_likelihood`), a secondary target.
    """
    from landscape.analysis.physical.outcome import physical_trials
    from landscape.analysis.physical.recording import measured_plateaus_deg
    from landscape.analysis.physical.response import PROTOCOL_PHASE, recorded_first_openings

    out_dir = Path(out_dir)
    fit_legs = {float(x) for x in fit_legs_deg}
    if fit_legs & set(HELD_OUT_LEGS_DEG):
        raise CalibrationError(
            f"--fit-legs {sorted(fit_legs)} includes a held-out leg amplitude {HELD_OUT_LEGS_DEG}; fit on the "
            "others (default 0,30) so that the held-out cells stay unseen"
        )
    cells = sorted({(t.theta_w_cmd_deg, t.theta_l_deg) for t in physical_trials(data_dir)})
    fit_cells = [c for c in cells if c[1] in fit_legs]
    if not fit_cells:
        raise CalibrationError(f"no recorded cell has a leg amplitude in --fit-legs {sorted(fit_legs)}")
    scored_phase = PROTOCOL_PHASE if opening_phase is None else float(opening_phase)
    if not 0.0 <= scored_phase < 1.0:
        raise CalibrationError(f"the openings' phase must lie in [0, 1); got {scored_phase!r}")
    recorded = {}
    if openings:
        for o in recorded_first_openings(data_dir):
            recorded.setdefault((o.theta_w_cmd_deg, o.theta_l_deg), []).append(o.response)
        plateau = measured_plateaus_deg(data_dir)
    keys = list(vary)
    combos = list(itertools.product(*(vary[k] for k in keys)))
    scored = []
    for i, values in enumerate(combos):
        overrides = dict(zip(keys, values, strict=True))
        name = f"candidate{i:03d}"
        ms = candidate_set(base, overrides, name, out_dir / "candidates" / f"{name}.toml").with_engine(engine)
        v, _ = validate(
            data_dir, db=out_dir / f"trials_{name}_{ms.model_set_hash}.sqlite", robot=robot,
            model_set=ms.source, trials=trials, cv=cv, seed=seed, cells=fit_cells, duration_s=duration_s,
            workers=workers, progress=progress, phase=phase, engine=engine,
        )  # fmt: skip
        k, n = v.agree_counts["all"]
        opening_ll = math.nan
        if openings:
            opening_ll = _openings_log_likelihood(
                ms.source, fit_cells, recorded, plateau, scored_phase, seed, robot, engine
            )
        side_ll = side_log_likelihood(v.side) if side else math.nan
        time_ll = time_log_likelihood(v.cells) if time_to_right else math.nan
        cand = Candidate(
            name, overrides, ms.model_set_hash, v.log_likelihood["all"], k, n, opening_ll, side_ll, time_ll
        )
        scored.append(cand)
        if on_candidate is not None:
            on_candidate(cand, i + 1, len(combos))
    scored.sort(key=lambda c: -c.score)
    best = scored[0]
    best_file = out_dir / "best.toml"
    ms = candidate_set(base, best.overrides, f"{Path(str(base)).stem}-calibrated", best_file)
    ms = ms.with_engine(engine)
    v, _ = validate(
        data_dir, db=out_dir / f"trials_best_{ms.model_set_hash}.sqlite", robot=robot, model_set=best_file,
        trials=validate_trials, cv=cv, seed=seed + 1, duration_s=duration_s, workers=workers, progress=progress,
        phase=phase, engine=engine,
    )  # fmt: skip
    return Calibration(str(base), tuple(fit_cells), tuple(scored), str(best_file), v, engine)


def side_log_likelihood(side: SideComparison) -> float:
    """Log-likelihood of the robot's roll-overs to +roll (``side.phys_positive`` of ``side.phys_events``) under
    the simulated fraction, shrunk as the outcomes' are (:func:`landscape.analysis.physical.validation.log_likelihood`);
    0 when either side has no roll-overs (no evidence either way).

    Examples
    --------
    >>> from landscape.analysis.physical.validation import SideComparison
    >>> round(side_log_likelihood(SideComparison(17, 18, 0, 0, 30, 40, 0, 0, False)), 2)
    -6.39
    """
    if not side.phys_events or not side.sim_events:
        return 0.0
    return log_likelihood([(side.phys_positive, side.phys_events, side.sim_positive, side.sim_events)])


TIME_SD_LOG = 0.35
"""Spread of a cell's median time to right, robot against simulation, in :func:`time_log_likelihood`: the
standard deviation of its logarithm (a factor of exp(0.35), about 1.4)."""
TIME_Z_CAP = 4.0
"""Largest deviation, in ``TIME_SD_LOG``, that one cell counts in :func:`time_log_likelihood`."""


def time_log_likelihood(cells) -> float:
    """Log-likelihood of the robot's median time to right under the simulation's, summed over the cells where both
    right: ``-z^2 / 2`` with ``z = log(robot / simulated) / TIME_SD_LOG`` (capped at ``TIME_Z_CAP``); cells where
    either never rights add nothing (the outcomes' likelihood scores those). 0 without such a cell.

    Examples
    --------
    >>> from types import SimpleNamespace as C
    >>> round(time_log_likelihood([C(phys_ttr_median_s=0.35, sim_ttr_median_s=1.15),
    ...                            C(phys_ttr_median_s=1.1, sim_ttr_median_s=float("nan"))]), 2)
    -5.78
    >>> time_log_likelihood([C(phys_ttr_median_s=0.35, sim_ttr_median_s=0.35)]) == 0.0
    True
    """
    total = 0.0
    for c in cells:
        robot, sim = c.phys_ttr_median_s, c.sim_ttr_median_s
        if math.isfinite(robot) and math.isfinite(sim) and robot > 0 and sim > 0:
            z = min(abs(math.log(robot / sim)) / TIME_SD_LOG, TIME_Z_CAP)
            total -= 0.5 * z * z
    return total


def _openings_log_likelihood(model_set, cells, recorded, plateau, phase, seed, robot, engine) -> float:
    """Sum over ``cells`` of one simulated first opening's (in ``engine``) log-likelihood under the cell's recorded
    ones."""
    from landscape.analysis.physical.response import opening_log_likelihood, simulated_opening

    measured = simulates_commands(model_set)
    total = 0.0
    for w, leg in cells:
        w_sim = w if measured else plateau[w]
        sim = simulated_opening(
            w_sim, leg, phase=phase, seed=seed, robot=robot, model_set=model_set, engine=engine
        )
        total += opening_log_likelihood(recorded[(w, leg)], sim)
    return total
