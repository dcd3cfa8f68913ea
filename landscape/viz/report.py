"""A self-contained HTML report (figures embedded, tables inline, no external resources) and its check in
headless Chromium (edge layer: writes files, starts a browser).

The module knows nothing of the science: the caller supplies the :class:`Section` objects, with their text,
PNG/SVG figures and CSV tables, and :func:`write_report` lays them out on one page that needs nothing but itself
(inline CSS, images as ``data:`` URIs, no fonts, no CDN, no JavaScript library).

The page carries a small self-check script (:data:`SELF_CHECK_JS`, itself silent on the console). It records
``console.error`` calls, uncaught exceptions, unhandled promise rejections and failed non-image resources, and
after the ``load`` event writes on ``<body>``:

- ``data-images-ok="N/M"``: N of the M ``<img>`` decoded with a non-zero width (``complete && naturalWidth > 0``);
- ``data-console-errors``: the recorded errors as a JSON list of strings;
- ``data-selfcheck="done"``.

:func:`check_page` loads the page in Debian's ``chromium`` with ``--dump-dom`` and reads those attributes back,
together with the browser's own console log on stderr. Chromium (checked with 156) logs *every* console message
as ``INFO``, whatever its level::

    [27702:27702:1122/131312.278420:INFO:CONSOLE:2] "boom 42", source: file:///tmp/p.html (2)
    [27702:27702:1122/131312.279972:INFO:CONSOLE:5] "Uncaught ReferenceError: f is not defined", source: file:///tmp/p.html (5)

so ``console.error`` and ``console.log`` cannot be told apart there: ``console.error`` is caught by the page's
self-check, and uncaught exceptions (``"Uncaught …"``, ``"Uncaught (in promise) …"``) are read from both.

It is one concept, the report page (layout, embedding, browser check), hence its length.
"""

from __future__ import annotations

import base64
import csv
import json
import os
import re
import shutil
import signal
import struct
import subprocess
import tempfile
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from datetime import datetime, timezone
from html import escape
from html.parser import HTMLParser
from pathlib import Path

PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
RESERVED_KEYS = ("contents", "inputs", "versions", "timings")
CHROMIUM_NAMES = ("chromium", "chromium-browser", "google-chrome", "chrome")
CHROMIUM_NOT_FOUND = "chromium not found; install Debian's chromium package (apt-get install chromium)"
CHROMIUM_FLAGS = (
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-quic",
    "--no-first-run",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
)
VIRTUAL_TIME_BUDGET_MS = 5000
SCREENSHOT_SIZE_PX = (1280, 2000)

SELF_CHECK_JS = """
(function () {
  "use strict";
  var errors = [];
  function record(msg) {
    errors.push(String(msg));
    if (document.body) { document.body.dataset.consoleErrors = JSON.stringify(errors); }
  }
  var original = console.error;
  console.error = function () {
    record("console.error: " + Array.prototype.map.call(arguments, String).join(" "));
    return original.apply(console, arguments);
  };
  window.addEventListener("error", function (e) {
    var t = e.target;
    if (t && t !== window && t.tagName) {
      if (t.tagName !== "IMG") { record("Failed to load <" + t.tagName.toLowerCase() + "> " + (t.src || t.href || "")); }
    } else {
      record(e.message + (e.filename ? " (" + e.filename + ":" + e.lineno + ")" : ""));
    }
  }, true);
  window.addEventListener("unhandledrejection", function (e) { record("Uncaught (in promise) " + String(e.reason)); });
  window.addEventListener("load", function () {
    var imgs = document.images, ok = 0;
    for (var i = 0; i < imgs.length; i++) { if (imgs[i].complete && imgs[i].naturalWidth > 0) { ok++; } }
    document.body.dataset.imagesOk = ok + "/" + imgs.length;
    document.body.dataset.consoleErrors = JSON.stringify(errors);
    document.body.dataset.selfcheck = "done";
  });
})();
"""

