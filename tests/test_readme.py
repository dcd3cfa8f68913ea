"""The README's and the documentation pages' examples run as written (so a line that stops working turns CI red)."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"
DOCS = ROOT / "docs"
PAGES = [README] + sorted(
    p for p in DOCS.rglob("*.md") if not {"_build", "auto_examples"} & set(p.relative_to(DOCS).parts)
)
"""The README and every Markdown page of the documentation: their examples run as written."""
TWINS_PAGE = DOCS / "howto" / "python_api.md"
SERVICE_PAGE = DOCS / "howto" / "service.md"


def _page_id(page: Path) -> str:
    return str(page.relative_to(ROOT))


def _fenced_blocks(info: str, page: Path = README) -> list[str]:
    """The page's fenced code blocks whose info string is ``info`` ("" for plain ```)."""
    blocks, current = [], None
    for line in page.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            if current is None:
                current = [] if line[3:].strip() == info else False
            else:
                if current is not False:
                    blocks.append("\n".join(current) + "\n")
                current = None
        elif current:
            current.append(line)
        elif current == []:
            current.append(line)
    return blocks


def _python_blocks() -> list[str]:
    return _fenced_blocks(info="python", page=TWINS_PAGE)


def test_the_python_api_page_has_the_python_twins():
    blocks = _python_blocks()
    assert blocks, "the Python API page lost its block"
    text = "\n".join(blocks)
    for cmd in (
        "compute",
        "barrier-map",
        "render",
        "simulate",
        "sweep",
        "export",
        "analyze",
        "report",
        "bench",
        "robot export",
        "physical table",
        "physical kinematics",
        "physical actuation",
        "physical validate",
        "physical calibrate",
        "serve",
    ):
        assert f"# landscape {cmd}" in text or f"; landscape {cmd}" in text, f"no Python twin for {cmd}"


@pytest.mark.e2e
@pytest.mark.parametrize("block", _python_blocks())
def test_python_twin_block_runs(block, capsys, monkeypatch):
    pytest.importorskip("pybullet")
    monkeypatch.chdir(ROOT)  # the block names ../shared relative to the checkout
    namespace: dict = {}
    exec(compile(block, str(TWINS_PAGE), "exec"), namespace)
    out = capsys.readouterr().out
    assert "righting" in out and "mJ by roll" in out
    assert namespace["summary"].ran == 2 and namespace["page"].is_file()
    assert "speed-up" in namespace["table"] and "robot.urdf" in namespace["files_by_name"]


PYCON = [(page, block) for page in PAGES for block in _fenced_blocks("pycon", page)]


def test_the_readme_has_a_python_snippet():
    assert any(page == README for page, _ in PYCON), "the README lost its Python snippet"


@pytest.mark.parametrize("page, block", PYCON, ids=[f"{_page_id(p)}-{i}" for i, (p, _) in enumerate(PYCON)])
def test_pycon_block_prints_what_the_page_shows(page, block):
    """A ``pycon`` block is a doctest: every ``>>>`` line runs and prints what the page shows under it."""
    import doctest

    pytest.importorskip("pybullet")
    test = doctest.DocTestParser().get_doctest(block, {}, _page_id(page), str(page), 0)
    runner = doctest.DocTestRunner(optionflags=doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE)
    runner.run(test)
    assert runner.failures == 0 and runner.tries > 0, f"{_page_id(page)}: see the doctest report above"


def test_every_service_endpoint_has_a_curl_and_a_python_example():
    routes = re.findall(
        r'@app\.(get|post|delete)\("(/api/[^"]*)"', (ROOT / "landscape/service/app.py").read_text()
    )
    assert len(routes) >= 15
    text = SERVICE_PAGE.read_text(encoding="utf-8")
    curl = "\n".join(_fenced_blocks("bash", SERVICE_PAGE))
    python = "\n".join(_fenced_blocks("python", SERVICE_PAGE))
    for method, path in routes:
        generic = re.sub(r"\{[^}]*\}", "{}", path)  # {job_id} on the page is {id}
        assert generic in re.sub(r"\{[^}]*\}", "{}", text), f"the page does not name {method.upper()} {path}"
        fixed = re.sub(r"\{[^}]*\}.*", "", path)  # the part before the first path parameter
        tail = path.rstrip("/").rsplit("/", 1)[-1]
        tail = "" if tail.startswith("{") else tail
        assert fixed in curl and tail in curl, f"{method.upper()} {path}: no curl example"
        assert f'"{fixed}' in python or f'f"{fixed}' in python, f"{method.upper()} {path}: no Python example"
        if method != "get":
            assert f"-X {method.upper()}" in curl or "-F " in curl, (
                f"{method.upper()} {path}: curl without -X"
            )
            assert f"api.{method}(" in python, f"{method.upper()} {path}: no api.{method} call"


