"""Everything ``landscape physical kinematics`` shows, as one value: where the body holds while the wings are open
(robot against model, in two frames), how each first opening moves the body, the protocol's leg phases, the held
body's lean with the leg swinging, and to which side the robot rolls over."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from landscape.analysis.physical.cells import Lateralisation, lateralisation
from landscape.analysis.physical.hold import (
    HoldFrame,
    hold_pitch_frames,
    per_servo_hold_deg,
    plateau_hold_deg,
    support_links,
)
from landscape.analysis.physical.lean import CellLean, cell_lean, recorded_leans
from landscape.analysis.physical.measured import LEG_PULSE_FILE, MeasuredDataError, leg_crossing_lag_s
from landscape.analysis.physical.mounting import RestMounting, mounting_from_rests
from landscape.analysis.physical.outcome import physical_trials
from landscape.analysis.physical.response import RecordedOpening, protocol_phases, recorded_first_openings
from landscape.analysis.physical.resting import RestingPitch, resting_pitch_table


@dataclass(frozen=True)
class ModelHold:
    """The model's hold beside the robot's.

    Attributes
    ----------
    name, source : str
        The model robot's name and file.
    hold_minus_rest_deg : list of float
        Per recorded wing command (:attr:`Kinematics.resting`'s order), the model's metastable pitch with every
        wing joint at the measured plateau minus its pitch at theta_w = 0, degrees.
    servo_model_set : str or None
        The model set whose measured actuation posed each wing servo at its own measured plateau for ``frames``;
        None when every wing joint was posed at the measured plateau.
    frames : list of HoldFrame
        The recorded hold against the model's in the IMU's frame and relative to each trial's rest.
    mounting : RestMounting
        The IMU's mounting measured from the two rests.
    closed_on : list of str
        The links the model rests on with its wings closed.
    """

    name: str
    source: str
    hold_minus_rest_deg: list[float]
    servo_model_set: str | None
    frames: list[HoldFrame]
    mounting: RestMounting
    closed_on: list[str]


@dataclass(frozen=True)
class Kinematics:
    """The robot's recorded kinematics, and the model's beside them.

    Attributes
    ----------
    resting : list of RestingPitch
        The body's pitch while the wings are held open, leg still, per wing command.
    model : ModelHold or None
        The model's hold (None without a model).
    first_openings : list of RecordedOpening
        The first opening of every trial.
    leg_phases : list of (float, float) or None
        The first attempt's leg phase under the protocol per leg amplitude (degrees, phase), sorted; None when
        the leg's recording is absent or unreadable (``leg_phase_error`` says why).
    leg_lag_s : dict of float to float or None
        The measured leg's lag from its command to the midline per leg amplitude, s.
    leg_phase_error : str or None
        Why the leg phases are not measured.
    leans : list of CellLean
        The held body's lean per recorded cell with the leg moving.
    lateralisation : Lateralisation
        To which side the robot rolls over.
    """

    resting: list[RestingPitch]
    model: ModelHold | None
    first_openings: list[RecordedOpening]
    leg_phases: list[tuple[float, float]] | None
    leg_lag_s: dict[float, float] | None
    leg_phase_error: str | None
    leans: list[CellLean]
    lateralisation: Lateralisation


def model_hold(robot, data_dir: str | Path, commands_deg: list[float], *, measured=None) -> ModelHold:
    """The model's hold at each measured wing plateau, and the frames that compare it with the recorded one.

    Parameters
    ----------
    robot : geometry.Robot
        The model, its CoM where its model set puts it.
    data_dir : str or Path
        The lab's data directory.
    commands_deg : list of float
        The recorded wing commands, degrees.
    measured : sim.actuation.MeasuredActuation, optional
        A model set's measured actuation: each wing servo is posed at its own plateau for the frames.

    Raises
    ------
    landscape.analysis.physical.recording.PhysicalDataError
        If the directory or a file is not in the lab's format.
    """
    from landscape.minima import metastable_orientation

    rest = metastable_orientation(robot, 0.0, 0.0)
    equal = plateau_hold_deg(robot, data_dir, commands_deg)  # every wing joint at the measured plateau
    hold = per_servo_hold_deg(robot, measured, commands_deg) if measured is not None else equal
    return ModelHold(
        robot.name,
        str(robot.source),
        [equal[c] - rest[0] for c in commands_deg],
        None,
        hold_pitch_frames(data_dir, hold, rest[0]),
        mounting_from_rests(data_dir, robot),
        support_links(robot.pose(0.0, 0.0), *rest),
    )


def kinematics(data_dir: str | Path, *, robot=None, model_set=None) -> Kinematics:
    """The robot's recorded kinematics (:class:`Kinematics`), with the model's hold when ``robot`` is given.

    Parameters
    ----------
    data_dir : str or Path
        The lab's data directory.
    robot : geometry.Robot, optional
        The model; None: the recordings only.
    model_set : sim.model_set.ModelSet, optional
        Moves the model's CoM as the set does and, with a measured actuation, poses each wing servo at its own
        plateau.

    Raises
    ------
    landscape.analysis.physical.recording.PhysicalDataError
        If the directory or a file is not in the lab's format.
    """
    resting = resting_pitch_table(data_dir)
    model = None
    if robot is not None:
        measured = None
        if model_set is not None:
            robot = model_set.robot_for(robot)  # the set's CoM, if it moves one
            measured = model_set.measured
        model = model_hold(robot, data_dir, [row.theta_w_cmd_deg for row in resting], measured=measured)
        if measured is not None:
            model = ModelHold(**{**model.__dict__, "servo_model_set": model_set.name})
    first = recorded_first_openings(data_dir)
    phases = lag = error = None
    try:
        lag = leg_crossing_lag_s(Path(data_dir) / LEG_PULSE_FILE)
        phases = sorted({(leg, round(p, 3)) for (_, leg), p in protocol_phases(data_dir).items()})
    except MeasuredDataError as exc:  # a folder without the leg's trace still gets every other table
        lag, error = None, str(exc)
    leans = [cell_lean(*cell, h) for cell, h in recorded_leans(data_dir).items()]
    return Kinematics(
        resting, model, first, phases, lag, error, leans, lateralisation(physical_trials(data_dir))
    )
