"""The self-contained HTML report and its headless-Chromium check (landscape/report.py)."""

import base64
import csv
import re
import stat

import pytest
from matplotlib.figure import Figure as MplFigure

from landscape.viz.report import (
    SELF_CHECK_JS,
    Figure,
    Section,
    Table,
    _console_errors_from_log,
    check_page,
    find_chromium,
    png_size,
    write_report,
)

# Each browser run here takes about 1 s; the limit keeps a hung browser from stalling the suite.
CHROMIUM_TIMEOUT_S = 15.0


def _png(path, w_in, h_in, dpi):
    """A matplotlib figure saved as PNG (w_in*dpi x h_in*dpi px) and SVG beside it."""
    fig = MplFigure(figsize=(w_in, h_in))
    fig.add_subplot().plot([0, 1], [0, 1])
    fig.savefig(path, dpi=dpi)
    fig.savefig(path.with_suffix(".svg"))
    return path


def _csv(path, rows):
    with open(path, "w", newline="", encoding="utf-8") as f:
        csv.writer(f).writerows(rows)
    return path


@pytest.fixture()
def page(tmp_path):
    a, b = _png(tmp_path / "a.png", 4, 3, 50), _png(tmp_path / "b.png", 2, 2, 50)
    small = _csv(tmp_path / "small.csv", [["name", "value"], ["<b>bold</b>", "1"], ["x & y", "2.5"]])
    big = _csv(tmp_path / "big.csv", [["i", "i2"]] + [[str(i), str(i * i)] for i in range(100)])
    sections = [
        Section(
            "one",
            "First",
            ("Some `code` here & <there>.",),
            (Figure(a, "fig A <4x3>", a.with_suffix(".svg")),),
            (Table("Small", small), Table("Big", big)),
        ),
        Section("two", "Second", figures=(Figure(b, "fig B"),)),
        Section(
            "three",
            "Third",
            figures=(Figure(b, "never shown"),),
            missing="run `landscape sweep --db x.sqlite` first",
        ),
    ]
    return write_report(
        sections,
        tmp_path / "out",
        title="Test <report>",
        inputs={"db": "x.sqlite"},
        versions={"python": "3.11", "numpy": "2.0"},
        timings_s={"all": 1.234, "plots": 0.006},
    )


def test_report_is_self_contained(page, tmp_path):
    text = page.read_text(encoding="utf-8")
    assert page == tmp_path / "out" / "index.html"
    assert [p.name for p in page.parent.iterdir()] == ["index.html"]  # no temporary file left behind
    assert not re.search(r"(src|href)\s*=\s*['\"]?\s*(https?:)?//", text, flags=re.IGNORECASE)
    assert "http://" not in text and "https://" not in text and "<link" not in text
    assert re.findall(r"\ssrc=['\"]([^'\"]{0,22})", text) == ["data:image/png;base64,"] * 2
    assert text.count("<script>") == 1 and "dataset.selfcheck" in text


def test_images_are_data_uris_with_their_pixel_size(page, tmp_path):
    text = page.read_text(encoding="utf-8")
    imgs = re.findall(
        r"<img src='data:image/png;base64,([^']+)' width='(\d+)' height='(\d+)' alt='([^']*)'>", text
    )
    # 4 x 3 in and 2 x 2 in at 50 dpi
    assert [(int(w), int(h)) for _, w, h, _ in imgs] == [(200, 150), (100, 100)]
    assert [png_size(tmp_path / n) for n in ("a.png", "b.png")] == [(200, 150), (100, 100)]
    assert [base64.b64decode(d) for d, *_ in imgs] == [
        (tmp_path / n).read_bytes() for n in ("a.png", "b.png")
    ]
    assert [alt for *_, alt in imgs] == ["fig A &lt;4x3&gt;", "fig B"]
    assert "href='../a.svg'>SVG</a>" in text and "never shown" not in text


def test_text_is_escaped_and_tables_truncated(page):
    text = page.read_text(encoding="utf-8")
    assert "&lt;b&gt;bold&lt;/b&gt;" in text and "<b>bold</b>" not in text
    assert "x &amp; y" in text and "<title>Test &lt;report&gt;</title>" in text
    assert "<p>Some <code>code</code> here &amp; &lt;there&gt;.</p>" in text
    assert "… 40 more rows in <a href='../big.csv'>big.csv</a>" in text
    assert ">59</td><td>3481</td>" in text and ">60</td>" not in text  # rows 0..59 shown
    assert (
        "<div class='missing'>Not enough data: run <code>landscape sweep --db x.sqlite</code> first" in text
    )


def test_contents_inputs_versions_and_timings(page):
    text = page.read_text(encoding="utf-8")
    for key in ("one", "two", "three", "inputs", "versions", "timings"):
        assert f"<a href='#{key}'>" in text and f"id='{key}'" in text
    assert "Third</a> <span class='small'>(not enough data)" in text
    assert "<th class='l'>db</th><td class='l'>x.sqlite</td>" in text
    assert "<th class='l'>numpy</th><td class='l'>2.0</td>" in text
    assert "<td class='l'>1.23 s</td>" in text and "<td class='l'>0.01 s</td>" in text
    assert re.search(r"<time datetime='\d{4}-\d\d-\d\dT\d\d:\d\d:\d\d\+00:00'>", text)