@pytest.mark.e2e
def test_the_service_page_python_examples_run(tmp_path):
    """docs/howto/service.md's Python examples, in order, against the app in process (TestClient for httpx)."""
    pytest.importorskip("fastapi")
    pytest.importorskip("httpx2")
    from fastapi.testclient import TestClient

    from landscape.service.app import create_app
    from landscape.service.config import ServiceConfig

    blocks = _fenced_blocks("python", SERVICE_PAGE)
    assert 'api = httpx.Client(base_url="http://127.0.0.1:8000")' in blocks[0]
    with TestClient(create_app(ServiceConfig(data_dir=tmp_path / "data", workers=1))) as client:
        namespace: dict = {"api": client}
        for block in blocks[1:]:
            exec(compile(block, str(SERVICE_PAGE), "exec"), namespace)
    assert namespace["job"]["status"] == "done" and namespace["rows"]


# ---------------------------------------------------------------------------------------------- $ landscape ...
VOLATILE = (
    "timing",
    "ms",
    " s ",
    " s;",
    " s)",
    "trials/s",
    "CPU",
    "/root/",
    "checked in",
    "...",
    "…",
    "wrote",
    "seed ",
    "0 already in",
    "s wall",
)
"""Output lines holding times, paths or machine-dependent counts: not compared."""


def _examples(page: Path = README) -> list[tuple[str, list[str]]]:
    """Every `$ landscape ...` line of a page with the output lines printed under it."""
    out: list[tuple[str, list[str]]] = []
    for block in _fenced_blocks(info="", page=page):
        current = None  # output lines belong to the command above them in the same block
        for line in block.splitlines():
            if line.startswith("$ landscape"):
                current = (line[2:].strip(), [])
                out.append(current)
            elif current is not None and line.strip() and not line.startswith("$"):
                current[1].append(line.rstrip())
    return out


def _slow(cmd: str) -> bool:
    return (
        "results.sqlite" in cmd
        or (" sweep" in cmd and "--trials" not in cmd)
        or " report" in cmd
        or " physical validate" in cmd
        or " physical calibrate" in cmd
        or " analyze compare" in cmd  # two paper-sized databases, one per engine
    )


def _marks(cmd: str) -> list:
    """slow: the paper-sized runs; e2e: the small sweeps (CI runs them as a step of their own)."""
    if _slow(cmd):
        return [pytest.mark.slow]
    return [pytest.mark.e2e] if " sweep" in cmd else []


EXAMPLES = [(page, c, e) for page in PAGES for c, e in _examples(page)]


def test_the_readme_shows_examples():
    readme = [c for page, c, _ in EXAMPLES if page == README]
    assert len(readme) >= 5 and any(c.startswith("landscape compute") for c in readme)
    for cmd in ("compute", "render", "barrier-map", "sweep", "report"):
        assert any(c.startswith(f"landscape {cmd} ") for c in readme), f"the README's tour lost {cmd}"


def test_the_tour_pictures_come_from_the_tours_own_commands():
    """figures/tour_figures.py runs the README's render, sweep and report commands as written and copies the
    pictures the README shows."""
    import importlib.util

    spec = importlib.util.spec_from_file_location("tour_figures", ROOT / "figures" / "tour_figures.py")
    tour = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tour)
    readme = [c for page, c, _ in EXAMPLES if page == README]
    for command in tour.COMMANDS:
        assert f"landscape {command}" in readme, command
    text = README.read_text(encoding="utf-8")
    for name in tour.COPIES.values():
        assert f"figures/tour/{name}" in text and (ROOT / "figures" / "tour" / name).is_file(), name


def _run(cmd: str, cwd: Path):
    import shlex
    import subprocess
    import sys

    args = shlex.split(cmd)
    args = [str(ROOT.parent / a[3:]) if a.startswith("../shared") else a for a in args]
    exe = Path(sys.executable).parent / "landscape"
    return subprocess.run([str(exe), *args[1:]], capture_output=True, text=True, cwd=cwd, timeout=900)


def _db(cmd: str) -> str | None:
    import shlex

    args = shlex.split(cmd)
    return args[args.index("--db") + 1] if "--db" in args[:-1] else None


