"""
The service called from Python
==============================

``landscape serve`` puts the library behind HTTP (FastAPI). Its app is an ordinary ASGI application, so it can
run in process, with no network and no server: Starlette's ``TestClient`` sends the requests straight to it.
Against a running server the same calls go through any HTTP client (``httpx``, ``requests``) at
``http://127.0.0.1:8000``; :doc:`the service how-to <../howto/service>` gives a curl and a Python example for
every endpoint.

Quick version: a sweep of 2 trials of at most 1 s at dt 1 ms. Full version (``LANDSCAPE_DOCS_FULL=1``): 8 trials
of 10 s at the default time step.
"""

import io
import os
import tempfile
import time
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
from fastapi.testclient import TestClient

from landscape.service.app import create_app
from landscape.service.config import ServiceConfig

full = os.environ.get("LANDSCAPE_DOCS_FULL") == "1"

# The app runs sweeps in worker processes started by spawn, which import this script again: the work sits under
# the usual ``if __name__ == "__main__":`` guard.
if __name__ == "__main__":
    app = create_app(ServiceConfig(data_dir=Path(tempfile.mkdtemp()) / "service", workers=1))
    client = TestClient(app)
    client.__enter__()  # starts the app's lifespan: the sweep runner thread

    print([r["id"] for r in client.get("/api/robots").json()])

# %%
# A landscape: the object of ``landscape compute --json``; ``format=npz`` returns the grid itself.
if __name__ == "__main__":
    summary = client.get("/api/landscape", params={"robot": "builtin", "theta_w": 74, "theta_l": 30}).json()
    b = summary["barrier"]
    print(
        f"righting {b['righting_j'] * 1e3:.3f} mJ by {b['direction']}, saddle ({b['saddle_pitch_deg']:.2f}°, "
        f"{b['saddle_roll_deg']:.2f}°)"
    )
    npz = np.load(
        io.BytesIO(
            client.get("/api/landscape", params={"theta_w": 74, "theta_l": 30, "format": "npz"}).content
        )
    )
    print(sorted(npz.files))

# %%
# A barrier map: small maps answer at once with their rows.
if __name__ == "__main__":
    rows = client.get("/api/barrier-map", params={"theta_w": "70:76:2", "theta_l": "20,30"}).json()
    print(len(rows), "rows; keys:", sorted(rows[0])[:6], "...")

# %%
# A sweep is a job: POST its options (those of ``landscape sweep``), poll its status, open its report.
if __name__ == "__main__":
    body = {"theta_w": "74", "theta_l": "30", "cv": "0.1", "trials": 8 if full else 2}
    body |= {"duration": 10.0} if full else {"duration": 1.0, "dt": 0.001}
    job = client.post("/api/sweeps", json=body).json()
    while job["status"] in ("queued", "running"):
        time.sleep(0.5)
        job = client.get(f"/api/sweeps/{job['id']}").json()
    print(f"sweep {job['id']}: {job['status']}, {job['done']}/{job['total']} trials")
    report = client.get(f"/api/sweeps/{job['id']}/report")
    print("report:", report.status_code, report.headers["content-type"])

# %%
# Bad input gets a 4xx with one line, never a traceback:
if __name__ == "__main__":
    bad = client.get("/api/landscape", params={"theta_w": 120})
    print(bad.status_code, bad.json()["detail"])

# %%
# The landscape from the service's ``npz`` answer, drawn here with the saddle its JSON answer named.
if __name__ == "__main__":
    fig, ax = plt.subplots(figsize=(6.4, 5.0))
    cs = ax.contourf(npz["pitch_deg"], npz["roll_deg"], npz["energy_j"].T * 1e3, levels=30, cmap="viridis")
    fig.colorbar(cs, ax=ax, label="potential energy (mJ)")
    ax.plot(*npz["minimum_deg"], "o", color="tab:red", label="start minimum")
    ax.plot(b["saddle_pitch_deg"], b["saddle_roll_deg"], "X", color="tab:orange", ms=10, label="saddle")
    ax.set(xlabel="body pitch (°)", ylabel="body roll (°)", title="GET /api/landscape?theta_w=74&theta_l=30")
    ax.legend(loc="lower left", fontsize=8)

    client.__exit__(None, None, None)  # stops the sweep runner