CSS = """
body { font-family: system-ui, -apple-system, 'Segoe UI', Roboto, sans-serif; max-width: 1100px; margin: 2em auto;
       padding: 0 1em; color: #222; line-height: 1.45; }
h1 { font-size: 1.6em; } h2 { border-bottom: 1px solid #ccc; padding-bottom: .2em; margin-top: 2em; }
table { border-collapse: collapse; margin: .6em 0 1.2em; font-size: .85em; }
th, td { border: 1px solid #bbb; padding: .2em .5em; text-align: right; vertical-align: top; }
th { background: #f0f0f0; } td.l, th.l { text-align: left; }
figure { margin: 1em 0; } figure img { max-width: 100%; height: auto; border: 1px solid #eee; }
figcaption { font-size: .85em; color: #555; }
.missing { background: #fff4e5; border-left: 4px solid #f0a020; padding: .6em 1em; margin: 1em 0; }
code { background: #f4f4f4; padding: 0 .25em; }
.small { font-size: .85em; color: #555; }
"""


@dataclass(frozen=True)
class Figure:
    """A PNG embedded in the page, with an optional SVG beside it (linked, not embedded).

    Parameters
    ----------
    png : Path
        PNG file; embedded as a ``data:image/png;base64`` URI.
    caption : str
        Plain text (escaped; `backticks` become ``<code>``); also the image's ``alt`` text.
    svg : Path or None
        SVG file linked from the caption with a path relative to the page.
    """

    png: Path
    caption: str
    svg: Path | None = None


@dataclass(frozen=True)
class Table:
    """A CSV file with a header row, shown as an HTML table and linked.

    Parameters
    ----------
    title : str
        Heading above the table.
    csv : Path
        CSV file, UTF-8, first row the header.
    max_rows : int
        Body rows shown (>= 0); the rest are counted in a line linking the CSV.
    """

    title: str
    csv: Path
    max_rows: int = 60


@dataclass(frozen=True)
class Section:
    """One part of the page.

    Parameters
    ----------
    key : str
        HTML id of the section (non-empty, no whitespace, unique on the page).
    title : str
        Heading, also listed in the table of contents.
    paragraphs : tuple of str
        Plain text paragraphs (escaped; `backticks` become ``<code>``).
    figures, tables : tuple of Figure, tuple of Table
        Content, in this order after the paragraphs.
    missing : str or None
        When set, a highlighted box "Not enough data: <missing>" replaces the figures and tables; the text
        should name the command that produces the data.
    """

    key: str
    title: str
    paragraphs: tuple[str, ...] = ()
    figures: tuple[Figure, ...] = ()
    tables: tuple[Table, ...] = ()
    missing: str | None = None


def png_size(path: Path) -> tuple[int, int]:
    """Width and height of a PNG image, read from its IHDR chunk.

    Parameters
    ----------
    path : Path
        PNG file.

    Returns
    -------
    width_px, height_px : int
        Image size, pixels.

    Raises
    ------
    ValueError
        If the file is not a PNG (signature or IHDR chunk missing).

    Examples
    --------
    >>> head = PNG_SIGNATURE + struct.pack(">I", 13) + b"IHDR" + struct.pack(">II", 640, 480)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     p = Path(d) / "x.png"
    ...     _ = p.write_bytes(head)
    ...     png_size(p)
    (640, 480)
    """
    with open(path, "rb") as f:
        head = f.read(24)
    if len(head) < 24 or head[:8] != PNG_SIGNATURE or head[12:16] != b"IHDR":
        raise ValueError(
            f"'{path}' is not a PNG file (no PNG signature and IHDR chunk in its first 24 bytes)"
        )
    width_px, height_px = struct.unpack(">II", head[16:24])
    return int(width_px), int(height_px)


def _text(s: str) -> str:
    """Escape plain text, then turn `code` spans into <code>."""
    return re.sub(r"`([^`]+)`", r"<code>\1</code>", escape(s))


def _rel(path: Path, base: Path) -> str:
    """``path`` relative to the directory ``base``, as an escaped href."""
    return escape(Path(os.path.relpath(Path(path).resolve(), base.resolve())).as_posix())


def _is_number(s: str) -> bool:
    try:
        float(s)
    except ValueError:
        return False
    return True


def _cell(tag: str, s: str) -> str:
    cls = "" if _is_number(s) else " class='l'"
    return f"<{tag}{cls}>{escape(s)}</{tag}>"


