"""Hostile and careless input through the real console script: exit status 2, one line on stderr, no traceback,
no output written, the inputs unchanged (issue #16)."""

from __future__ import annotations

import hashlib
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = Path(sys.executable).parent / "landscape"


def landscape(*args, cwd=None, timeout=120):
    exe = [str(SCRIPT)] if SCRIPT.is_file() else [sys.executable, "-m", "landscape"]
    env = {k: v for k, v in os.environ.items() if k != "LANDSCAPE_DEBUG"}
    return subprocess.run(
        [*exe, *map(str, args)], capture_output=True, text=True, cwd=cwd, timeout=timeout, env=env
    )


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture(scope="module")
def corpus(tmp_path_factory):
    d = tmp_path_factory.mktemp("hostile")
    import trimesh

    trimesh.creation.box(extents=(0.1, 0.06, 0.02)).export(d / "box.stl")
    (d / "not_a_db.sqlite").write_bytes(b"hello, I am not a database")
    (d / "robotdir").mkdir()
    return d


def refused(r, *needles):
    assert r.returncode == 2, (r.returncode, r.stdout, r.stderr)
    lines = r.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("landscape: error: "), r.stderr
    assert "Traceback" not in r.stderr + r.stdout
    for n in needles:
        assert n in r.stderr, (n, r.stderr)


@pytest.mark.parametrize(
    "args, needles",
    [
        (["compute", "--theta-w", "nan"], ["--theta-w must be a finite number"]),
        (["compute", "--theta-w", "120"], ["--theta-w 120 deg is outside [-10, 95] deg"]),
        (["compute", "--step", "7"], ["does not divide 360"]),
        (["compute", "--method", "magic"], ["magic"]),
        (["compute", "--robot", "{d}/robotdir"], ["is a directory"]),
        (["compute", "--mesh", "{d}/robotdir"], ["is a directory"]),
        (["compute", "--robot", "{d}/absent.urdf"], ["absent.urdf"]),
        (["compute", "--mesh", "{d}/box.stl", "--com", "0,0,0.5"], ["outside the convex hull"]),
        (
            ["compute", "--mesh", "{d}/box.stl", "--com", "0,0,0.5", "--method", "grid"],
            ["outside the convex hull"],
        ),
        (
            ["compute", "--mesh", "{d}/box.stl", "--com", "0,0,0.5", "--method", "sphere"],
            ["outside the convex hull"],
        ),
        (["compute", "--mesh", "{d}/box.stl", "--joints", "wing=a;leg=b"], ["--joints applies to a URDF"]),
        (["barrier-map", "--theta-w", "0:90:1e-7", "--out", "{d}/bm"], ["more than the 100000 allowed"]),
        (["barrier-map", "--theta-w", "0:1e308:1e-308", "--out", "{d}/bm"], ["more than the 100000 allowed"]),
        (["barrier-map", "--theta-w", "", "--out", "{d}/bm"], ["is empty"]),
        (["bench", "--repeat", "0"], ["--repeat"]),
        (["sweep", "--db", "{d}/s.sqlite", "--scheduler", "not a url"], ["not a scheduler address"]),
        (["export", "--db", "{d}/absent.sqlite", "--csv", "{d}/x.csv"], ["not found"]),
    ],
)
def test_refused_with_one_line(corpus, args, needles):
    r = landscape(*[a.format(d=corpus) for a in args])
    refused(r, *needles)
    assert (
        not (corpus / "bm").exists()
        and not (corpus / "s.sqlite").exists()
        and not (corpus / "x.csv").exists()
    )


def test_export_never_writes_over_its_input(corpus, tmp_path):
    db = tmp_path / "trials.sqlite"
    shutil.copy(corpus / "not_a_db.sqlite", db)
    before = digest(db)
    refused(landscape("export", "--db", db, "--csv", db), "also an input")
    assert digest(db) == before


def test_compute_json_is_strict(corpus):
    """JSON output never holds NaN or Infinity tokens, whatever the method."""
    import json

    for method in ("exact", "grid", "sphere"):
        r = landscape("compute", "--mesh", corpus / "box.stl", "--method", method, "--json")
        assert r.returncode == 0, r.stderr
        json.loads(r.stdout, parse_constant=lambda tok, m=method: pytest.fail(f"{m}: {tok} in JSON"))


