"""Files and tables of the physical robot's trials (:mod:`landscape.analysis.physical`): CSV and markdown."""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from itertools import groupby
from pathlib import Path

import numpy as np


def _fmt(v) -> str:
    if isinstance(v, bool):
        return str(int(v))
    if isinstance(v, float):
        return "" if math.isnan(v) else f"{v:.6g}"
    return str(v)


def write_rows_csv(rows: Sequence, path: str | Path) -> Path:
    """Write frozen dataclasses with a ``CSV_COLUMNS`` attribute as CSV (booleans 0/1, nan as empty)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    cols = type(rows[0]).CSV_COLUMNS if rows else ()
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(cols)
        for r in rows:
            w.writerow([_fmt(getattr(r, c)) for c in cols])
    return path


def _pct(x: float) -> str:
    return f"{100 * x:.0f}"


def cells_table(cells: Sequence, attempts: Sequence = ()) -> str:
    """Markdown table of :class:`~landscape.analysis.physical.cells.PhysicalCell` (and per-attempt rates)."""
    lines = [
        "| wing cmd (measured) | leg | righted | Wilson 95 % | median time to right |",
        "|---|---|---|---|---|",
    ]
    for c in cells:
        t = "" if math.isnan(c.median_time_to_right_s) else f"{c.median_time_to_right_s:.2f} s"
        lines.append(
            f"| {c.theta_w_cmd_deg:g}° ({c.theta_w_measured_deg:.1f}°) | {c.theta_l_deg:g}° | "
            f"{c.successes}/{c.n} | [{_pct(c.ci_low)}, {_pct(c.ci_high)}] % | {t} |"
        )
    if attempts:
        lines += [
            "",
            "| wing cmd (measured) | successful attempts | rate | Wilson 95 % |",
            "|---|---|---|---|",
        ]
        for a in attempts:
            lines.append(
                f"| {a.theta_w_cmd_deg:g}° ({a.theta_w_measured_deg:.1f}°) | {a.successes}/{a.attempts} | "
                f"{_pct(a.p)} % | [{_pct(a.ci_low)}, {_pct(a.ci_high)}] % |"
            )
    return "\n".join(lines)


def resting_pitch_markdown(rows: Sequence, model_deg: Sequence[float] | None = None) -> str:
    """Markdown table of :class:`~landscape.analysis.physical.resting.RestingPitch`, beside the model's pitch."""
    head = "| wing command | measured plateau | robot, median [IQR] (n) | first openings | closed again |"
    rule = "|---|---|---|---|---|"
    if model_deg is not None:
        head += " model's metastable pitch | model - robot |"
        rule += "---|---|"
    lines = [head, rule]
    for k, r in enumerate(rows):
        line = (
            f"| {r.theta_w_cmd_deg:g}° | {r.theta_w_measured_deg:.1f}° | {r.median_deg:.1f}° "
            f"[{r.q25_deg:.1f}, {r.q75_deg:.1f}] ({r.n}) | {r.first_opening_median_deg:.1f}° | {r.closed_median_deg:.1f}° |"
        )
        if model_deg is not None:
            line += f" {model_deg[k]:.1f}° | {model_deg[k] - r.median_deg:+.1f}° |"
        lines.append(line)
    return "\n".join(lines)


def hold_frames_markdown(rows: Sequence) -> str:
    """Markdown table of :class:`~landscape.analysis.physical.hold.HoldFrame` rows (first openings, leg still)."""
    lines = [
        "| wing command | n | robot, IMU frame (sd) | robot, minus its rest (sd) | rest sd | model | "
        "robot - mounting - model | same, mounting fitted on the other commands |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r.theta_w_cmd_deg:g}° | {r.n} | {r.recorded_deg:.1f}° ({r.recorded_sd_deg:.1f}°) | "
            f"{r.relative_deg:.1f}° ({r.relative_sd_deg:.1f}°) | {r.rest_sd_deg:.1f}° | {r.model_deg:.1f}° | "
            f"{r.residual_deg:+.1f}° | {r.residual_held_out_deg:+.1f}° |"
        )
    if rows:
        lines.append(
            f"\nIMU mounting (recorded minus model, mean over the commands): {rows[0].offset_deg:.1f}°; the model's "
            f"rest with the wings closed: {rows[0].model_rest_deg:.1f}°"
        )
    return "\n".join(lines)


