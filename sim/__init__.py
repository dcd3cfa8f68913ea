"""Self-righting trials in pybullet or MuJoCo: model (URDF with simplified hulls), world (one engine instance per
trial, behind :class:`sim.engine.EngineWorld`), actuation profiles, trials and sweeps. See docs/sim.md.

Imports point down only: ``sim -> geometry``. pybullet is imported by :mod:`sim.world` and mujoco by
:mod:`sim.mujoco_world` alone, and names below load on first use (PEP 562), so ``sim.protocol``, ``sim.engine``
and ``sim.actuation`` are cheap to import.
"""

from __future__ import annotations

import importlib

_EXPORTS = {
    **dict.fromkeys(
        ("Actuation", "attempt_phases", "attempt_starts_s", "leg_profile_deg", "wing_profile_deg"),
        "sim.actuation",
    ),
    **dict.fromkeys(("SimModel", "default_robot_urdf", "sim_model"), "sim.model"),
    **dict.fromkeys(("DEFAULT_DT_S", "OTHER_ROBOT_DT_S"), "sim.protocol"),
    **dict.fromkeys(
        ("Numerics", "Trace", "Trial", "TrialInputError", "TrialResult", "run_trial", "simulate_trial"),
        "sim.trial",
    ),
    **dict.fromkeys(("Modifier", "ModelSetError", "register"), "sim.modifier"),
    **dict.fromkeys(("Contact",), "sim.world"),
    **dict.fromkeys(
        ("ENGINES", "EngineError", "MujocoParams", "SimulationDiverged", "open_world"), "sim.engine"
    ),
    **dict.fromkeys(("TrialSpec", "run_sweep", "sweep_specs"), "sim.sweep"),
    **dict.fromkeys(("TrialStore", "StoreError"), "sim.store"),
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name in _EXPORTS:
        value = getattr(importlib.import_module(_EXPORTS[name]), name)
        globals()[name] = value
        return value
    raise AttributeError(f"module 'sim' has no attribute {name!r}")


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))