def _table_html(t: Table, base: Path) -> str:
    with open(t.csv, newline="", encoding="utf-8-sig") as f:
        rows = list(csv.reader(f))
    href, name = _rel(t.csv, base), escape(Path(t.csv).name)
    out = [f"<h3>{escape(t.title)} <span class='small'>(<a href='{href}'>{name}</a>)</span></h3>"]
    if not rows:
        return "\n".join([*out, "<p class='small'>(empty)</p>"])
    head, body = rows[0], rows[1:]
    out.append("<table><thead><tr>" + "".join(_cell("th", h) for h in head) + "</tr></thead><tbody>")
    out += ["<tr>" + "".join(_cell("td", c) for c in r) + "</tr>" for r in body[: t.max_rows]]
    out.append("</tbody></table>")
    if len(body) > t.max_rows:
        out.append(
            f"<p class='small'>… {len(body) - t.max_rows} more rows in <a href='{href}'>{name}</a></p>"
        )
    return "\n".join(out)


def _figure_html(fig: Figure, base: Path) -> str:
    width_px, height_px = png_size(fig.png)
    data = base64.b64encode(Path(fig.png).read_bytes()).decode("ascii")
    links = f"<a href='{_rel(fig.png, base)}'>PNG</a>"
    if fig.svg is not None:
        links += f" · <a href='{_rel(fig.svg, base)}'>SVG</a>"
    return (
        f"<figure><img src='data:image/png;base64,{data}' width='{width_px}' height='{height_px}' "
        f"alt='{escape(fig.caption)}'><figcaption>{_text(fig.caption)} ({links})</figcaption></figure>"
    )


def _kv_table(d: Mapping[str, str], header: tuple[str, str]) -> str:
    rows = "".join(
        f"<tr><th class='l'>{escape(str(k))}</th><td class='l'>{escape(str(v))}</td></tr>"
        for k, v in d.items()
    )
    return (
        f"<table><thead><tr><th class='l'>{escape(header[0])}</th><th class='l'>{escape(header[1])}</th>"
        f"</tr></thead><tbody>{rows}</tbody></table>"
    )


def _check_sections(sections: Sequence[Section]) -> None:
    seen: set[str] = set()
    for s in sections:
        if not s.key or re.search(r"\s", s.key):
            raise ValueError(f"Section key must be a non-empty HTML id without whitespace; got {s.key!r}")
        if s.key in seen or s.key in RESERVED_KEYS:
            raise ValueError(
                f"Section key {s.key!r} is used twice or reserved ({', '.join(RESERVED_KEYS)}); "
                "give each section its own key"
            )
        if s.missing is None:
            for t in s.tables:
                if t.max_rows < 0:
                    raise ValueError(f"Table {t.title!r}: max_rows must be >= 0; got {t.max_rows}")
        seen.add(s.key)


