import numpy as np
import pytest
import trimesh

from geometry import NotAVolumeError, mesh_mass_properties, shell_mass_properties, solid_mass_properties


def test_box_solid_closed_form():
    a, b, c, m = 0.3, 0.2, 0.1, 2.0
    box = trimesh.creation.box(extents=(a, b, c))
    box.apply_translation([1.0, -2.0, 0.5])
    mp = solid_mass_properties(box, mass_kg=m)
    assert mp.com_m == pytest.approx([1.0, -2.0, 0.5], abs=1e-12)
    assert np.diag(mp.inertia_kg_m2) == pytest.approx(
        [m * (b**2 + c**2) / 12, m * (a**2 + c**2) / 12, m * (a**2 + b**2) / 12], rel=1e-9
    )
    assert box.volume == pytest.approx(a * b * c, rel=1e-12)


def test_open_mesh_refused_as_solid():
    box = trimesh.creation.box(extents=(1, 1, 1))
    box.update_faces(np.arange(len(box.faces)) > 1)
    with pytest.raises(NotAVolumeError, match="watertight=False"):
        mesh_mass_properties(box, mass_kg=1.0, com_model="solid")
    assert mesh_mass_properties(box, mass_kg=1.0).model == "shell"


def test_shell_hemisphere_centroid():
    """Area centroid of a thin hemispherical shell is r/2 from the centre (Archimedes)."""
    s = trimesh.creation.icosphere(subdivisions=5, radius=1.0)
    s = trimesh.intersections.slice_mesh_plane(s, plane_normal=[0, 0, 1], plane_origin=[0, 0, 0])
    mp = shell_mass_properties(s, mass_kg=1.0)
    assert mp.com_m[2] == pytest.approx(0.5, rel=2e-3)


def test_spherical_shell_inertia():
    s = trimesh.creation.icosphere(subdivisions=5, radius=2.0)
    mp = shell_mass_properties(s, mass_kg=3.0)
    assert np.diag(mp.inertia_kg_m2) == pytest.approx([2 / 3 * 3.0 * 4.0] * 3, rel=1e-3)
