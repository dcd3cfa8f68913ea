"""Screenshot of the `landscape serve` page for the README: starts the server on a free loopback port with a
fresh data directory, lets headless Chromium load the page and run its scripts, saves figures/service_page.png.

    .venv/bin/python figures/service_screenshot.py
"""

from __future__ import annotations

import shutil
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

HERE = Path(__file__).resolve().parent


def main() -> int:
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if chromium is None:
        print("chromium is not installed (apt-get install chromium)", file=sys.stderr)
        return 2
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    with tempfile.TemporaryDirectory() as tmp:
        exe = Path(sys.executable).parent / "landscape"
        server = subprocess.Popen(
            [str(exe), "serve", "--port", str(port), "--data", f"{tmp}/data"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.DEVNULL,
        )
        try:
            for _ in range(300):
                try:
                    urllib.request.urlopen(f"http://127.0.0.1:{port}/api/health", timeout=1).read()
                    break
                except OSError:
                    time.sleep(0.1)
            out = HERE / "service_page.png"
            subprocess.run(
                [
                    chromium,
                    "--headless",
                    "--no-sandbox",
                    "--disable-gpu",
                    "--no-first-run",
                    "--disable-background-networking",
                    f"--user-data-dir={tmp}/profile",
                    "--hide-scrollbars",
                    "--window-size=1280,1300",
                    "--virtual-time-budget=20000",
                    f"--screenshot={out}",
                    f"http://127.0.0.1:{port}/",
                ],
                check=True,
                capture_output=True,
                timeout=180,
            )
            print(f"wrote {out}")
        finally:
            server.terminate()
            server.wait(timeout=30)
    return 0


if __name__ == "__main__":
    sys.exit(main())
