"""A self-contained HTML report (figures embedded, tables inline, no external resources) and its check in
headless Chromium (edge layer).

The page carries a small self-check script: it records ``console.error`` calls and uncaught errors, and after the
``load`` event writes ``data-images-ok="N/M"`` (images decoded with a non-zero size), ``data-console-errors`` and
``data-selfcheck="done"`` on ``<body>``. :func:`check_page` loads the page in Debian's ``chromium`` with
``--dump-dom`` and reads those attributes back, together with the browser's own console log on stderr (Chromium
logs every console message as ``INFO:CONSOLE``; uncaught exceptions start with ``"Uncaught``), then takes a
screenshot.
"""

from __future__ import annotations

import base64
import csv
import html
import os
import re
import shutil
import struct
import subprocess
import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path

SELF_CHECK_JS = """
(function () {
  var errors = [];
  var orig = console.error;
  console.error = function () { errors.push(Array.prototype.join.call(arguments, " ")); };
  window.addEventListener("error", function (e) { errors.push(String(e.message || "resource error")); }, true);
  window.addEventListener("load", function () {
    var imgs = document.images, ok = 0;
    for (var i = 0; i < imgs.length; i++) { if (imgs[i].complete && imgs[i].naturalWidth > 0) { ok++; } }
    document.body.dataset.imagesOk = ok + "/" + imgs.length;
    document.body.dataset.consoleErrors = JSON.stringify(errors);
    document.body.dataset.selfcheck = "done";
    console.error = orig;
  });
})();
"""

CSS = """
body { font-family: system-ui, -apple-system, 'Segoe UI', sans-serif; max-width: 1100px; margin: 2em auto;
       padding: 0 1em; color: #222; line-height: 1.45; }
h1 { font-size: 1.6em; } h2 { border-bottom: 1px solid #ccc; padding-bottom: .2em; margin-top: 2em; }
table { border-collapse: collapse; margin: .6em 0 1.2em; font-size: .85em; }
th, td { border: 1px solid #bbb; padding: .2em .5em; text-align: right; }
th { background: #f0f0f0; } td.l, th.l { text-align: left; }
figure { margin: 1em 0; } figure img { max-width: 100%; height: auto; border: 1px solid #eee; }
figcaption { font-size: .85em; color: #555; }
.missing { background: #fff4e5; border-left: 4px solid #f0a020; padding: .6em 1em; }
code { background: #f4f4f4; padding: 0 .25em; }
.small { font-size: .85em; color: #555; }
"""


@dataclass(frozen=True)
class Figure:
    """A PNG embedded in the page (and an SVG beside it, linked)."""

    png: Path
    caption: str
    svg: Path | None = None


@dataclass(frozen=True)
class Table:
    """A CSV file shown as an HTML table (the first ``max_rows`` rows) and linked."""

    title: str
    csv: Path
    max_rows: int = 60


@dataclass(frozen=True)
class Section:
    """One analysis on the page; ``missing`` replaces its content with what to run to get the data."""

    key: str
    title: str
    paragraphs: tuple[str, ...] = ()
    figures: tuple[Figure, ...] = ()
    tables: tuple[Table, ...] = ()
    missing: str | None = None


def png_size(path: Path) -> tuple[int, int]:
    """(width, height) in pixels from a PNG's IHDR chunk.

    Raises
    ------
    ValueError
        If the file is not a PNG.
    """
    head = Path(path).read_bytes()[:24]
    if head[:8] != b"\x89PNG\r\n\x1a\n" or head[12:16] != b"IHDR":
        raise ValueError(f"'{path}' is not a PNG file")
    return struct.unpack(">II", head[16:24])


def _text(s: str) -> str:
    """Escape, then turn `code` spans into <code>."""
    return re.sub(r"`([^`]+)`", r"<code>\1</code>", html.escape(s))


def _rel(path: Path, base: Path) -> str:
    try:
        return Path(os.path.relpath(Path(path).resolve(), base.resolve())).as_posix()
    except ValueError:
        return Path(path).resolve().as_uri()


