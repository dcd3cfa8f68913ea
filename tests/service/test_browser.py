"""The page in a real browser: headless Chromium, driven over the Chrome DevTools protocol, opens the page served by
a real uvicorn on 127.0.0.1, moves the theta_w slider, sees the righting barrier and the robot drawn at the start
and at the saddle change to the service's numbers for the new angle, and logs no console error; with a token, the
page given #token=T works and a sweep's report opens from its link. Skipped when Chromium or the websockets package
is absent."""

from __future__ import annotations

import json
import re
import signal
import time
from pathlib import Path

import pytest

from tests.browser import CDP, devtools_chromium, page

from .test_sweeps import TINY, _call, _free_port, _wait, start_server, stop_server

pytestmark = pytest.mark.e2e  # browser sessions against a served page: CI runs them as a step of their own


@pytest.fixture
def chromium(tmp_path):
    """The DevTools port of a headless Chromium (skips without Chromium or websockets)."""
    with devtools_chromium(tmp_path / "profile") as port:
        yield port


ROBOT_VIEW = """(() => {{
  const d = document.getElementById('{div}').data || [];
  const m = d.find((t) => t.type === 'mesh3d' && t.name === 'robot');
  const c = d.find((t) => t.type === 'scatter3d' && t.name === 'CoM');
  return m && c && m.x.length > 0 && m.i.length > 0 ? [m.x.length, m.i.length, Math.min(...m.z), c.z[0]] : null;
}})()"""


def _want_view(
    port: int, theta_w: float, pitch: float, roll: float, token: str | None = None, model: str | None = None
) -> list:
    """What the robot view must show, from the API: vertices, faces, lowest z (mm) and CoM height (mm)."""
    q = f"theta_w={theta_w}&theta_l=0&pitch={pitch}&roll={roll}" + (f"&model={model}" if model else "")
    pose = _call(port, "GET", f"/api/robot-pose?{q}", token=token)
    return [
        sum(len(p["vertices_m"]) for p in pose["parts"]),
        sum(len(p["faces"]) for p in pose["parts"]),
        0.0,
        pose["com_height_m"] * 1e3,
    ]


def _wait_view(cdp: CDP, div: str, want: list) -> list:
    """Wait until the robot view ``div`` draws the posed robot ``want`` (vertices, faces, lowest z, CoM z)."""
    t0 = time.monotonic()
    got = None
    while time.monotonic() - t0 < 60:
        got = cdp.eval(ROBOT_VIEW.format(div=div))
        if got and got[:2] == want[:2] and got[2:] == pytest.approx(want[2:], abs=1e-3):
            return got
        time.sleep(0.1)
    raise AssertionError(f"{div} shows {got}, want {want}")


RIGHTING_SHOWN = """(() => {{ const t = document.getElementById('righting-mj').textContent;
  return (/^[0-9.]+$/.test(t) && t !== '{other_than}') ? t : ''; }})()"""
"""The righting barrier the page shows (mJ, as text) once it is a number other than ``other_than``."""


def _open(cdp: CDP, port: int) -> str:
    """Open the page of the server on ``port``, collecting console events, and wait for its first righting
    barrier (returned as shown, mJ)."""
    for domain in ("Runtime.enable", "Log.enable", "Page.enable"):
        cdp.send(domain)
    cdp.send("Page.navigate", url=f"http://127.0.0.1:{port}/")
    return cdp.wait_for(RIGHTING_SHOWN.format(other_than=""))


def test_slider_updates_the_barrier_without_console_errors(chromium, tmp_path):
    port = _free_port()
    server = start_server(tmp_path / "data", port, tmp_path / "server.log")
    try:
        with page(chromium) as cdp:
            first = _open(cdp, port)
            assert cdp.eval("document.getElementById('theta-w').value") == "74"
            assert cdp.eval("document.querySelector('#contour .main-svg') !== null")
            s74 = _call(port, "GET", "/api/landscape?theta_w=74&theta_l=0&method=exact")
            start74 = _want_view(port, 74, s74["minimum"]["pitch_deg"], s74["minimum"]["roll_deg"])
            _wait_view(cdp, "robot-start", start74)
            cdp.eval(
                "(() => { const s = document.getElementById('theta-w'); s.value = '60';"
                " s.dispatchEvent(new Event('input', {bubbles: true})); })()"
            )
            second = cdp.wait_for(RIGHTING_SHOWN.format(other_than=first))
            want = _call(port, "GET", "/api/landscape?theta_w=60&theta_l=0&method=exact")
            assert float(second) == pytest.approx(want["barrier"]["righting_j"] * 1e3, abs=5e-4)
            # the robot views follow the slider: the robot at theta_w 60 at its start and at its saddle
            m, r = want["minimum"], want["paths"]["righting"]
            start60 = _want_view(port, 60, m["pitch_deg"], m["roll_deg"])
            saddle60 = _want_view(port, 60, r["saddle_pitch_deg"], r["saddle_roll_deg"])
            assert start60 != start74
            _wait_view(cdp, "robot-start", start60)
            _wait_view(cdp, "robot-saddle", saddle60)
            lift_mm = saddle60[3] - start60[3]
            assert lift_mm == pytest.approx(r["barrier_j"] / (want["mass_kg"] * 9.81) * 1e3, abs=1e-3)
            assert "mm above the ground" in cdp.eval(
                "document.getElementById('robot-start-caption').textContent"
            )
            assert re.match(r"theta_w 60°", cdp.eval("document.getElementById('status').textContent"))
            time.sleep(0.5)
            cdp.eval("1")  # collect the events logged meanwhile
            assert cdp.errors() == []
    finally:
        stop_server(server, signal.SIGTERM)