def write_report(
    sections: Sequence[Section],
    out_dir: Path,
    *,
    title: str,
    inputs: Mapping[str, str],
    versions: Mapping[str, str],
    timings_s: Mapping[str, float],
    filename: str = "index.html",
) -> Path:
    """Write one self-contained HTML page: table of contents, sections, inputs, versions and run times.

    Images are embedded as ``data:`` URIs with their pixel size from the PNG header; tables and SVGs are linked
    with paths relative to ``out_dir``. The page loads nothing from outside itself. The file is written to a
    temporary name and renamed, so a reader never sees half a page.

    Parameters
    ----------
    sections : sequence of Section
        Content, in page order.
    out_dir : Path
        Directory of the page (created if needed).
    title : str
        Page title and top heading.
    inputs, versions : mapping of str to str
        Shown as the "Inputs" (the data used) and "Software versions" tables.
    timings_s : mapping of str to float
        Run time of each part, seconds; shown with 2 decimals.
    filename : str
        Name of the page inside ``out_dir``.

    Returns
    -------
    path : Path
        The page written, ``out_dir / filename``.

    Raises
    ------
    ValueError
        If a section key is empty, holds whitespace, repeats or is reserved, a table's ``max_rows`` < 0, or a
        figure is not a PNG.
    FileNotFoundError
        If a figure's PNG or a table's CSV does not exist.

    Examples
    --------
    >>> with tempfile.TemporaryDirectory() as d:
    ...     page = write_report([Section("sweep", "Sweep", missing="run `landscape sweep`")], Path(d), title="T",
    ...                         inputs={"db": "x.sqlite"}, versions={"python": "3.11"}, timings_s={"all": 0.5})
    ...     text = page.read_text(encoding="utf-8")
    >>> page.name, "Not enough data: run <code>landscape sweep</code>" in text, "0.50 s" in text
    ('index.html', True, True)
    """
    _check_sections(sections)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    stamp = datetime.now(timezone.utc).isoformat(timespec="seconds")
    parts = [
        "<!DOCTYPE html>",
        "<html lang='en'><head><meta charset='utf-8'>",
        "<meta name='viewport' content='width=device-width, initial-scale=1'>",
        f"<title>{escape(title)}</title>",
        f"<style>{CSS}</style>",
        f"<script>{SELF_CHECK_JS}</script>",
        "</head><body>",
        f"<h1>{escape(title)}</h1>",
        f"<p class='small'>Generated <time datetime='{stamp}'>{stamp}</time> (UTC).</p>",
        "<nav id='contents'><h2>Contents</h2><ul>",
    ]
    parts += [
        f"<li><a href='#{escape(s.key)}'>{escape(s.title)}</a>"
        + (" <span class='small'>(not enough data)</span>" if s.missing is not None else "")
        + "</li>"
        for s in sections
    ]
    parts += [
        "<li><a href='#inputs'>Inputs</a></li>",
        "<li><a href='#versions'>Software versions</a></li>",
        "<li><a href='#timings'>Run times</a></li>",
        "</ul></nav>",
    ]
    for s in sections:
        parts.append(f"<section id='{escape(s.key)}'><h2>{escape(s.title)}</h2>")
        parts += [f"<p>{_text(p)}</p>" for p in s.paragraphs]
        if s.missing is not None:
            parts.append(f"<div class='missing'>Not enough data: {_text(s.missing)}</div>")
        else:
            parts += [_figure_html(f, out_dir) for f in s.figures]
            parts += [_table_html(t, out_dir) for t in s.tables]
        parts.append("</section>")
    parts += [
        "<section id='inputs'><h2>Inputs</h2>",
        _kv_table(inputs, ("input", "value")),
        "</section>",
        "<section id='versions'><h2>Software versions</h2>",
        _kv_table(versions, ("software", "version")),
        "</section>",
        "<section id='timings'><h2>Run times</h2>",
        _kv_table({k: f"{float(v):.2f} s" for k, v in timings_s.items()}, ("part", "time")),
        "</section>",
        "</body></html>",
        "",
    ]
    path = out_dir / filename
    fd, tmp = tempfile.mkstemp(prefix=f".{filename}.", suffix=".tmp", dir=out_dir)
    try:
        with os.fdopen(fd, "w", encoding="utf-8") as f:
            f.write("\n".join(parts))
        os.chmod(tmp, 0o644)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


# ---------------------------------------------------------------------------------------------- browser check
@dataclass(frozen=True)
class PageCheck:
    """Result of :func:`check_page`.

    Parameters
    ----------
    ok : bool
        The self-check ran, every image loaded, no console error and (if asked) a screenshot was written.
    images_ok, images_total : int
        Images decoded with a non-zero width, and all ``<img>`` on the page.
    console_errors : tuple of str
        ``console.error`` calls (``"console.error: …"``), uncaught exceptions (``"Uncaught …"``) and failed
        non-image resources, plus one line when the self-check did not run or no screenshot was written.
    screenshot : Path or None
        The screenshot (PNG), when one was asked for and written.
    browser : str
        The browser's ``--version``, e.g. ``"Chromium 156.0.8078.79 built on Debian GNU/Linux 12 (bookworm)"``.
    """

    ok: bool
    images_ok: int
    images_total: int
    console_errors: tuple[str, ...]
    screenshot: Path | None
    browser: str