def _table_html(t: Table, base: Path) -> str:
    with open(t.csv, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return f"<p>{html.escape(t.title)}: (empty)</p>"
    head, body = rows[0], rows[1:]
    out = [f"<h3>{html.escape(t.title)} <span class='small'>(<a href='{html.escape(_rel(t.csv, base))}'>"
           f"{html.escape(Path(t.csv).name)}</a>)</span></h3>", "<table><tr>"]
    out += [f"<th>{html.escape(h)}</th>" for h in head]
    out.append("</tr>")
    for r in body[: t.max_rows]:
        out.append("<tr>" + "".join(f"<td>{html.escape(c)}</td>" for c in r) + "</tr>")
    out.append("</table>")
    if len(body) > t.max_rows:
        out.append(f"<p class='small'>… {len(body) - t.max_rows} more rows in <a href='"
                   f"{html.escape(_rel(t.csv, base))}'>{html.escape(Path(t.csv).name)}</a></p>")
    return "\n".join(out)


def _kv_table(d: Mapping[str, str]) -> str:
    rows = "".join(f"<tr><th class='l'>{html.escape(str(k))}</th><td class='l'>{html.escape(str(v))}</td></tr>"
                   for k, v in d.items())
    return f"<table>{rows}</table>"


def write_report(sections: Sequence[Section], out_dir: Path, *, title: str, inputs: Mapping[str, str],
                 versions: Mapping[str, str], timings_s: Mapping[str, float], filename: str = "index.html") -> Path:
    """Write one self-contained HTML page; return its path.

    Parameters
    ----------
    sections : sequence of Section
    out_dir : Path
        Directory of the page (created); tables and SVGs are linked relative to it.
    title : str
    inputs, versions : mapping of str to str
        Shown as tables (the data used; software versions).
    timings_s : mapping of str to float
        Run time of each part, s.

    Returns
    -------
    Path
    """
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    stamp = datetime.now(timezone.utc).isoformat(timespec="seconds")
    parts = ["<!DOCTYPE html>", "<html lang='en'><head><meta charset='utf-8'>",
             f"<title>{html.escape(title)}</title>", f"<style>{CSS}</style>",
             f"<script>{SELF_CHECK_JS}</script>", "</head><body>", f"<h1>{html.escape(title)}</h1>",
             f"<p class='small'>Generated {stamp} (UTC).</p>", "<ul>"]
    parts += [f"<li><a href='#{html.escape(s.key)}'>{html.escape(s.title)}</a>"
              + (" (not enough data)" if s.missing else "") + "</li>" for s in sections]
    parts += ["<li><a href='#inputs'>Inputs, software and run times</a></li>", "</ul>"]
    for s in sections:
        parts.append(f"<h2 id='{html.escape(s.key)}'>{html.escape(s.title)}</h2>")
        if s.missing:
            parts.append(f"<div class='missing'>Not enough data: {_text(s.missing)}</div>")
            continue
        parts += [f"<p>{_text(p)}</p>" for p in s.paragraphs]
        for fig in s.figures:
            w, h = png_size(fig.png)
            data = base64.b64encode(Path(fig.png).read_bytes()).decode()
            links = f" <a href='{html.escape(_rel(fig.png, out_dir))}'>PNG</a>"
            if fig.svg is not None:
                links += f" · <a href='{html.escape(_rel(fig.svg, out_dir))}'>SVG</a>"
            parts.append(f"<figure><img src='data:image/png;base64,{data}' width='{w}' height='{h}' "
                         f"alt='{html.escape(fig.caption)}'><figcaption>{_text(fig.caption)} ({links.strip()})"
                         "</figcaption></figure>")
        parts += [_table_html(t, out_dir) for t in s.tables]
    parts += ["<h2 id='inputs'>Inputs, software and run times</h2>", "<h3>Inputs</h3>", _kv_table(inputs),
              "<h3>Software versions</h3>", _kv_table(versions), "<h3>Run times</h3>",
              _kv_table({k: f"{v:.2f} s" for k, v in timings_s.items()}), "</body></html>"]
    path = out_dir / filename
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text("\n".join(parts), encoding="utf-8")
    os.replace(tmp, path)
    return path


# ---------------------------------------------------------------------------------------------- browser check
@dataclass(frozen=True)
class PageCheck:
    """Result of :func:`check_page`."""

    ok: bool
    images_ok: int
    images_total: int
    console_errors: tuple[str, ...]
    screenshot: Path | None
    browser: str


CHROMIUM_FLAGS = ("--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
                  "--disable-background-networking", "--disable-component-update", "--disable-sync")


def find_chromium() -> str | None:
    """Path of a Chromium executable (``$LANDSCAPE_CHROMIUM`` first), or None."""
    env = os.environ.get("LANDSCAPE_CHROMIUM")
    if env:
        return env if Path(env).is_file() else shutil.which(env)
    for name in ("chromium", "chromium-browser", "google-chrome", "chrome"):
        found = shutil.which(name)
        if found:
            return found
    return None


def _run_chromium(exe: str, args: list[str], timeout_s: float) -> subprocess.CompletedProcess:
    with tempfile.TemporaryDirectory(prefix="landscape-chromium-") as profile:
        try:
            return subprocess.run([exe, *CHROMIUM_FLAGS, f"--user-data-dir={profile}", *args], capture_output=True,
                                  text=True, timeout=timeout_s, check=False)
        except subprocess.TimeoutExpired:
            raise RuntimeError(f"chromium did not finish within {timeout_s:g} s") from None


def check_page(page: Path, *, screenshot: Path | None = None, timeout_s: float = 60.0) -> PageCheck:
    """Open an HTML page in headless Chromium: images loaded, console errors, optional screenshot.

    Raises
    ------
    RuntimeError
        If Chromium is not installed or does not finish in time.
    """
    exe = find_chromium()
    if exe is None:
        raise RuntimeError("chromium not found; install Debian's chromium package (apt-get install chromium)")
    url = Path(page).resolve().as_uri()
    version = subprocess.run([exe, "--version"], capture_output=True, text=True, timeout=timeout_s).stdout.strip()
    res = _run_chromium(exe, ["--enable-logging=stderr", "--v=0", "--virtual-time-budget=5000", "--dump-dom", url],
                        timeout_s)
    dom = res.stdout
    m = re.search(r'data-images-ok="(\d+)/(\d+)"', dom)
    ok_img, total = (int(m.group(1)), int(m.group(2))) if m else (0, -1)
    done = 'data-selfcheck="done"' in dom
    errors: list[str] = []
    em = re.search(r'data-console-errors="([^"]*)"', dom)
    if em:
        import json

        errors += [str(e) for e in json.loads(html.unescape(em.group(1)) or "[]")]
    for line in res.stderr.splitlines():  # uncaught exceptions before the self-check was installed, too
        cm = re.search(r':CONSOLE[^\]]*\] "(Uncaught[^"]*)"', line)
        if cm and cm.group(1) not in errors:
            errors.append(cm.group(1))
    if not done:
        errors.append(f"the page's self-check did not run (chromium exit status {res.returncode})")
    shot = None
    if screenshot is not None:
        screenshot = Path(screenshot).resolve()
        screenshot.parent.mkdir(parents=True, exist_ok=True)
        _run_chromium(exe, [f"--screenshot={screenshot}", "--window-size=1280,2000", "--hide-scrollbars", url],
                      timeout_s)
        if screenshot.is_file() and screenshot.stat().st_size > 0:
            png_size(screenshot)
            shot = screenshot
        else:
            errors.append("chromium wrote no screenshot")
    ok = done and total >= 0 and ok_img == total and not errors and (screenshot is None or shot is not None)
    return PageCheck(ok, ok_img, max(total, 0), tuple(errors), shot, version)
