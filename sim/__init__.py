"""Self-righting trials in pybullet: model (URDF with simplified hulls), world (one DIRECT client per trial),
actuation profiles, trials and sweeps. See docs/sim.md.

Imports point down only: ``sim -> geometry``. pybullet is imported by :mod:`sim.world` alone.
"""

from .actuation import Actuation, attempt_phases, attempt_starts_s, leg_profile_deg, wing_profile_deg
from .model import SimModel, default_robot_urdf, sim_model
from .trial import DEFAULT_DT_S, OTHER_ROBOT_DT_S, Trace, TrialInputError, TrialResult, run_trial
from .world import Contact, SimulationDiverged

__all__ = [
    "Actuation", "attempt_phases", "attempt_starts_s", "leg_profile_deg", "wing_profile_deg",
    "SimModel", "default_robot_urdf", "sim_model",
    "DEFAULT_DT_S", "OTHER_ROBOT_DT_S", "Trace", "TrialInputError", "TrialResult", "run_trial",
    "Contact", "SimulationDiverged",
]
