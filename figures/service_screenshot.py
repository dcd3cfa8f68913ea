"""Screenshot of the `landscape serve` page for the README: starts the server on a free loopback port with a
fresh data directory, lets headless Chromium load the page and run its scripts, saves a PNG.

    .venv/bin/python figures/service_screenshot.py                                 # screenshots/service_page.png
    .venv/bin/python figures/service_screenshot.py --out figures/service_page.png  # the committed screenshot

By default it writes screenshots/service_page.png in the checkout, a folder git ignores, so trying it leaves the
checkout unchanged; ``--out figures/service_page.png`` regenerates the screenshot the README and the docs show.
"""

from __future__ import annotations

import argparse
import shutil
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DEFAULT_OUT = ROOT / "screenshots" / "service_page.png"


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument(
        "--out",
        type=Path,
        default=DEFAULT_OUT,
        help="PNG to write [default: screenshots/service_page.png in the checkout; figures/service_page.png is "
        "the committed one]",
    )
    out = ap.parse_args(argv).out
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
            out.parent.mkdir(parents=True, exist_ok=True)
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
                    f"--screenshot={out.resolve()}",
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