@pytest.mark.e2e
def test_a_robot_the_landscape_accepts_can_be_simulated_and_swept(tmp_path):
    """A URDF with renamed joints and its --joints map: compute, simulate (no --dt) and sweep all accept it, and
    the sweep's rows are keyed by the mapped robot (#9)."""
    pytest.importorskip("pybullet")
    from geometry.builtin import URDF_NAME, builtin_description

    for name, data in builtin_description().items():
        (tmp_path / name).write_bytes(data)
    urdf = tmp_path / URDF_NAME
    text = urdf.read_text()
    for j in ("wing_pitch_left", "wing_pitch_right", "wing_roll_left", "wing_roll_right", "leg"):
        text = text.replace(f'joint name="{j}"', f'joint name="j_{j}"')
    urdf.write_text(text)
    jm = "wing=j_wing_pitch_left,j_wing_pitch_right,j_wing_roll_left,j_wing_roll_right;leg=j_leg"
    r = landscape("compute", "--robot", urdf, "--joints", jm, "--theta-w", "74", "--json")
    assert r.returncode == 0, r.stderr
    r = landscape(
        "simulate",
        "--robot",
        urdf,
        "--joints",
        jm,
        "--theta-w",
        "74",
        "--theta-l",
        "30",
        "--duration",
        "0.2",
        "--json",
    )
    assert r.returncode == 0, r.stderr
    db = tmp_path / "s.sqlite"
    r = landscape(
        "sweep",
        "--robot",
        urdf,
        "--joints",
        jm,
        "--theta-w",
        "74",
        "--theta-l",
        "30",
        "--cv",
        "0",
        "--trials",
        "1",
        "--duration",
        "0.2",
        "--db",
        db,
        "--workers",
        "1",
        "--no-progress",
    )
    assert r.returncode == 0, r.stderr
    refused(
        landscape(
            "sweep",
            "--robot",
            urdf,
            "--theta-w",
            "74",
            "--theta-l",
            "30",
            "--cv",
            "0",
            "--trials",
            "1",
            "--duration",
            "0.2",
            "--db",
            db,
            "--workers",
            "1",
            "--no-progress",
        ),
        "none of the default",
    )


def test_an_unwritable_cache_names_landscape_cache(tmp_path):
    """The built-in robot's files cannot be written: one line naming the cache and LANDSCAPE_CACHE (#16)."""
    blocker = tmp_path / "not_a_dir"
    blocker.write_text("a file where the cache directory should be")
    exe = [str(SCRIPT)] if SCRIPT.is_file() else [sys.executable, "-m", "landscape"]
    env = {**{k: v for k, v in os.environ.items() if k != "LANDSCAPE_DEBUG"}, "LANDSCAPE_CACHE": str(blocker)}
    r = subprocess.run(
        [*exe, "compute", "--theta-w", "74"], capture_output=True, text=True, env=env, timeout=300
    )
    refused(r, "cannot write the built-in robot's files", "LANDSCAPE_CACHE")


def _limited():
    """Run the child with 4 GiB of address space, so a regression that tries to allocate fails, not the host."""
    import resource

    resource.setrlimit(resource.RLIMIT_AS, (4 * 2**30, 4 * 2**30))


@pytest.mark.parametrize(
    "args, needle",
    [
        (
            ["simulate", "--theta-w", "74", "--theta-l", "30", "--duration", "1e308"],
            "--duration 1e+308 s is outside (0, 600] s",
        ),
        (
            ["simulate", "--theta-w", "74", "--theta-l", "30", "--duration", "1e6"],
            "--duration 1000000 s is outside (0, 600] s",
        ),
        (["simulate", "--theta-w", "74", "--theta-l", "30", "--dt", "1e-300"], "dt"),
        (["simulate", "--theta-w", "74", "--theta-l", "30", "--dt", "1e-9", "--duration", "0.1"], "dt"),
        (["sweep", "--trials", "1000000000", "--db", "{d}/big.sqlite"], "--trials"),
        (
            [
                "sweep",
                "--theta-w",
                "0:90:0.001",
                "--theta-l",
                "0:50:0.01",
                "--cv",
                "0",
                "--trials",
                "1",
                "--db",
                "{d}/big.sqlite",
            ],
            "more than MAX_TRIALS",
        ),
        (["barrier-map", "--theta-w", "0:90:1e-7", "--out", "{d}/bm"], "more than the 100000 allowed"),
        (["compute", "--step", "0.05"], "needs about 3.7 GB"),
    ],
)
def test_resource_bounds_refused_up_front_under_a_memory_limit(corpus, args, needle):
    """Requests that would exhaust memory or time are refused before any work, even with 4 GiB and 60 s."""
    exe = [str(SCRIPT)] if SCRIPT.is_file() else [sys.executable, "-m", "landscape"]
    env = {k: v for k, v in os.environ.items() if k != "LANDSCAPE_DEBUG"}
    r = subprocess.run(
        [*exe, *[a.format(d=corpus) for a in args]],
        capture_output=True,
        text=True,
        env=env,
        timeout=60,
        preexec_fn=_limited,
    )
    refused(r, needle)
    assert not (corpus / "big.sqlite").exists()