CLI_ROW = re.compile(
    r"^\s+(righting|pitch-wise|roll-wise|escape)\s+([-\d.]+) mJ\s+= CoM lift\s+([-\d.]+) mm\s+"
    r"saddle \(\s*([-\d.]+),\s*([-\d.]+)\)\s+(\S+)$"
)
CLI_MINIMUM = re.compile(r"^minimum\s+pitch ([-\d.]+)°\s+roll ([-\d.]+)°\s+E ([-\d.]+) mJ\s+h ([-\d.]+) mm")
PAGE_TABLE = """[...document.querySelectorAll('#barriers tbody tr')].map((tr) =>
  [...tr.querySelectorAll('th, td')].map((c) => c.textContent))"""
CONTOUR = """(() => { const d = document.getElementById('contour');
  return [d.layout.xaxis.title.text, d.layout.yaxis.title.text, d.data[0].x.length, d.data[0].x[0], d.data[0].y[0],
          d.data[0].z.length, d.data[2].x[0], d.data[2].y[0], d.data[3].x[0], d.data[3].y[0]]; })()"""


def test_the_page_shows_what_the_command_line_prints(chromium, tmp_path, capsys):
    """At its first pose, θw 74°, θl 0°, the page's table is `landscape compute --theta-w 74`'s, digit for digit
    (energies and lifts to 0.001 mJ and mm, angles to 0.01°), on the same default grid (the page once read a
    pitch-wise barrier of 42.607 mJ at (88, -180) on a 2° grid for the command line's 41.733 mJ at (89, -180)),
    and its contour map has pitch on x and roll on y, as contour.png."""
    from landscape.cli import main

    assert main(["compute", "--theta-w", "74"]) == 0
    lines = capsys.readouterr().out.splitlines()
    want = {}
    for line in lines:
        m = CLI_ROW.match(line)
        if m:
            k, mj, mm, p, r, d = m.groups()
            want[k.replace("-", "_")] = [mj, mm, f"({p}, {r}) {d}"]
        m = CLI_MINIMUM.match(line)
        if m:
            p, r, e, h = m.groups()
            want["minimum"] = [e, h, f"({p}, {r})"]
    assert len(want) == 5 and want["pitch_wise"][0] == "41.733", want
    port = _free_port()
    server = start_server(tmp_path / "data", port, tmp_path / "server.log")
    try:
        with page(chromium) as cdp:
            _open(cdp, port)
            assert cdp.eval("document.getElementById('step').value") == "1"
            rows = {r[0].replace("-", "_"): r for r in cdp.eval(PAGE_TABLE)}
            for k, cells in want.items():
                assert rows[k][1:] == cells, (k, rows[k])
            # the robot views' captions say the table's height and lift
            saddle = cdp.wait_for(
                "document.getElementById('robot-saddle-caption').textContent.includes('lifted')"
                " && document.getElementById('robot-saddle-caption').textContent"
            )
            assert saddle.endswith(f"lifted {want['righting'][1]} mm"), saddle
            start = cdp.eval("document.getElementById('robot-start-caption').textContent")
            assert start.endswith(f"CoM {want['minimum'][1]} mm above the ground"), start
            s = _call(port, "GET", "/api/landscape?theta_w=74&theta_l=0")
            m, r = s["minimum"], s["paths"]["righting"]
            got = cdp.wait_for(CONTOUR)
            assert got[:5] == ["pitch (°)", "roll (°)", 361, -180, -180]
            assert got[5] == 361  # z rows: one per roll
            assert got[6:8] == pytest.approx([m["pitch_deg"], m["roll_deg"]])  # the start minimum's mark
            assert got[8:10] == pytest.approx([r["saddle_pitch_deg"], r["saddle_roll_deg"]])  # the saddle's
    finally:
        stop_server(server, signal.SIGTERM)


