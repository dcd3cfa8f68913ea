"""Synthetic trial rows for the report sections' tests."""

import numpy as np


def _row(**kw):
    base = dict(
        status="ok",
        attempts=0,
        theta_w_deg=74.0,
        theta_l_deg=30.0,
        cv=0.1,
        phase=0.7,
        wing_period_s=2.0,
        leg_period_s=0.8,
        duration_s=10.0,
        dt_s=5e-4,
        seed=1,
        success=False,
        time_to_right_s=None,
        attempt=None,
        mode=None,
        attempt_starts_s=[],
        robot_hash="h",
        robot="r.urdf",
    )
    base.update(kw)
    return base


def _won(**kw):
    return _row(success=True, time_to_right_s=2.0, attempt=1, mode="roll", **kw)


def _map_rows(good_phases, theta_w=74.0, theta_l=30.0):
    """A single-attempt phase map without noise at Tl 0.8 s: phases 0, 0.05, ..., 0.95."""
    return [
        _row(
            attempts=1,
            cv=0.0,
            theta_w_deg=theta_w,
            theta_l_deg=theta_l,
            phase=ph,
            success=ph in good_phases,
            time_to_right_s=ph * 0.8 + 0.8 if ph in good_phases else None,
            attempt_starts_s=[ph * 0.8],
        )
        for ph in np.round(np.arange(0, 1, 0.05), 2)
    ]