def find_chromium() -> str | None:
    """Path of a Chromium-family browser, or None.

    ``$LANDSCAPE_CHROMIUM`` (a path or a command name), when set, is the only candidate; otherwise the first of
    ``chromium``, ``chromium-browser``, ``google-chrome``, ``chrome`` on ``$PATH``.

    Returns
    -------
    path : str or None
        Executable to run.
    """
    env = os.environ.get("LANDSCAPE_CHROMIUM")
    if env:
        if Path(env).is_file() and os.access(env, os.X_OK):
            return env
        return shutil.which(env)
    for name in CHROMIUM_NAMES:
        found = shutil.which(name)
        if found:
            return found
    return None


def _run_chromium(exe: str, args: Sequence[str], timeout_s: float) -> subprocess.CompletedProcess:
    """Run the browser with a fresh profile in its own process group; kill the group on timeout."""
    with tempfile.TemporaryDirectory(prefix="landscape-chromium-", ignore_cleanup_errors=True) as profile:
        cmd = [exe, *CHROMIUM_FLAGS, f"--user-data-dir={profile}", *args]
        proc = subprocess.Popen(
            cmd,
            stdin=subprocess.DEVNULL,
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
            errors="replace",
            start_new_session=True,
        )
        try:
            out, err = proc.communicate(timeout=timeout_s)
        except subprocess.TimeoutExpired:
            _kill_group(proc)
            raise RuntimeError(
                f"{Path(exe).name} did not finish within {timeout_s:g} s "
                f"({' '.join(a for a in args if not a.startswith('--'))})"
            ) from None
        _kill_group(proc)  # helpers the browser left behind in its group
        return subprocess.CompletedProcess(cmd, proc.returncode, out, err)


_VERSIONS: dict[str, str] = {}


def _browser_version(exe: str, timeout_s: float) -> str:
    """``exe --version`` (run once per executable)."""
    if exe not in _VERSIONS:
        _VERSIONS[exe] = _run_chromium(exe, ["--version"], timeout_s).stdout.strip() or Path(exe).name
    return _VERSIONS[exe]


def _kill_group(proc: subprocess.Popen) -> None:
    try:
        os.killpg(proc.pid, signal.SIGKILL)
    except (ProcessLookupError, PermissionError):
        pass
    try:
        proc.communicate(timeout=5)
    except (subprocess.TimeoutExpired, ValueError):
        pass


