"""Analyses (edge layer: statistics and tables; no click, no plotting). They join the numerics, :mod:`sim` and
the physical robot's recordings:

- :mod:`landscape.analysis.trials`: simulated trial databases (probability, phase maps, prediction, barrier
  against outcome), the source paper's analyses;
- :mod:`landscape.analysis.prediction`: the first righting attempt predicted from the phase and the state;
- :mod:`landscape.analysis.energy`: the energy budget of simulated and recorded attempts;
- :mod:`landscape.analysis.physical`: everything that reads the lab's recordings (outcomes, openings, leans,
  the IMU's mounting, the servo profiles, validation and calibration of model sets against them);
- :mod:`landscape.analysis.reruns`: stored trials run again with a trace;
- :mod:`landscape.analysis.bench`: the speed and memory of the numerics.
"""
