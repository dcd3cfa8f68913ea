"""Analyses of the physical robot's recordings (edge layer: reads the lab's files; no click, no plotting).

The data directory is the lab's ``data-robot`` folder as described in ``../shared/ref/physical_robot/README.md``
(always passed in; nothing of it is in this repository). It holds one MATLAB v7.3 (HDF5) file per trial,
``run5_W_W_W_W_L_K.bag.mat`` with the IMU's orientation quaternions (``quat``), the servo commands (``servo``) and
the IMU's angular rate (``gyro``); ``robot_attempts.mat`` (MATLAB v5) with the lab's per-attempt outcomes and
measured wing traces; and the servo pulse recordings ``vib_pulse_v2.mat`` and ``motor_pulse_v2.mat``.

Every analysis reads trials through :func:`~landscape.analysis.physical.recording.read_recording`, which hands a
file to the reader registered for its name ending. A lab with another format writes one function ``path ->``
:class:`~landscape.analysis.physical.recording.Recording` and registers it::

    from landscape.analysis.physical.recording import register_reader
    register_reader(".csv", read_my_csv)  # run5_W_W_W_W_L_K.csv files are read by read_my_csv

Modules, one concept each:

- :mod:`~landscape.analysis.physical.recording`: the file format, the reader and the IMU's frame;
- :mod:`~landscape.analysis.physical.outcome`: the outcome rule (when a trial has righted);
- :mod:`~landscape.analysis.physical.cells`: outcome tables per command, and the side the robot rolls to;
- :mod:`~landscape.analysis.physical.attempts`: attempts by the lab's rule and as pitch-roll paths;
- :mod:`~landscape.analysis.physical.resting`: the body's pitch while the wings are held open;
- :mod:`~landscape.analysis.physical.response`: the first opening's response, recorded and simulated;
- :mod:`~landscape.analysis.physical.lean`: the held body's lean with the leg swinging;
- :mod:`~landscape.analysis.physical.hold`: the hold pitch in the model's and the IMU's frame;
- :mod:`~landscape.analysis.physical.mounting`: the IMU's mounting from the two rests;
- :mod:`~landscape.analysis.physical.kinematics`: all of the above that ``landscape physical kinematics`` shows;
- :mod:`~landscape.analysis.physical.motion`: recordings as motions for the energy budget;
- :mod:`~landscape.analysis.physical.measured`: servo profiles fitted to the pulse recordings;
- :mod:`~landscape.analysis.physical.validation`: simulated trials beside the recorded ones;
- :mod:`~landscape.analysis.physical.calibration`: model sets ranked against the recordings.
"""
