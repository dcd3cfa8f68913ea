"""Figures: 3-D landscape and robot (pyvista, off-screen), VTK file, contour map, and the `render` command.

Rendering tests need pyvista and an off-screen OpenGL (EGL or OSMesa); without either they skip, saying why.
"""

from __future__ import annotations

import importlib

import numpy as np
import pytest
import trimesh
from PIL import Image

from geometry import Robot
from geometry.frames import up_vector
from landscape.cli import main
from landscape.computation import compute
from landscape.energy import height_at
from landscape.viz import render as rd
from landscape.viz.scene import nearest_twin_deg, posed_meshes_world, wrapped_path_deg


def _importable(name: str) -> bool:
    try:
        importlib.import_module(name)
    except ImportError:
        return False
    return True


HAS_PYVISTA = _importable("pyvista")
needs_pyvista = pytest.mark.skipif(not HAS_PYVISTA, reason="pyvista not installed (pip install -e .)")
BOX_M = (0.04, 0.02, 0.01)


@pytest.fixture()
def pv():
    """pyvista set to render off-screen, or a skip that says what is missing."""
    problem = rd.off_screen_problem()
    if problem is not None:
        pytest.skip(problem)
    import pyvista

    before = pyvista.OFF_SCREEN
    pyvista.OFF_SCREEN = True
    yield pyvista
    pyvista.close_all()
    pyvista.OFF_SCREEN = before


def _rgb(path):
    return np.asarray(Image.open(path).convert("RGB"), dtype=np.int64)


def _hex(colour):
    return np.array([int(colour[i : i + 2], 16) for i in (1, 3, 5)])


def _pixels_near(img, colour, tol=45):
    return int((np.abs(img - _hex(colour)).max(axis=-1) <= tol).sum())


@pytest.fixture(scope="module")
def bowl():
    """A synthetic landscape on a 10 deg grid with a marked minimum, saddle and path."""
    a = np.arange(-180.0, 181.0, 10.0)
    p, r = np.meshgrid(np.deg2rad(a), np.deg2rad(a), indexing="ij")
    e = 0.1 + 0.02 * (1 - np.cos(p)) + 0.01 * (1 - np.cos(2 * r))  # J; minimum 0.1 J at (0, 0)
    path = np.array([[0.0, 0.0], [0.0, 20.0], [0.0, 45.0], [0.0, 70.0]])
    path_j = 0.1 + 0.01 * (1 - np.cos(2 * np.deg2rad(path[:, 1])))
    return {
        "energy_j": e,
        "pitch_deg": a,
        "roll_deg": a,
        "minimum_deg": (0.0, 0.0),
        "minimum_j": 0.1,
        "saddle_deg": (0.0, 45.0),
        "saddle_j": 0.12,
        "path_deg": path,
        "path_j": path_j,
    }


@pytest.fixture()
def box_stl(tmp_path):
    f = tmp_path / "box.stl"
    trimesh.creation.box(extents=[1e3 * x for x in BOX_M]).export(f)
    return f


# ------------------------------------------------------------------------------------------------ layout helpers
def test_wrapped_path_breaks_where_it_wraps():
    path = np.array([[170.0, -175.0], [178.0, -179.0], [186.0, -183.0], [190.0, -190.0]])
    w = wrapped_path_deg(path)
    assert w.shape == (5, 2)
    assert np.isnan(w[2]).all()
    np.testing.assert_allclose(w[[0, 1, 3, 4]], [[170, -175], [178, -179], [-174, 177], [-170, 170]])
    np.testing.assert_allclose(wrapped_path_deg(np.array([[10.0, 20.0], [11.0, 21.0]])), [[10, 20], [11, 21]])


@pytest.mark.parametrize(("p", "r"), [(70.0, 10.0), (-30.0, 170.0), (89.0, -120.0)])
def test_nearest_twin_is_the_same_orientation(p, r):
    twin = (180.0 - p, r + 180.0)
    for near, want in (((p, r), (p, r)), (twin, twin)):
        got = nearest_twin_deg(p, r, np.array([near]))
        np.testing.assert_allclose(up_vector(*np.deg2rad(got)), up_vector(*np.deg2rad((p, r))), atol=1e-12)
        np.testing.assert_allclose(np.cos(np.deg2rad(got)), np.cos(np.deg2rad(want)), atol=1e-12)