def _page_scripts(page: Path) -> list[tuple[str, str]]:
    """The scripts a page writes and runs: a ```python block followed by a block whose first line is
    `$ python NAME.py` (NAME.py is that block), in page order."""
    scripts, last_python, info, lines = [], None, None, []
    for line in page.read_text(encoding="utf-8").splitlines():
        if line.startswith("```"):
            if info is None:
                info, lines = line[3:].strip(), []
                continue
            if info == "python":
                last_python = "\n".join(lines) + "\n"
            elif info == "" and lines and last_python is not None:
                m = re.fullmatch(r"\$ python (\S+\.py)", lines[0].strip())
                if m:
                    scripts.append((m.group(1), last_python))
            info = None
        elif info is not None:
            lines.append(line)
    return scripts


@pytest.fixture(scope="module")
def page_dirs(tmp_path_factory):
    """One scratch directory per page: a page's commands run in order there, so a report finds its sweep; the
    scripts the page writes and runs (:func:`_page_scripts`) run there first."""
    import subprocess
    import sys

    dirs = {}
    for page in PAGES:
        cwd = dirs[page] = tmp_path_factory.mktemp(page.stem)
        for name, code in _page_scripts(page):
            (cwd / name).write_text(code, encoding="utf-8")
            r = subprocess.run([sys.executable, name], capture_output=True, text=True, cwd=cwd, timeout=300)
            assert r.returncode == 0, f"{_page_id(page)}: `python {name}` failed:\n{r.stdout}{r.stderr}"
    return dirs


def test_a_page_script_runs_before_the_page_commands(tmp_path):
    """The legless-body page writes its URDF with a script; the harness finds it."""
    scripts = _page_scripts(DOCS / "howto" / "legless_body.md")
    assert [name for name, _ in scripts] == ["make_flapper.py"] and "flapper.urdf" in scripts[0][1]


@pytest.mark.parametrize(
    "page, cmd, expected",
    [pytest.param(p, c, e, marks=_marks(c), id=f"{_page_id(p)}: {c[:60]}") for p, c, e in EXAMPLES],
)
def test_command_prints_what_the_page_shows(page, cmd, expected, page_dirs):
    """Each command of a page runs as written (in that page's scratch directory) and prints the page's stable
    lines; a command reading a database an earlier command of the page writes gets that command run first."""
    if "../shared" in cmd and not (ROOT.parent / "shared").is_dir():
        pytest.skip("needs ../shared")
    cwd = page_dirs[page]
    db = _db(cmd)
    if db and not (cwd / db).exists() and " sweep " not in cmd:
        producers = [c for p, c, _ in EXAMPLES if p == page and " sweep " in c and _db(c) == db]
        if producers:
            made = _run(producers[0], cwd)
            assert made.returncode == 0, made.stdout + made.stderr
    r = _run(cmd, cwd)
    text = r.stdout + r.stderr
    error_example = any(e.startswith("landscape: error:") for e in expected)
    assert (r.returncode == 2) if error_example else (r.returncode == 0), text
    if "--json" in cmd.split():
        _check_json_excerpt(expected, r.stdout, cmd)
        return
    for line in expected:
        if not any(v in line for v in VOLATILE):
            assert line.strip() in text, f"README line not printed by `{cmd}`:\n{line}\n--- got ---\n{text}"


def _leaves(obj, out: dict) -> dict:
    if isinstance(obj, dict):
        for k, v in obj.items():
            if isinstance(v, (dict, list)):
                _leaves(v, out)
            else:
                out.setdefault(k, []).append(v)
    elif isinstance(obj, list):
        out.setdefault("", []).extend(obj)
    return out


def _check_json_excerpt(expected: list[str], stdout: str, cmd: str) -> None:
    """A README JSON excerpt is abridged and rounded: every `"key": number` shown must be a value of that key
    in the real output, to the digits shown; every `"key": "text"` must be there as written."""
    import json

    values = _leaves(json.loads(stdout), {})
    pairs = re.findall(r'"(\w+)": (-?[0-9]+(?:\.[0-9]+)?|"[^"]*")', "\n".join(expected))
    assert pairs, cmd
    for key, shown in pairs:
        got = values.get(key, [])
        if shown.startswith('"'):
            assert shown.strip('"') in got, (key, shown, got)
        else:
            digits = len(shown.split(".")[1]) if "." in shown else 0
            assert any(isinstance(v, (int, float)) and round(v, digits) == float(shown) for v in got), (
                key,
                shown,
                got,
            )
