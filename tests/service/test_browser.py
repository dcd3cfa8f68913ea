"""The page in a real browser: headless Chromium, driven over the Chrome DevTools protocol, opens the page served by
a real uvicorn on 127.0.0.1, moves the theta_w slider, sees the righting barrier change to the service's number
for the new angle, and logs no console error. Skipped when Chromium or the websockets package is absent."""

from __future__ import annotations

import contextlib
import itertools
import json
import re
import shutil
import signal
import subprocess
import time
from pathlib import Path

import pytest

from .test_sweeps import _call, _free_port, start_server, stop_server

CHROMIUM = shutil.which("chromium") or shutil.which("chromium-browser") or shutil.which("google-chrome")


class CDP:
    """The smallest Chrome DevTools protocol client: send a command, collect events."""

    def __init__(self, ws):
        self.ws = ws
        self.ids = itertools.count(1)
        self.events: list[dict] = []

    def send(self, method: str, timeout_s: float = 30.0, **params) -> dict:
        i = next(self.ids)
        self.ws.send(json.dumps({"id": i, "method": method, "params": params}))
        t0 = time.monotonic()
        while time.monotonic() - t0 < timeout_s:
            msg = json.loads(self.ws.recv(timeout=timeout_s))
            if msg.get("id") == i:
                if "error" in msg:
                    raise AssertionError(f"{method}: {msg['error']}")
                return msg.get("result", {})
            self.events.append(msg)
        raise AssertionError(f"{method}: no answer in {timeout_s} s")

    def eval(self, expr: str):
        r = self.send("Runtime.evaluate", expression=expr, returnByValue=True, awaitPromise=True)
        if "exceptionDetails" in r:
            raise AssertionError(f"{expr}: {r['exceptionDetails']}")
        return r["result"].get("value")

    def wait_for(self, expr: str, timeout_s: float = 60.0):
        t0 = time.monotonic()
        while time.monotonic() - t0 < timeout_s:
            try:
                v = self.eval(expr)
            except AssertionError:  # the page is not there yet
                v = None
            if v:
                return v
            time.sleep(0.1)
        raise AssertionError(f"timed out waiting for {expr}")

    def errors(self) -> list[str]:
        out = []
        for e in self.events:
            m, p = e.get("method"), e.get("params", {})
            if m == "Runtime.exceptionThrown":
                out.append(json.dumps(p["exceptionDetails"])[:500])
            elif m == "Runtime.consoleAPICalled" and p.get("type") in ("error", "assert"):
                out.append(json.dumps(p.get("args"))[:500])
            elif m == "Log.entryAdded" and p["entry"].get("level") == "error":
                out.append(p["entry"].get("text", "")[:500])
        return out


@pytest.fixture
def chromium(tmp_path):
    if CHROMIUM is None:
        pytest.skip("chromium is not installed")
    pytest.importorskip("websockets")
    profile = tmp_path / "profile"
    proc = subprocess.Popen(
        [
            CHROMIUM,
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-background-networking",
            "--no-first-run",
            "--no-default-browser-check",
            f"--user-data-dir={profile}",
            "--remote-debugging-address=127.0.0.1",
            "--remote-debugging-port=0",
            "about:blank",
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    try:
        port_file = profile / "DevToolsActivePort"
        t0 = time.monotonic()
        while not port_file.is_file() or len(port_file.read_text().splitlines()) < 2:
            if proc.poll() is not None or time.monotonic() - t0 > 60:
                pytest.skip(
                    f"chromium did not start: {proc.stderr.read()[-500:] if proc.poll() is not None else ''}"
                )
            time.sleep(0.1)
        yield int(port_file.read_text().splitlines()[0])
    finally:
        stop_server(proc, signal.SIGTERM)
        proc.stderr.close()


@contextlib.contextmanager
def page(devtools_port: int):
    """A CDP session on the browser's page."""
    import urllib.request

    from websockets.sync.client import connect

    with urllib.request.urlopen(f"http://127.0.0.1:{devtools_port}/json/list", timeout=10) as r:
        targets = json.loads(r.read())
    url = next(t["webSocketDebuggerUrl"] for t in targets if t["type"] == "page")
    with connect(url, max_size=2**26, open_timeout=30) as ws:
        yield CDP(ws)


def test_slider_updates_the_barrier_without_console_errors(chromium, tmp_path):
    port = _free_port()
    server = start_server(tmp_path / "data", port, tmp_path / "server.log")
    try:
        with page(chromium) as cdp:
            for domain in ("Runtime.enable", "Log.enable", "Page.enable"):
                cdp.send(domain)
            cdp.send("Page.navigate", url=f"http://127.0.0.1:{port}/")
            first = cdp.wait_for(
                "(() => { const t = document.getElementById('righting-mj').textContent;"
                " return /^[0-9.]+$/.test(t) ? t : ''; })()"
            )
            assert cdp.eval("document.getElementById('theta-w').value") == "74"
            assert cdp.eval("document.querySelector('#contour .main-svg') !== null")
            cdp.eval(
                "(() => { const s = document.getElementById('theta-w'); s.value = '60';"
                " s.dispatchEvent(new Event('input', {bubbles: true})); })()"
            )
            second = cdp.wait_for(
                f"(() => {{ const t = document.getElementById('righting-mj').textContent;"
                f" return (/^[0-9.]+$/.test(t) && t !== '{first}') ? t : ''; }})()"
            )
            want = _call(port, "GET", "/api/landscape?theta_w=60&theta_l=0&method=exact&step=2")
            assert float(second) == pytest.approx(want["barrier"]["righting_j"] * 1e3, abs=5e-4)
            assert re.match(r"theta_w 60°", cdp.eval("document.getElementById('status').textContent"))
            time.sleep(0.5)
            cdp.eval("1")  # collect the events logged meanwhile
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
            time.sleep(1.0)
            png = base64.b64decode(cdp.send("Page.captureScreenshot", format="png")["data"])
            Path(tmp_path / "page.png").write_bytes(png)
            assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 20_000
    finally:
        stop_server(server, signal.SIGTERM)