def test_write_report_refuses_bad_input(tmp_path):
    with pytest.raises(ValueError, match="used twice or reserved"):
        write_report(
            [Section("a", "A"), Section("a", "B")], tmp_path, title="t", inputs={}, versions={}, timings_s={}
        )
    with pytest.raises(ValueError, match="without whitespace"):
        write_report([Section("a b", "A")], tmp_path, title="t", inputs={}, versions={}, timings_s={})
    fake = tmp_path / "fake.png"
    fake.write_bytes(b"not a png at all, really not")
    with pytest.raises(ValueError, match="not a PNG"):
        write_report(
            [Section("a", "A", figures=(Figure(fake, "x"),))],
            tmp_path,
            title="t",
            inputs={},
            versions={},
            timings_s={},
        )
    assert not list(tmp_path.glob("*.html")) and not list(tmp_path.glob(".*"))


def test_console_errors_are_read_from_chromium_log():
    # Lines as Chromium 156 writes them with --enable-logging=stderr: every console level is INFO.
    log = "\n".join(
        [
            "/usr/bin/chromium: 9: [: 25275772928: unexpected operator",
            "[27702:27732:1122/131311.733550:ERROR:dbus/bus.cc:405] Failed to connect to the bus: No such file",
            '[27702:27702:1122/131312.277960:INFO:CONSOLE:2] "just-a-log", source: file:///tmp/p.html (2)',
            '[27702:27702:1122/131312.278420:INFO:CONSOLE:2] "boom 42", source: file:///tmp/p.html (2)',
            '[27702:27702:1122/131312.279972:INFO:CONSOLE:5] "Uncaught ReferenceError: f is not defined", '
            "source: file:///tmp/p.html (5)",
            '[27702:27702:1122/131312.290847:INFO:CONSOLE:4] "Uncaught (in promise) Error: no", '
            "source: file:///tmp/p.html (4)",
            '[1:1:0101/000000.1:INFO:CONSOLE(7)] "Uncaught Error: old format", source: file:///tmp/p.html (7)',
        ]
    )
    assert _console_errors_from_log(log) == [
        ("Uncaught ReferenceError: f is not defined", "file:///tmp/p.html:5"),
        ("Uncaught (in promise) Error: no", "file:///tmp/p.html:4"),
        ("Uncaught Error: old format", "file:///tmp/p.html:7"),
    ]


def test_missing_browser_and_timeout_are_clear_errors(tmp_path, monkeypatch):
    html = tmp_path / "p.html"
    html.write_text("<html><body></body></html>")
    monkeypatch.setenv("LANDSCAPE_CHROMIUM", str(tmp_path / "no-such-browser"))
    assert find_chromium() is None
    with pytest.raises(RuntimeError, match=r"chromium not found; install Debian's chromium package"):
        check_page(html)
    slow = tmp_path / "slow-browser"
    slow.write_text("#!/bin/sh\nexec sleep 30\n")
    slow.chmod(slow.stat().st_mode | stat.S_IXUSR)
    monkeypatch.setenv("LANDSCAPE_CHROMIUM", str(slow))
    assert find_chromium() == str(slow)
    with pytest.raises(RuntimeError, match=r"^slow-browser did not finish within 0.5 s"):
        check_page(html, timeout_s=0.5)
    with pytest.raises(FileNotFoundError, match="no HTML page"):
        check_page(tmp_path / "absent.html")


@pytest.fixture()
def chromium():
    exe = find_chromium()
    if exe is None:
        pytest.skip("chromium is not installed (apt-get install chromium)")
    return exe


def test_report_loads_in_headless_chromium(chromium, page, tmp_path):
    res = check_page(page, screenshot=tmp_path / "shot" / "page.png", timeout_s=CHROMIUM_TIMEOUT_S)
    assert res.console_errors == () and (res.images_ok, res.images_total) == (2, 2)
    assert res.ok
    assert res.screenshot == tmp_path / "shot" / "page.png" and res.screenshot.stat().st_size > 0
    assert png_size(res.screenshot) == (1280, 2000)
    assert "Chromium" in res.browser or "Chrome" in res.browser


def test_browser_check_catches_broken_images_and_console_errors(chromium, tmp_path):
    bad = tmp_path / "bad.html"
    bad.write_text(
        f"<html><head><script>{SELF_CHECK_JS}</script></head><body>"
        "<img src='data:image/png;base64,AAAA'><script>console.log('just-a-log'); "
        "console.error('boom'); undefinedFunction();</script></body></html>"
    )
    res = check_page(bad, timeout_s=CHROMIUM_TIMEOUT_S)
    assert not res.ok and (res.images_ok, res.images_total) == (0, 1) and res.screenshot is None
    assert any("boom" in e for e in res.console_errors)
    assert any(e.startswith("Uncaught ReferenceError: undefinedFunction") for e in res.console_errors)
    assert len(res.console_errors) == 2 and not any("just-a-log" in e for e in res.console_errors)


def test_browser_check_fails_a_page_without_the_self_check(chromium, tmp_path):
    plain = tmp_path / "plain.html"
    plain.write_text("<html><body><p>no self-check here</p></body></html>")
    res = check_page(plain, timeout_s=CHROMIUM_TIMEOUT_S)
    assert not res.ok and (res.images_ok, res.images_total) == (0, 0)
    assert (
        res.console_errors == (res.console_errors[0],) and "self-check did not run" in res.console_errors[0]
    )