class _BodyAttrs(HTMLParser):
    """The attributes of the first ``<body>`` start tag (values unescaped)."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.attrs: dict[str, str] | None = None

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        if tag == "body" and self.attrs is None:
            self.attrs = {k: v or "" for k, v in attrs}


def _body_attrs(dom: str) -> dict[str, str]:
    parser = _BodyAttrs()
    parser.feed(dom)
    parser.close()
    return parser.attrs or {}


# [pid:tid:MMDD/HHMMSS.us:INFO:CONSOLE:5] "msg", source: url (5)   (older builds: INFO:CONSOLE(5)] ...)
_CONSOLE_LINE = re.compile(
    r':(?P<level>[A-Z]+|VERBOSE\d*):CONSOLE(?::\d+|\(\d+\))?\] "(?P<msg>.*)", '
    r"source: (?P<src>.*?)(?: \((?P<line>\d+)\))?$"
)


def _console_errors_from_log(stderr: str) -> list[tuple[str, str]]:
    """(message, location) of the console errors in the browser's log; other lines (dbus, gpu, …) are noise.

    Chromium logs every console message of a page as INFO, so only uncaught exceptions can be recognised here
    (their message starts with ``Uncaught``), besides lines an older or other build logs as ERROR.
    """
    found = []
    for line in stderr.splitlines():
        m = _CONSOLE_LINE.search(line)
        if m and (m["msg"].startswith("Uncaught") or m["level"] in ("ERROR", "FATAL")):
            where = m["src"] + (f":{m['line']}" if m["line"] else "")
            found.append((m["msg"], where))
    return found


def _merge_errors(in_page: Sequence[str], logged: Sequence[tuple[str, str]]) -> list[str]:
    """In-page records first, then logged errors whose message the page did not record already."""
    errors = list(in_page)
    seen = {re.sub(r" \([^()]*:\d+\)$", "", e) for e in errors}
    for msg, where in logged:
        if msg not in seen:
            seen.add(msg)
            errors.append(f"{msg} ({where})" if where else msg)
    return errors


def check_page(html: Path, *, screenshot: Path | None = None, timeout_s: float = 60.0) -> PageCheck:
    """Open an HTML page in headless Chromium: images loaded, console errors, optional screenshot.

    The page must carry :data:`SELF_CHECK_JS` (pages from :func:`write_report` do). One browser run dumps the
    DOM after the ``load`` event and ``VIRTUAL_TIME_BUDGET_MS`` of virtual time; a second one, when
    ``screenshot`` is given, writes a 1280 x 2000 px PNG. Each run has a fresh profile, removed afterwards.

    Parameters
    ----------
    html : Path
        The page, opened as a ``file://`` URL.
    screenshot : Path or None
        Where to write the screenshot (PNG, overwritten).
    timeout_s : float
        Limit for each browser run, s (> 0).

    Returns
    -------
    check : PageCheck
        ``ok`` is True when the self-check ran, every image loaded, no console error was seen and the
        screenshot (if asked for) is a non-empty PNG.

    Raises
    ------
    RuntimeError
        If no browser is found (see :func:`find_chromium`) or a run does not finish within ``timeout_s``.
    FileNotFoundError
        If ``html`` does not exist.
    ValueError
        If ``timeout_s`` <= 0.

    Examples
    --------
    >>> check_page(Path("report/index.html"), screenshot=Path("report/screenshot.png"))  # doctest: +SKIP
    PageCheck(ok=True, images_ok=5, images_total=5, console_errors=(), screenshot=..., browser='Chromium 156...')
    """
    if not timeout_s > 0:
        raise ValueError(f"timeout_s must be > 0 s; got {timeout_s!r}")
    page = Path(html).resolve()
    if not page.is_file():
        raise FileNotFoundError(f"no HTML page at '{page}'; write it first (write_report)")
    exe = find_chromium()
    if exe is None:
        raise RuntimeError(CHROMIUM_NOT_FOUND)
    url = page.as_uri()
    browser = _browser_version(exe, timeout_s)

    res = _run_chromium(
        exe,
        [
            "--enable-logging=stderr",
            "--v=0",
            f"--virtual-time-budget={VIRTUAL_TIME_BUDGET_MS}",
            "--dump-dom",
            url,
        ],
        timeout_s,
    )
    attrs = _body_attrs(res.stdout)
    done = attrs.get("data-selfcheck") == "done"
    m = re.fullmatch(r"(\d+)/(\d+)", attrs.get("data-images-ok", ""))
    images_ok, images_total = (int(m[1]), int(m[2])) if m else (0, 0)
    try:
        in_page = [str(e) for e in json.loads(attrs.get("data-console-errors") or "[]")]
    except json.JSONDecodeError:
        in_page = [f"unreadable data-console-errors: {attrs['data-console-errors'][:200]}"]
    errors = _merge_errors(in_page, _console_errors_from_log(res.stderr))
    if not done:
        errors.append(
            f"the page's self-check did not run ({Path(exe).name} exit status {res.returncode}; "
            "does the page carry SELF_CHECK_JS?)"
        )

    shot = None
    if screenshot is not None:
        target = Path(screenshot).resolve()
        target.parent.mkdir(parents=True, exist_ok=True)
        target.unlink(missing_ok=True)
        w_px, h_px = SCREENSHOT_SIZE_PX
        _run_chromium(
            exe,
            [
                f"--screenshot={target}",
                f"--window-size={w_px},{h_px}",
                "--hide-scrollbars",
                f"--virtual-time-budget={VIRTUAL_TIME_BUDGET_MS}",
                url,
            ],
            timeout_s,
        )
        try:
            if target.stat().st_size > 0:
                png_size(target)
                shot = target
        except (OSError, ValueError):
            pass
        if shot is None:
            errors.append(f"{Path(exe).name} wrote no PNG screenshot to '{target}'")
    ok = done and images_ok == images_total and not errors
    return PageCheck(ok, images_ok, images_total, tuple(errors), shot, browser)


__all__ = [
    "Figure",
    "Table",
    "Section",
    "PageCheck",
    "SELF_CHECK_JS",
    "png_size",
    "write_report",
    "find_chromium",
    "check_page",
]
