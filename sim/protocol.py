"""The experiment's constants, in one place: the source paper's protocol and the simulator's default steps.

Pure constants (no pybullet), so the command line can show them in its help without loading the engine. The
``*_BOUNDS`` are the ranges the command line and the service accept (:class:`geometry.bounds.Bounds`).
"""

import math

from geometry.bounds import Bounds

PAPER_WING_PERIOD_S = 2.0
"""Tw of the source paper's protocol, s (the default of :class:`sim.actuation.Actuation`)."""
PAPER_LEG_PERIOD_S = 0.8
"""Tl of the source paper's protocol, s (the default of :class:`sim.actuation.Actuation`)."""
PAPER_THETA_W_DEG = (70.0, 72.0, 74.0, 76.0)
"""The source paper's wing angles, degrees."""
PAPER_THETA_L_DEG = (20.0, 30.0, 40.0, 50.0)
"""The source paper's leg amplitudes, degrees."""
PAPER_CV = (0.0, 0.05, 0.1, 0.15, 0.2, 0.25)
"""The source paper's noise levels Cv = sigma / Tl."""
PAPER_TRIALS = 40
"""Trials per setting in the source paper."""
PAPER_PHASE = 0.7
"""First-attempt phase phi_1 of the default sweep."""
DEFAULT_DURATION_S = 10.0
"""Trial length, s (the source paper's)."""
DEFAULT_DT_S = 1.25e-4
"""Default pybullet time step of the built-in robot, s: the largest of 1e-3, 5e-4, 2.5e-4 and 1.25e-4 s at which
at least 95 of the 100 borderline single attempts end as at a quarter of the step
(``benchmarks/sim_convergence.py --borderline``; docs/sim.md)."""
OTHER_ROBOT_DT_S = 1.25e-4
"""Default pybullet time step of any other robot, s: no larger than the built-in robot's (the lab URDF passed the
earlier orientation criterion at 2e-4 s); run the convergence benchmark on a new robot before trusting a larger
one."""
MUJOCO_DT_S = 1.25e-4
"""Default MuJoCo time step of the built-in robot, s: the largest of 2e-3 ... 1.25e-4 s that passes the same
criterion (``benchmarks/sim_convergence.py --borderline``; docs/sim.md)."""
MUJOCO_OTHER_ROBOT_DT_S = 1.25e-4
"""Default MuJoCo time step of any other robot, s (no larger than the built-in robot's)."""

# Bounds: a request past them is refused up front with its cost (``sim.trial.check_trial_cost``).
MAX_DURATION_S = 600.0
"""Longest trial, s (the paper's trials last 10 s); a longer one is refused before anything is allocated."""
MIN_DT_S = 1e-6
"""Smallest time step, s (the convergence benchmark's finest is 5e-5 s)."""
MAX_DT_S = 0.01
"""Largest time step, s (the servo time constant ``sim.trial.SERVO_TAU_S``)."""
MAX_STEPS = 5_000_000
"""Most physics steps of one trial, settling included (the default trial takes 21,000; at about 0.1 ms each the
limit is about 10 min of CPU per trial)."""
MAX_TRIALS = 1_000_000
"""Most trials of one sweep (the paper's has 3,840)."""

# Ranges of the inputs of trials and sweeps, as every interface states and checks them.
CV_BOUNDS = Bounds(0.0, 1.0, meaning="Cv is sigma / Tl as a fraction", percent=True)
"""Noise Cv = sigma / Tl: a fraction (the paper's go up to 0.25); '10%' is 0.1."""
PHASE_BOUNDS = Bounds(0.0, 1.0, hi_open=True, meaning="a phase is a fraction of the leg period Tl")
"""First-attempt phase phi_1 = dt_1 / Tl."""
DURATION_S_BOUNDS = Bounds(
    0.0, MAX_DURATION_S, unit="s", lo_open=True, meaning="a trial's length (the paper's: 10 s)"
)
"""Trial length, s: up to ``MAX_DURATION_S``."""
DT_S_BOUNDS = Bounds(MIN_DT_S, MAX_DT_S, unit="s", meaning="the physics time step")
"""Physics time step, s: ``MIN_DT_S`` to ``MAX_DT_S``."""
PERIOD_S_BOUNDS = Bounds(
    0.0, MAX_DURATION_S, unit="s", lo_open=True, meaning="a period of the wings (Tw) or the leg (Tl)"
)
"""Tw and Tl, s (the paper's: 2 s and 0.8 s): positive, at most the longest trial."""
TRIALS_BOUNDS = Bounds(1, MAX_TRIALS, integer=True, meaning="trials per setting")
"""Trials per parameter combination."""
ATTEMPTS_BOUNDS = Bounds(0, math.inf, integer=True, meaning="wing openings per trial (0: no limit)")
"""Most wing openings of a trial; 0: no limit."""
SEED_BOUNDS = Bounds(0, 2**63 - 1, integer=True, hi_text="2^63 - 1", meaning="a random seed")
"""Random seeds: what a trial's seed and the store's INTEGER column hold."""
HEADING_DEG_BOUNDS = Bounds(-360.0, 360.0, unit="deg", meaning="a heading within one turn")
"""The robot's heading on the ground, degrees about the vertical."""