SENT = """(() => performance.getEntriesByType('resource').map((e) => e.name)
  .filter((u) => u.includes('/api/'))
  .map((u) => { const x = new URL(u); return [x.pathname, x.searchParams.get('model')]; }))()"""
"""Every API request the page made so far: its path and its model parameter (null without one)."""


def test_the_model_set_selector_lists_the_sets_and_the_page_follows_it(chromium, tmp_path):
    """The selector offers none and every shipped set (from GET /api/model-sets); choosing physical-offset sends
    model=physical-offset with the landscape, robot-pose, barrier-map and sweep requests, shows that set's numbers
    and draws the robot as the set models it, and names the set with its hash next to each result."""
    port = _free_port()
    server = start_server(tmp_path / "data", port, tmp_path / "server.log")
    try:
        sets = _call(port, "GET", "/api/model-sets")
        offset = next(m for m in sets if m["name"] == "physical-offset")
        with page(chromium) as cdp:
            first = _open(cdp, port)
            options = cdp.eval(
                "[...document.querySelectorAll('#model option')].map((o) => [o.value, o.text])"
            )
            assert options == [["", "none (as paper)"]] + [[m["name"], m["label"]] for m in sets]
            assert cdp.eval("document.getElementById('model').value") == ""
            assert cdp.eval("document.getElementById('landscape-model').textContent") == "model set: none"
            assert {m for path, m in cdp.eval(SENT) if path in ("/api/landscape", "/api/robot-pose")} == {
                None
            }
            cdp.eval(
                "(() => { const s = document.getElementById('model'); s.value = 'physical-offset';"
                " s.dispatchEvent(new Event('change', {bubbles: true})); })()"
            )
            shown = cdp.wait_for(
                "(() => { const t = document.getElementById('landscape-model').textContent;"
                " return t.includes('physical-offset') ? t : ''; })()"
            )
            assert shown.startswith(f"model set: {offset['label']}; wing joints ")
            want = _call(
                port, "GET", "/api/landscape?theta_w=74&theta_l=0&method=exact&model=physical-offset"
            )
            got = cdp.wait_for(RIGHTING_SHOWN.format(other_than=first))
            assert float(got) == pytest.approx(want["barrier"]["righting_j"] * 1e3, abs=5e-4)
            m = want["minimum"]
            start = _want_view(port, 74, m["pitch_deg"], m["roll_deg"], model="physical-offset")
            assert start != _want_view(port, 74, m["pitch_deg"], m["roll_deg"])
            _wait_view(cdp, "robot-start", start)
            assert offset["model_set_hash"] in cdp.eval("document.getElementById('robot-model').textContent")
            sent = cdp.eval(SENT)
            assert ["/api/landscape", "physical-offset"] in sent and [
                "/api/robot-pose",
                "physical-offset",
            ] in sent
            # the barrier map and a sweep go with the set too
            cdp.eval(
                "(() => { const f = document.getElementById('map-form'); f.theta_w.value = '74';"
                " f.theta_l.value = '0'; f.requestSubmit(); })()"
            )
            status = cdp.wait_for(
                "(() => { const t = document.getElementById('map-status').textContent;"
                " return t.includes('poses') ? t : ''; })()"
            )
            assert status == f"1 poses, model set {offset['label']}"
            assert ["/api/barrier-map", "physical-offset"] in cdp.eval(SENT)
            assert offset["label"] in cdp.eval("document.getElementById('sweep-model').textContent")
            cdp.eval(
                "(() => { const f = document.getElementById('sweep-form'); f.trials.value = '1';"
                " f.duration.value = '0.05'; f.cv.value = '0'; f.requestSubmit(); })()"
            )
            jobs = _wait(lambda: _call(port, "GET", "/api/sweeps"), lambda j: len(j) == 1, timeout_s=30)
            assert jobs[0]["request"]["model"] == "physical-offset"
            assert jobs[0]["request"]["engine"] == "pybullet"  # the form's engine, its first choice
            assert cdp.eval(
                "[...document.getElementById('sweep-form').engine.options].map(o => o.value)"
            ) == [
                "pybullet",
                "mujoco",
            ]
            cell = cdp.wait_for(
                "(() => { const c = document.querySelector('#sweeps tbody td:nth-child(2)');"
                " return c ? c.textContent : ''; })()"
            )
            assert cell == offset["label"]
            time.sleep(0.3)
            cdp.eval("1")
            assert cdp.errors() == []
    finally:
        stop_server(server, signal.SIGTERM)


