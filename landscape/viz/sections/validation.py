"""The validation section: ``landscape physical validate`` outputs, with the recorded openings and leans."""

from __future__ import annotations

from dataclasses import asdict
from pathlib import Path

from landscape.viz.report import Figure, Section, Table
from landscape.viz.sections.data import (
    write_csv,
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
    from landscape.analysis.physical.validation import HELD_OUT_LEGS_DEG, validation_from_json
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
        "Wilson 95 % interval; cells with leg amplitude "
        + " or ".join(f"{leg:g}°" for leg in HELD_OUT_LEGS_DEG)
        + " are held out of any calibration and counted apart."
    )
    for k, doc in enumerate(docs):
        v = validation_from_json(doc)
        engine = doc.get("engine") or "pybullet"
        tag = f"{v.model_set} ({v.model_set_hash})" + ("" if engine == "pybullet" else f" in {engine}")
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
        cells = write_csv(d / "cells.csv", [{c: getattr(x, c) for c in x.CSV_COLUMNS} for x in v.cells])
        att = write_csv(
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
                write_csv(out / "validation" / "resting_pitch.csv", out_rows),
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
                    write_csv(out / "validation" / "hold_body_frame.csv", body_rows),
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
            ms = load_model_set(doc["model_set"]).with_engine(doc.get("engine") or "pybullet")
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

    from landscape.analysis.physical.lean import LEVEL_TILT_DEG, cell_lean, recorded_leans
    from landscape.analysis.physical.response import (
        CLOSING_WINDOW_S,
        ROLLED_TILT_DEG,
        TRANSIENT_WINDOW_S,
        recorded_first_openings,
    )

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
            write_csv(out / "validation" / "hold_frames.csv", frames),
        ),
        Table(
            "First opening of every recorded trial: the leg command's lead, the body's roll while the leg is held "
            "and when it rolled fastest before the opening (the leg's swing), the pitch overshoot, the rise time and "
            "the lateral tilt asin(cos p sin r) of largest magnitude "
            f"{TRANSIENT_WINDOW_S[0]:g}-{TRANSIENT_WINDOW_S[1]:g} s after the opening starts, the tilt when the wings "
            f"start closing ({CLOSING_WINDOW_S[0]:g}-{CLOSING_WINDOW_S[1]:g} s), when it rolled past a tilt of "
            f"{ROLLED_TILT_DEG:g} deg and how far the recorded tilt strays from the gyro's",
            write_csv(out / "validation" / "first_openings.csv", first),
        ),
        Table(
            "Every opening until the robot first rights, leg moving: the held body's median lateral tilt with the "
            "leg settled on + and on - (windows counted), and when the openings that roll over leave the level "
            f"(the tilt last rising through {LEVEL_TILT_DEG:g} deg before passing {ROLLED_TILT_DEG:g} deg; median, s "
            "after the opening starts)",
            write_csv(out / "validation" / "hold_leans.csv", leans),
        ),
    ]
