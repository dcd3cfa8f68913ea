"""A robot at fixed joint angles: its parts (one link's geometry and inertial each) and the posed rigid body."""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from numpy.typing import NDArray

from .hull import Hull, convex_hull
from .mass import MassProperties, combine


@dataclass(frozen=True)
class Part:
    """One link's geometry and inertial, in the link frame.

    Attributes
    ----------
    link : str
        Link name.
    mass : MassProperties
        Mass, CoM (m, link frame) and inertia of the link.
    hull_link_m : ndarray of shape (K, 3)
        Convex hull vertices of all the link's collision geometry, link frame, m (may be empty).
    points_link_m : ndarray of shape (N, 3)
        Every vertex of the link's meshes, link frame, m (only for the brute-force reference method).
    """

    link: str
    mass: MassProperties
    hull_link_m: NDArray[np.float64]
    points_link_m: NDArray[np.float64]


@dataclass(frozen=True)
class Pose:
    """The rigid body a robot is at fixed joint angles, in the body (base-link) frame.

    Attributes
    ----------
    theta_w_deg, theta_l_deg : float or None
        Wing and leg angle, degrees (None for a single rigid mesh).
    mass_kg : float
        Total mass, kg.
    com_m : ndarray of shape (3,)
        Mass-weighted CoM, m.
    hull_points_m : ndarray of shape (M, 3)
        Every part's own hull vertices in the body frame, m; ``hull`` is their convex hull.
    link_transforms : dict[str, ndarray of shape (4, 4)]
        Link-to-body transforms.
    """

    theta_w_deg: float | None
    theta_l_deg: float | None
    mass_kg: float
    com_m: NDArray[np.float64]
    hull_points_m: NDArray[np.float64] = field(repr=False)
    link_transforms: dict[str, NDArray[np.float64]] = field(repr=False)
    parts: tuple[Part, ...] = field(repr=False)

    @cached_property
    def hull(self) -> Hull:
        """Convex hull of every part's geometry, m (computed on first use)."""
        return convex_hull(self.hull_points_m)

    @cached_property
    def inertia_kg_m2(self) -> NDArray[np.float64]:
        """Inertia tensor about the CoM in the body frame, kg m^2: the posed parts' own, combined by the
        parallel-axis theorem (computed on first use; zero for a pose built without parts).

        Examples
        --------
        >>> from geometry.robots import load_robot
        >>> pose = load_robot("builtin").pose(74.0, 30.0)
        >>> bool(np.allclose(pose.inertia_kg_m2, pose.inertia_kg_m2.T) and (np.linalg.eigvalsh(pose.inertia_kg_m2) > 0).all())
        True
        """
        masses = _posed_masses(self.link_transforms, self.parts)
        return combine(masses).inertia_kg_m2 if masses else np.zeros((3, 3))

    def all_points_m(self) -> NDArray[np.float64]:
        """Every mesh vertex of every part in the body frame, m (the lab's brute-force input)."""
        out = [
            _apply(self.link_transforms[p.link], p.points_link_m) for p in self.parts if len(p.points_link_m)
        ]
        return np.concatenate(out) if out else np.zeros((0, 3))


def _apply(T: NDArray[np.float64], pts: NDArray[np.float64]) -> NDArray[np.float64]:
    return pts @ T[:3, :3].T + T[:3, 3]


def _posed_masses(T: dict, parts) -> list[MassProperties]:
    """The parts with mass, their CoM and inertia turned into the body frame by the link transforms ``T``."""
    return [
        MassProperties(
            p.mass.mass_kg,
            _apply(T[p.link], p.mass.com_m[None])[0],
            T[p.link][:3, :3] @ p.mass.inertia_kg_m2 @ T[p.link][:3, :3].T,
            p.mass.model,
        )
        for p in parts
        if p.mass.mass_kg > 0
    ]