@pytest.mark.parametrize(
    ("p", "r", "height_m"),
    [
        (0.0, 0.0, BOX_M[2] / 2),  # on its back: up is body z
        (0.0, 90.0, BOX_M[1] / 2),  # on its side: up is body y
        (90.0, 0.0, BOX_M[0] / 2),  # on its end: up is -x
        (30.0, 0.0, BOX_M[0] / 2 * 0.5 + BOX_M[2] / 2 * np.sqrt(3) / 2),  # balanced on an edge
    ],
)
def test_posed_box_rests_on_the_ground(p, r, height_m):
    pose = Robot.from_trimesh(trimesh.creation.box(extents=BOX_M)).pose()
    meshes, com = posed_meshes_world(pose, p, r)
    z = np.concatenate([v[:, 2] for v, _ in meshes])
    assert z.min() == pytest.approx(0.0, abs=1e-15)
    assert com[2] == pytest.approx(height_m, rel=1e-12)
    assert com[2] == pytest.approx(float(height_at(pose, p, r)), rel=1e-12)
    np.testing.assert_allclose(com[:2], 0.0, atol=1e-15)
    extent = np.ptp(np.concatenate([v for v, _ in meshes]), axis=0)
    a, b, c = (
        BOX_M  # at roll 0 pitch turns x into z about y: extents a|cos p| + c|sin p|, b, a|sin p| + c|cos p|
    )
    cp, sp = abs(np.cos(np.deg2rad(p))), abs(np.sin(np.deg2rad(p)))
    want = (
        sorted(BOX_M) if r else sorted([a * cp + c * sp, b, a * sp + c * cp])
    )  # roll 90 at pitch 0: a permutation
    assert sorted(extent) == pytest.approx(want, rel=1e-12)


def test_posed_lab_robot_com_height_is_the_minimum_height(lab_robot):
    c = compute(lab_robot, theta_w_deg=74.0, theta_l_deg=30.0, step_deg=5.0)
    meshes, com = posed_meshes_world(c.pose, c.minimum.pitch_deg, c.minimum.roll_deg)
    assert len(meshes) >= 5
    assert min(float(v[:, 2].min()) for v, _ in meshes) == pytest.approx(0.0, abs=1e-12)
    assert com[2] == pytest.approx(c.minimum.height_m, rel=1e-9)


# ------------------------------------------------------------------------------------------------ contour map
def test_contour_svg_has_the_marks_and_png_its_size(tmp_path, bowl):
    marks = {k: bowl[k] for k in ("minimum_deg", "saddle_deg", "saddle_j", "path_deg")}
    arrays = (bowl["energy_j"], bowl["pitch_deg"], bowl["roll_deg"])
    svg = rd.render_contour(*arrays, tmp_path / "c.svg", title="bowl", **marks)
    text = svg.read_text()
    for gid in ("start-minimum", "saddle", "saddle-level", "barrier-path"):
        assert f'id="{gid}"' in text, gid
    assert "pitch (°)" in text and "roll (°)" in text and "energy (mJ)" in text
    png = rd.render_contour(*arrays, tmp_path / "c.png", **marks)
    img = _rgb(png)
    assert img.shape == (5.2 * 150, 6.4 * 150, 3)
    assert _pixels_near(img, rd.START_COLOUR) > 20 and _pixels_near(img, rd.PATH_COLOUR) > 20
    bare = _rgb(rd.render_contour(*arrays, tmp_path / "bare.png"))
    assert _pixels_near(bare, rd.START_COLOUR) == 0


def test_contour_refuses_mismatched_shapes(tmp_path, bowl):
    with pytest.raises(ValueError, match=r"shape \(len\(pitch_deg\), len\(roll_deg\)\)"):
        rd.render_contour(bowl["energy_j"][:, :-1], bowl["pitch_deg"], bowl["roll_deg"], tmp_path / "x.png")
    e = bowl["energy_j"].copy()
    e[3, 4] = np.nan
    with pytest.raises(ValueError, match="finite"):
        rd.render_contour(e, bowl["pitch_deg"], bowl["roll_deg"], tmp_path / "x.png")


