"""One answer per pose, whichever door: the Python API, the command line and the service give the same numbers for
the same robot and pose, on the same default grid; the page asks for that grid and draws pitch-roll maps the way
every figure does. (The page in a browser: test_browser.py.)"""

from __future__ import annotations

import inspect
import json
import re
from html.parser import HTMLParser

import pytest

from landscape.grid import DEFAULT_STEP_DEG
from landscape.service.app import STATIC

POSES = [(74.0, 0.0), (60.0, 30.0), (90.0, 10.0)]
"""θw, θl: the issue's pose (the pitch-wise barrier once read 41.733 mJ by the command line, 42.607 mJ by the page)
and two others."""


def _without_timing(d: dict) -> dict:
    d = {k: v for k, v in d.items() if k not in ("timing_s", "paths", "grid")}
    d["robot"] = {k: v for k, v in d["robot"].items() if k != "source"}
    return d


@pytest.mark.parametrize("theta_w, theta_l", POSES)
def test_the_service_answers_what_compute_returns(client, capsys, theta_w, theta_l):
    """Every number of the service's JSON (energies in J to the last digit it carries, saddles in degrees) is that
    of ``landscape.compute()`` and of ``landscape compute --json``, each on its default grid."""
    import landscape
    from landscape.cli import main
    from landscape.viz import files

    robot = landscape.load_robot()
    c = landscape.compute(robot, theta_w_deg=theta_w, theta_l_deg=theta_l)
    python = files.summary(
        c, robot_name=robot.name, robot_source=None, robot_hash=robot.robot_hash, com_source=robot.com_source
    )
    got = client.get("/api/landscape", params={"theta_w": theta_w, "theta_l": theta_l}).json()
    assert main(["compute", "--theta-w", f"{theta_w:g}", "--theta-l", f"{theta_l:g}", "--json"]) == 0
    cli = json.loads(capsys.readouterr().out)
    assert got["step_deg"] == cli["step_deg"] == python["step_deg"] == DEFAULT_STEP_DEG
    assert _without_timing(got) == _without_timing(cli)
    for key in ("righting_j", "pitch_wise_j", "roll_wise_j", "escape_j"):
        assert got["barrier"][key] == python["barrier"][key], key
    assert got["minimum"] == python["minimum"]
    for k, x in python["paths"].items():
        for f in ("barrier_j", "saddle_pitch_deg", "saddle_roll_deg", "direction"):
            assert (got["paths"][k] or {}).get(f) == (x or {}).get(f), (k, f)


def _defaults_of_step():
    import landscape
    from landscape.analysis import trials
    from landscape.energy import energy_landscape
    from landscape.viz.sections import barrier, physical, trajectories

    for f in (
        landscape.compute,
        landscape.barrier_map,
        energy_landscape,
        trials.landscape_barriers,
        barrier.section_barrier,
        physical.section_physical,
        trajectories.section_trajectories,
    ):
        yield f"{f.__module__}.{f.__qualname__}", inspect.signature(f).parameters["step_deg"].default


def test_one_default_grid_step_in_every_interface(client):
    """The Python API, the report's sections, the command line, the service and the page default to
    :data:`landscape.grid.DEFAULT_STEP_DEG`."""
    from landscape.cli import cli

    got = dict(_defaults_of_step())
    for path in (["compute"], ["barrier-map"], ["render"], ["analyze", "barrier"]):
        cmd = cli
        for name in path:
            cmd = cmd.commands[name]
        got[" ".join(path) + " --step"] = next(p for p in cmd.params if p.name == "step").default
    spec = client.get("/openapi.json").json()["paths"]
    for route in ("/api/landscape", "/api/barrier-map"):
        got[route] = next(p for p in spec[route]["get"]["parameters"] if p["name"] == "step")["schema"][
            "default"
        ]
    got["the page"] = float(_page_step_default())
    assert got == dict.fromkeys(got, DEFAULT_STEP_DEG)
    assert len(got) == 14


def _page_step_default() -> str:
    """The option selected in the page's grid-step selector."""

    class Select(HTMLParser):
        inside, selected = False, []

        def handle_starttag(self, tag, attrs):
            a = dict(attrs)
            if tag == "select":
                self.inside = a.get("id") == "step"
            elif tag == "option" and self.inside and "selected" in a:
                self.selected.append(True)

        def handle_data(self, data):
            if self.selected and self.selected[-1] is True:
                self.selected[-1] = data.strip()

    p = Select()
    p.feed((STATIC / "index.html").read_text())
    assert len(p.selected) == 1, p.selected
    return p.selected[0]


def test_the_page_draws_pitch_on_x_and_roll_on_y():
    """The page's pitch-roll maps use the axes of every other figure (contour.png: pitch on x, roll on y) and
    the barrier map those of barrier_map.png (θl on x, θw on y); in a browser, test_browser.py reads the drawn
    plots."""
    from landscape.viz import render

    js = (STATIC / "app.js").read_text()
    axes = re.search(
        r"const MAP_AXES = \{ xaxis: \{ title: \{ text: \"(.+?)\" \} \}, yaxis: \{ title: \{ text: \"(.+?)\"",
        js,
    )
    assert axes is not None and axes.groups() == ("pitch (°)", "roll (°)")
    assert render.PITCH_LABEL == "pitch (°)" and render.ROLL_LABEL == "roll (°)"