def rest_mounting_markdown(frames: Sequence, mounting) -> str:
    """The IMU's mounting measured from the robot's two rests (:class:`~landscape.analysis.physical.mounting.RestMounting`)
    as one line, then a Markdown table of the first openings' hold (:class:`~landscape.analysis.physical.hold.HoldFrame`
    rows) in the body frame that mounting gives, beside the model's: the resting-pose check."""
    m = mounting
    lines = [
        f"IMU mounting from the two rests ({m.n} righted trials; recorded on its back {m.recorded_back_deg:+.1f}°, "
        f"upright {m.recorded_upright_deg:+.1f}°; model {m.model_back_deg:+.1f}°, {m.model_upright_deg:+.1f}°): "
        f"{m.mount_deg:.1f}° [{m.mount_q25_deg:.1f}, {m.mount_q75_deg:.1f}]",
        "",
        "| wing command | robot, IMU frame | robot, body frame | model | model - robot |",
        "|---|---|---|---|---|",
    ]
    for r in frames:
        body = r.recorded_deg - m.mount_deg
        lines.append(
            f"| {r.theta_w_cmd_deg:g}° | {r.recorded_deg:.1f}° | {body:.1f}° | {r.model_deg:.1f}° | "
            f"{r.model_deg - body:+.1f}° |"
        )
    return "\n".join(lines)