# ------------------------------------------------------------------------------------------------ VTK file
@needs_pyvista
def test_vtk_file_reads_back_with_the_same_energies(tmp_path, bowl):
    import pyvista

    e = bowl["energy_j"][:, :-3]  # P != R, so a transposed layout would fail
    f = rd.write_vtk(e, bowl["pitch_deg"], bowl["roll_deg"][:-3], tmp_path / "sub" / "ls.vts")
    assert f.stat().st_size > 0
    grid = pyvista.read(f)
    assert isinstance(grid, pyvista.StructuredGrid) and grid.dimensions == (e.shape[0], e.shape[1], 1)
    np.testing.assert_array_equal(grid.point_data["energy_j"].reshape(e.shape, order="F"), e)
    np.testing.assert_allclose(grid.point_data["energy_mJ"], 1e3 * grid.point_data["energy_j"])
    pts = grid.points.reshape((*e.shape, 3), order="F")
    np.testing.assert_array_equal(pts[:, 0, 0], bowl["pitch_deg"])
    np.testing.assert_array_equal(pts[0, :, 1], bowl["roll_deg"][:-3])
    with pytest.raises(ValueError, match=r"\.vts"):
        rd.write_vtk(e, bowl["pitch_deg"], bowl["roll_deg"][:-3], tmp_path / "ls.vtk")


# ------------------------------------------------------------------------------------------------ 3-D renders
def test_landscape_png_size_content_and_marks(pv, tmp_path, bowl):
    f = rd.render_landscape(path=tmp_path / "ls.png", window_size=(480, 360), title="bowl", **bowl)
    img = _rgb(f)
    assert img.shape == (360, 480, 3)
    assert img.std() > 20
    scene = img[100:]  # below the title and legend
    for colour in (rd.START_COLOUR, rd.SADDLE_COLOUR, rd.PATH_COLOUR):
        assert _pixels_near(scene, colour) > 5, colour
    plain = _rgb(
        rd.render_landscape(
            bowl["energy_j"], bowl["pitch_deg"], bowl["roll_deg"], tmp_path / "p.png", window_size=(480, 360)
        )
    )
    assert _pixels_near(plain[100:], rd.PATH_COLOUR) == 0


def test_robot_png_shows_parts_on_the_ground(pv, tmp_path):
    box = trimesh.creation.box(extents=(0.04, 0.02, 0.01))
    v = np.asarray(box.vertices) + [0.0, 0.0, 0.005]
    f = rd.render_robot(
        [(v, box.faces), (v + [0.0, 0.0, 0.01], box.faces)],
        tmp_path / "r.png",
        com_m=(0.0, 0.0, 0.01),
        window_size=(400, 300),
        title="two boxes",
    )
    img = _rgb(f)
    assert img.shape == (300, 400, 3)
    assert img.std() > 20
    assert _pixels_near(img, rd.START_COLOUR) > 5  # the CoM shows through the boxes
    with pytest.raises(ValueError, match="empty"):
        rd.render_robot([], tmp_path / "x.png")
    with pytest.raises(ValueError, match="out of range"):
        rd.render_robot([(v, box.faces + 8)], tmp_path / "x.png")


def test_html_export_is_offline_titled_and_holds_the_landscape(tmp_path, bowl):
    """landscape.html: one page that fetches nothing (plotly.js embedded), titled by what it shows (#17)."""
    import json
    import re

    out = rd.export_landscape_html(path=tmp_path / "sub" / "ls.html", title="box  wing 74°", **bowl)
    page = out.read_text(encoding="utf-8")
    assert re.search(r"<title>(.*?)</title>", page).group(1) == "Energy landscape: box  wing 74°"
    assert "OfflineLocalView" not in page and "VTK.js" not in page
    # nothing to fetch: no script or stylesheet from elsewhere, plotly.js itself inline
    assert not re.search(r"<script[^>]*\bsrc=", page) and not re.search(r"<link[^>]*\bhref=", page)
    assert "Plotly.newPlot" in page and len(page) > 1_000_000
    m = re.search(r'Plotly\.newPlot\(\s*"[^"]+",\s*(\[.*?\]),\s*\{"template"', page, re.S)
    surface = json.loads(m.group(1))[0]
    assert surface["type"] == "surface"
    np.testing.assert_allclose(_plotly_array(surface["z"]), bowl["energy_j"].T * 1e3, rtol=1e-12)
    np.testing.assert_allclose(_plotly_array(surface["x"]), bowl["pitch_deg"])


def _plotly_array(v):
    """An array as plotly writes it into a page: a list, or base64 data with a dtype and shape."""
    import base64

    if isinstance(v, dict):
        a = np.frombuffer(base64.b64decode(v["bdata"]), dtype=np.dtype(v["dtype"]))
        return a.reshape([int(n) for n in str(v.get("shape", len(a))).split(",")])
    return np.asarray(v, dtype=float)


