"""Headless Chromium driven over the Chrome DevTools protocol, for the tests that look at pages in a real browser
(the service's page, the documentation's layout): start the browser, open a session on its page, evaluate
JavaScript, collect console errors. Skips (pytest.skip) when Chromium or the websockets package is absent."""

from __future__ import annotations

import contextlib
import itertools
import json
import os
import shutil
import signal
import subprocess
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

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


@contextlib.contextmanager
def devtools_chromium(profile: Path) -> Iterator[int]:
    """A headless Chromium with the user profile ``profile``; yields its DevTools port, and ends it on exit."""
    if CHROMIUM is None:
        pytest.skip("chromium is not installed")
    pytest.importorskip("websockets")
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
        with contextlib.suppress(ProcessLookupError):
            os.killpg(proc.pid, signal.SIGTERM)
        proc.wait(timeout=30)
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