def first_openings_markdown(openings: Sequence) -> str:
    """Markdown table of the recorded first openings per cell (:class:`~landscape.analysis.physical.response.RecordedOpening`):
    medians of the leg command's lead, the overshoot, the rise and the lateral tilt (with its range), the tilt when
    the wings start closing (with its range), how many rolled past a tilt of ``ROLLED_TILT_DEG`` (median time) and how far the
    recorded tilt strays from the gyro's (median)."""
    from landscape.analysis.physical.response import ROLLED_TILT_DEG

    cells: dict[tuple[float, float], list] = {}
    for o in openings:
        cells.setdefault((o.theta_w_cmd_deg, o.theta_l_deg), []).append(o)
    lines = [
        "| wing command | leg | n | leg command's lead | roll, leg held | body's fastest roll before | overshoot "
        f"| rise | lateral tilt [range] | tilt at closing [range] | rolled past {ROLLED_TILT_DEG:g}° "
        "| gyro against recorded tilt |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for (w, leg), os_ in sorted(cells.items()):
        lead = [o.leg_lead_s for o in os_ if math.isfinite(o.leg_lead_s)]
        swing = [o.leg_swing_s for o in os_ if math.isfinite(o.leg_swing_s)]
        held = [o.leg_hold_roll_deg for o in os_ if math.isfinite(o.leg_hold_roll_deg)]
        tilt = [o.response.tilt_deg for o in os_]
        closing = [o.response.closing_tilt_deg for o in os_]
        rolled = [o.response.rolled_s for o in os_ if math.isfinite(o.response.rolled_s)]
        gyro = [o.gyro_deviation_deg for o in os_ if math.isfinite(o.gyro_deviation_deg)]
        lines.append(
            f"| {w:g}° | {leg:g}° | {len(os_)} | "
            + (f"{float(np.median(lead)):.1f} s" if lead else "–")
            + " | "
            + (f"{float(np.median(held)):+.2f}°" if held else "–")
            + " | "
            + (f"{float(np.median(swing)):.2f} s" if swing else "–")
            + f" | {float(np.median([o.response.overshoot_deg for o in os_])):+.1f}° | "
            f"{float(np.median([o.response.rise_s for o in os_])):.2f} s | {float(np.median(tilt)):+.1f}° "
            f"[{min(tilt):+.1f}, {max(tilt):+.1f}] | {float(np.median(closing)):+.1f}° "
            f"[{min(closing):+.1f}, {max(closing):+.1f}] | {len(rolled)}/{len(os_)}"
            + (f" at {float(np.median(rolled)):.2f} s" if rolled else "")
            + " | "
            + (f"{float(np.median(gyro)):.1f}°" if gyro else "–")
            + " |"
        )
    return "\n".join(lines)


def lean_text(value_deg: float, n: int) -> str:
    """A median lean and its number of windows, e.g. ``+7.8° (3)``; ``– (0)`` without a window."""
    return f"{value_deg:+.1f}° ({n})" if n else "– (0)"


def departure_text(cell) -> str:
    """A :class:`~landscape.analysis.physical.lean.CellLean`'s median departure and rolled/openings, e.g.
    ``0.81 s (6/8)``; ``(0/3)`` if none rolled over."""
    at = f"{cell.departure_s:.2f} s " if cell.n_rolled else ""
    return f"{at}({cell.n_rolled}/{cell.n_openings})"


def hold_leans_markdown(cells: Sequence) -> str:
    """Markdown table of the recorded held body's lean with the leg on each side and the departure of the
    openings that roll over, per cell (:class:`~landscape.analysis.physical.lean.CellLean`).

    Examples
    --------
    >>> from landscape.analysis.physical.lean import CellLean
    >>> print(hold_leans_markdown([CellLean(60.0, 30.0, 7.8, 3, -1.0, 7, 0.81, 6, 8),
    ...                            CellLean(90.0, 45.0, math.nan, 0, math.nan, 0, 0.28, 5, 5)]))
    | wing command | leg | lean, leg on + | lean, leg on − | roll-overs leave the level |
    |---|---|---|---|---|
    | 60° | 30° | +7.8° (3) | -1.0° (7) | 0.81 s (6/8) |
    | 90° | 45° | – (0) | – (0) | 0.28 s (5/5) |
    """
    lines = [
        "| wing command | leg | lean, leg on + | lean, leg on − | roll-overs leave the level |",
        "|---|---|---|---|---|",
    ]
    for c in cells:
        lines.append(
            f"| {c.theta_w_cmd_deg:g}° | {c.theta_l_deg:g}° | {lean_text(c.plus_deg, c.n_plus)} | "
            f"{lean_text(c.minus_deg, c.n_minus)} | {departure_text(c)} |"
        )
    return "\n".join(lines)


def robot_rule_text(v) -> str:
    """How the robot's trials were judged when not as recorded: ``--robot-attempts N`` (the rightings after its
    first N openings it left out) and ``--imu-mounting DEG``; '' when as recorded."""
    parts = []
    if v.robot_attempts is not None:
        late = sorted(v.late_rightings)
        where = "; ".join(
            f"{w:g}°/{leg:g}° at opening {', '.join(str(a) for _, _, a in group)}"
            for (w, leg), group in groupby(late, key=lambda x: (x[0], x[1]))
        )
        parts.append(
            f"robot trials counted as righted within their first {v.robot_attempts} openings (--robot-attempts): "
            + (f"{len(late)} later rightings left out ({where})" if late else "no later rightings")
        )
    if v.imu_mount_deg:
        parts.append(
            f"the robot judged upright in a body frame pitched {v.imu_mount_deg:g}° below its IMU's (--imu-mounting)"
        )
    return "; ".join(parts)


def consistent_text(v) -> str:
    """How many cells the trials cannot tell apart (Fisher's exact test, :data:`landscape.analysis.trials.CONSISTENT_P`), all and
    per split, and the cells that differ with their p-values; '' for a validation stored without the test."""
    from landscape.analysis.trials import CONSISTENT_P

    cells = [c for c in v.cells if math.isfinite(c.fisher_p)]
    if not cells or len(cells) < len(v.cells):
        return ""
    ok = [c for c in cells if c.fisher_p >= CONSISTENT_P]
    per = ", ".join(
        f"{split} {sum(c.fisher_p >= CONSISTENT_P for c in cells if c.split == split)} of "
        f"{sum(c.split == split for c in cells)}"
        for split in ("fit", "held-out")
        if any(c.split == split for c in cells)
    )
    apart = "; ".join(
        f"{c.theta_w_cmd_deg:g}°/{c.theta_l_deg:g}° p = {c.fisher_p:.3f}"
        for c in cells
        if c.fisher_p < CONSISTENT_P
    )
    return (
        f"cells the trials cannot tell apart (Fisher's exact test, p >= {CONSISTENT_P:g}): {len(ok)} of {len(cells)} "
        f"({per})" + (f"; apart: {apart}" if apart else "")
    )


def _frac(k: int, n: int, lo: float, hi: float) -> str:
    return f"{k}/{n} [{_pct(lo)}, {_pct(hi)}] %"


def _ttr(med: float, sd: float) -> str:
    if math.isnan(med):
        return "–"
    return f"{med:.2f}" + ("" if math.isnan(sd) else f" ± {sd:.2f}") + " s"


def validation_markdown(v) -> str:
    """Markdown tables of a :class:`~landscape.analysis.physical.validation.Validation`: cells by split, the per-attempt
    rates, the side and the totals."""
    lines = [f"model set: {v.model_set} ({v.model_set_hash})", ""]
    head = (
        "| wing cmd (simulated at) | leg | physical righted [Wilson 95 %] | simulated righted [Wilson 95 %] | agree |"
        " physical time to right | simulated time to right |"
    )
    for split in ("fit", "held-out"):
        cells = [c for c in v.cells if c.split == split]
        if not cells:
            continue
        k, n = v.agree_counts[split]
        lines += [f"{split} cells: {k} of {n} agree (log-likelihood {v.log_likelihood[split]:.2f})", "", head]
        lines.append("|---|---|---|---|---|---|---|")
        for c in cells:
            lines.append(
                f"| {c.theta_w_cmd_deg:g}° ({c.theta_w_sim_deg:.1f}°) | {c.theta_l_deg:g}° | "
                f"{_frac(c.phys_k, c.phys_n, c.phys_low, c.phys_high)} | "
                f"{_frac(c.sim_k, c.sim_n, c.sim_low, c.sim_high)} | {'yes' if c.agree else 'NO'} | "
                f"{_ttr(c.phys_ttr_median_s, c.phys_ttr_sd_s)} | {_ttr(c.sim_ttr_median_s, c.sim_ttr_sd_s)} |"
            )
        lines.append("")
    k, n = v.agree_counts["all"]
    lines.append(f"all cells: {k} of {n} agree (log-likelihood {v.log_likelihood['all']:.2f})")
    lines += [t for t in (consistent_text(v), robot_rule_text(v)) if t]
    if v.attempts:
        lines += [
            "",
            "| wing cmd | physical attempts righting [Wilson 95 %] | simulated [Wilson 95 %] | agree |",
            "|---|---|---|---|",
        ]
        for a in v.attempts:
            p, s = a.physical, a.simulated
            lines.append(
                f"| {a.theta_w_cmd_deg:g}° | {_frac(p.successes, p.attempts, p.ci_low, p.ci_high)} | "
                f"{_frac(s.successes, s.attempts, s.ci_low, s.ci_high)} | {'yes' if a.agree else 'NO'} |"
            )
    s = v.side
    sim = _frac(s.sim_positive, s.sim_events, s.sim_low, s.sim_high) if s.sim_events else "no righting events"
    lines += [
        "",
        f"righting to + roll: physical {_frac(s.phys_positive, s.phys_events, s.phys_low, s.phys_high)}, "
        f"simulated {sim}; inside the physical interval: {'yes' if s.sim_inside_phys else 'no'}",
    ]
    return "\n".join(lines)


def time_to_right_figure(v, path: str | Path) -> Path:
    """Median time to right ± s.d. per cell, physical beside simulated (the source paper's Fig. 4(c) analogue),
    PNG and SVG; held-out cells hatched. ``v``: a :class:`~landscape.analysis.physical.validation.Validation`."""
    from landscape.viz._mpl import plt, save

    cells = list(v.cells)
    x = list(range(len(cells)))
    fig, ax = plt.subplots(figsize=(max(6.0, 0.6 * len(cells) + 2), 3.6), dpi=150)
    for off, who, color in ((-0.18, "phys", "0.25"), (0.18, "sim", "tab:blue")):
        med = [getattr(c, f"{who}_ttr_median_s") for c in cells]
        sd = [getattr(c, f"{who}_ttr_sd_s") for c in cells]
        sd = [0.0 if math.isnan(e) else e for e in sd]
        label = "physical robot" if who == "phys" else f"simulation ({v.model_set})"
        bars = ax.bar([i + off for i in x], [0.0 if math.isnan(m) else m for m in med], 0.36, yerr=sd,
                      color=color, label=label, capsize=2)  # fmt: skip
        for b, c in zip(bars, cells, strict=True):
            if c.split == "held-out":
                b.set_hatch("//")
    ax.set_xticks(x, [f"{c.theta_w_cmd_deg:g}/{c.theta_l_deg:g}" for c in cells], fontsize=7)
    ax.set_xlabel("wing command / leg amplitude (deg); hatched: held-out cells")
    ax.set_ylabel("time to right (s), median ± s.d.")
    ax.legend(fontsize=7)
    fig.tight_layout()
    return save(fig, path, svg_too=True)


def kinematics_text(k) -> list[str]:
    """The blocks ``landscape physical kinematics`` prints for a
    :class:`~landscape.analysis.physical.kinematics.Kinematics`, captions from the analyses' constants."""
    from landscape.analysis.physical.lean import LEAN_SETTLE_S, LEAN_WINDOW_S, LEVEL_TILT_DEG
    from landscape.analysis.physical.measured import LEG_PERIOD_S, LEG_PULSE_FILE
    from landscape.analysis.physical.response import (
        CLOSING_WINDOW_S,
        ROLLED_TILT_DEG,
        SIM_OPENING_S,
        TRANSIENT_WINDOW_S,
    )
    from landscape.analysis.physical.resting import HOLD_WINDOW_S, REST_WINDOW_S

    m = k.model
    out = []
    if m is not None:
        out.append(f"model: {m.name} ({m.source}); pitch at each measured plateau minus pitch at theta_w = 0")
    out.append(
        f"pitch {HOLD_WINDOW_S[0]:g}-{HOLD_WINDOW_S[1]:g} s after each opening starts minus the rest in the "
        f"{REST_WINDOW_S:g} s before the first opening (leg amplitude 0, openings before the robot first becomes "
        "upright)"
    )
    out.append(resting_pitch_markdown(k.resting, None if m is None else m.hold_minus_rest_deg))
    if m is not None:
        how = (
            "every wing joint at the measured plateau"
            if m.servo_model_set is None
            else f"each wing servo at its own measured plateau (model set {m.servo_model_set})"
        )
        out.append(
            "\nfirst openings only, leg still: the recorded hold in the IMU's frame and minus each trial's rest; the "
            f"model's hold with {how}; the IMU's mounting fitted as one constant"
        )
        out.append(hold_frames_markdown(m.frames))
        out.append(f"the model rests with the wings closed on: {', '.join(m.closed_on)}")
        out.append(
            "\nthe same holds in the body frame: the recorded hold minus the IMU's mounting measured from the rests "
            "on its back (before the first opening) and upright (after righting), which the hold does not enter"
        )
        out.append(rest_mounting_markdown(m.frames, m.mounting))
    out.append(
        "\nfirst opening of every trial: the leg command's last rise before it (servo log, 10 Hz), the body's "
        "roll while the leg is held at its first command before it, when the body rolled fastest before it (the "
        "leg's swing), the pitch overshoot past the hold, the rise time to half the hold, the lateral tilt "
        f"asin(cos p sin r) of largest magnitude {TRANSIENT_WINDOW_S[0]:g}-{TRANSIENT_WINDOW_S[1]:g} s after the "
        "opening starts, the tilt when the wings start closing "
        f"({CLOSING_WINDOW_S[0]:g}-{CLOSING_WINDOW_S[1]:g} s), the openings that rolled past a tilt of "
        f"{ROLLED_TILT_DEG:g} deg within {SIM_OPENING_S:g} s, and how far the recorded tilt strays from the tilt "
        f"the gyro alone gives, {-REST_WINDOW_S:g} to {CLOSING_WINDOW_S[1]:g} s (medians)"
    )
    out.append(first_openings_markdown(k.first_openings))
    if k.leg_phases is None:
        out.append(f"the first attempt's leg phase under the protocol: not measured ({k.leg_phase_error})")
    else:
        out.append(
            "the first attempt's leg phase under the protocol (validate --phase protocol): "
            + ", ".join(f"leg {leg:g}° {p:.3f}" for leg, p in k.leg_phases)
            + " (the leg command's lead above minus the measured leg's lag from its command to the midline, "
            + ", ".join(f"{k.leg_lag_s[leg]:.3f} s" for leg, _ in k.leg_phases)
            + f" ({LEG_PULSE_FILE}), over its {LEG_PERIOD_S:g} s period)"
        )
    out.append(
        "\nevery opening until the robot first rights, leg moving: the held body's median lateral tilt in each window "
        f"with the leg settled on one side ({LEAN_SETTLE_S:g} s after it gets there, "
        f"{LEAN_WINDOW_S[0]:.1f}-{LEAN_WINDOW_S[1]:.1f} s after the opening starts; windows in brackets) and, for "
        f"the openings that roll over, when the tilt last rose through {LEVEL_TILT_DEG:g} deg before passing "
        f"{ROLLED_TILT_DEG:g} deg (median, s after the opening starts; rolled/openings)"
    )
    out.append(hold_leans_markdown(k.leans))
    out.append(
        "\n"
        + lateralisation_text(k.lateralisation)
        + "; a mirror-symmetric model has 50 % over random phases"
    )
    return out


def lateralisation_text(lat) -> str:
    """The side the robot rolls over to (:class:`~landscape.analysis.physical.cells.Lateralisation`), one line.

    Examples
    --------
    >>> from landscape.analysis.physical.cells import Lateralisation
    >>> lateralisation_text(Lateralisation(3, 1, 0.75, 0.3, 0.95))
    'roll-overs to + roll: 3 of 4 (Wilson 95 % [30, 95] %)'
    """
    return (
        f"roll-overs to + roll: {lat.positive} of {lat.positive + lat.negative} "
        f"(Wilson 95 % [{100 * lat.ci_low:.0f}, {100 * lat.ci_high:.0f}] %)"
    )