def test_html_figure_marks_and_path(bowl):
    fig = rd.landscape_figure(**bowl)
    names = [t.name for t in fig.data]
    assert names[:2] == ["energy", "barrier path"]
    assert names[2].startswith("start minimum (0.0°, 0.0°), 100.0 mJ") and names[3].startswith(
        "saddle (0.0°, 45.0°)"
    )
    lift = 0.01 * np.ptp(bowl["energy_j"]) * 1e3
    assert fig.data[3].z[0] == pytest.approx(120.0 + 2 * lift)
    with pytest.raises(ValueError):
        rd.landscape_figure(bowl["energy_j"][:-1], bowl["pitch_deg"], bowl["roll_deg"])


# ------------------------------------------------------------------------------------------------ command line
def test_cli_render_writes_every_figure(pv, capsys, box_stl, tmp_path):
    out = tmp_path / "fig"
    code = main(["render", "--mesh", str(box_stl), "--units", "mm", "--step", "10", "--out", str(out)])
    stdout, stderr = capsys.readouterr()
    assert code == 0, stderr
    names = [
        "landscape.png",
        "landscape.vts",
        "contour.png",
        "contour.svg",
        "robot_start.png",
        "robot_saddle.png",
    ]
    for name in names:
        assert (out / name).stat().st_size > 0, name
    assert _rgb(out / "landscape.png").shape == (960, 1280, 3)
    assert _rgb(out / "robot_start.png").std() > 20
    assert "<title>Energy landscape: " in (out / "landscape.html").read_text(encoding="utf-8")
    assert stderr == ""  # the HTML page needs nothing optional
    robot = Robot.from_mesh(box_stl, units="mm")
    _, e = compute(robot, step_deg=10.0).landscape.inclusive()
    grid = pv.read(out / "landscape.vts")
    np.testing.assert_allclose(grid.point_data["energy_j"].reshape(e.shape, order="F"), e, rtol=1e-12)
    svg = (out / "contour.svg").read_text()
    assert 'id="saddle"' in svg and 'id="barrier-path"' in svg
    assert stdout.startswith("wrote ")


@needs_pyvista
def test_cli_render_without_off_screen_gl_fails_in_one_line(monkeypatch, capsys, box_stl, tmp_path):
    monkeypatch.setattr(rd, "off_screen_problem", lambda: "vtk cannot render off-screen here: test")
    out = tmp_path / "fig"
    code = main(["render", "--mesh", str(box_stl), "--units", "mm", "--step", "30", "--out", str(out)])
    _, stderr = capsys.readouterr()
    assert code == 2
    assert stderr.count("\n") == 1 and stderr.startswith("landscape: error: vtk cannot render off-screen")
    assert "wrote only contour.png, contour.svg, landscape.vts" in stderr
    assert (out / "contour.svg").is_file() and not (out / "landscape.png").exists()


def test_cli_render_without_pyvista_writes_the_contour_map_and_fails_in_one_line(
    monkeypatch, capsys, box_stl, tmp_path
):
    def missing():
        raise rd.MissingDependencyError(rd.PYVISTA_MISSING)

    monkeypatch.setattr(rd, "_pv", missing)
    out = tmp_path / "fig"
    code = main(["render", "--mesh", str(box_stl), "--units", "mm", "--step", "30", "--out", str(out)])
    _, stderr = capsys.readouterr()
    assert code == 2
    assert (
        stderr.count("\n") == 1
        and "needs pyvista" in stderr
        and "wrote only contour.png, contour.svg in" in stderr
    )
    assert (out / "contour.png").is_file() and not (out / "landscape.vts").exists()


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (["--step", "7"], "does not divide 360"),
        (["--theta-w", "nan"], "--theta-w must be a finite number"),
        (["--exit", "sideways"], "'sideways' is not one of"),
    ],
)
def test_cli_render_bad_input_exits_2_with_one_line(capsys, box_stl, tmp_path, args, message):
    code = main(["render", "--mesh", str(box_stl), "--units", "mm", *args, "--out", str(tmp_path / "o")])
    _, stderr = capsys.readouterr()
    assert code == 2
    assert stderr.count("\n") == 1 and stderr.startswith("landscape: error:") and message in stderr
    assert not (tmp_path / "o").exists()


def test_cli_render_needs_out(capsys, box_stl):
    code = main(["render", "--mesh", str(box_stl)])
    _, stderr = capsys.readouterr()
    assert code == 2 and "--out" in stderr and stderr.count("\n") == 1