def test_screenshot_of_the_page(chromium, tmp_path):
    """The page renders its plots (kept as tmp_path/page.png for a person to look at)."""
    import base64

    port = _free_port()
    server = start_server(tmp_path / "data", port, tmp_path / "server.log")
    try:
        with page(chromium) as cdp:
            cdp.send("Runtime.enable")
            cdp.send(
                "Emulation.setDeviceMetricsOverride",
                width=1280,
                height=1400,
                deviceScaleFactor=1,
                mobile=False,
            )
            cdp.send("Page.navigate", url=f"http://127.0.0.1:{port}/")
            cdp.wait_for("/^[0-9.]+$/.test(document.getElementById('righting-mj').textContent)")
            cdp.wait_for(ROBOT_VIEW.format(div="robot-saddle"))
            time.sleep(1.0)
            assert cdp.eval(MODEBAR_CLEAR) == []
            png = base64.b64decode(cdp.send("Page.captureScreenshot", format="png")["data"])
            Path(tmp_path / "page.png").write_bytes(png)
            assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 20_000
    finally:
        stop_server(server, signal.SIGTERM)


MODEBAR_CLEAR = """(() => {
  const hit = (a, b) => a.left < b.right && b.left < a.right && a.top < b.bottom && b.top < a.bottom;
  const bad = [];
  for (const div of document.querySelectorAll('.plot')) {
    const bar = div.querySelector('.modebar');
    if (!bar) continue;
    const m = bar.getBoundingClientRect();
    const texts = [...div.querySelectorAll('svg text')].filter((t) => !bar.contains(t) && t.textContent.trim());
    const area = [...div.querySelectorAll('.nsewdrag')];
    const caption = div.parentElement.querySelector('figcaption');
    for (const el of texts.concat(area, caption ? [caption] : [])) {
      if (hit(m, el.getBoundingClientRect())) bad.push(div.id + ': ' + (el.textContent || el.getAttribute('class')));
    }
  }
  return bad;
})()"""


def test_with_a_token_the_page_works_and_a_report_opens_from_its_link(chromium, tmp_path):
    """The page given #token=T calls the API with the token, and the report link (opened by the browser, which
    cannot add the Authorization header) loads the report, not a 401; the page's cookie opens nothing else."""
    token = "t0k3n-of-the-browser-test"
    port = _free_port()
    server = start_server(tmp_path / "data", port, tmp_path / "server.log", token=token)
    try:
        job = _call(port, "POST", "/api/sweeps", {**TINY, "trials": 1}, token=token)
        with page(chromium) as cdp:
            for domain in ("Runtime.enable", "Log.enable", "Page.enable"):
                cdp.send(domain)
            cdp.send("Page.navigate", url=f"http://127.0.0.1:{port}/#token={token}")
            cdp.wait_for("/^[0-9.]+$/.test(document.getElementById('righting-mj').textContent)")
            cdp.wait_for(ROBOT_VIEW.format(div="robot-start"))
            assert cdp.eval("location.hash") == ""  # the token leaves the address bar
            _wait(
                lambda: _call(port, "GET", f"/api/sweeps/{job['id']}", token=token),
                lambda j: j["status"] == "done",
            )
            href = cdp.wait_for(
                "(() => { const a = document.querySelector('#sweeps a'); return a ? a.href : ''; })()"
            )
            assert href.endswith(f"/api/sweeps/{job['id']}/report")
            time.sleep(0.3)
            cdp.eval("1")
            assert cdp.errors() == []
            cdp.send("Page.navigate", url=href)  # a navigation, as the new tab makes: no Authorization header
            cdp.wait_for(
                f"location.pathname === '/api/sweeps/{job['id']}/report' && document.readyState === 'complete'"
            )
            text = cdp.eval("document.body.innerText")
            assert (
                "missing or wrong token" not in text
                and cdp.eval("document.querySelectorAll('h1, h2').length") > 0
            )
            # the files the report links load too, and the cookie does not open the API
            links = cdp.eval(
                "[...document.querySelectorAll('a[href]')].map((a) => a.href)"
                ".filter((h) => h.includes('/report/') && !h.includes('#'))"
            )
            for link in links[:3]:
                assert cdp.eval(f"fetch({json.dumps(link)}).then((r) => r.status)") == 200, link
            assert cdp.eval("fetch('/api/sweeps').then((r) => r.status)") == 401
    finally:
        stop_server(server, signal.SIGTERM)
