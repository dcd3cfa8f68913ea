"""The self-contained HTML report and its headless-browser check (landscape/report.py)."""

import csv
import re

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import pytest  # noqa: E402

from landscape.report import Figure, Section, Table, check_page, find_chromium, png_size, write_report  # noqa: E402


def _png(path, w_in, h_in):
    fig, ax = plt.subplots(figsize=(w_in, h_in))
    ax.plot([0, 1], [0, 1])
    fig.savefig(path, dpi=50)
    fig.savefig(path.with_suffix(".svg"))
    plt.close(fig)
    return path


@pytest.fixture()
def page(tmp_path):
    a, b = _png(tmp_path / "a.png", 4, 3), _png(tmp_path / "b.png", 2, 2)
    small = tmp_path / "small.csv"
    with open(small, "w", newline="") as f:
        csv.writer(f).writerows([["name", "value"], ["<b>bold</b>", "1"], ["x", "2"]])
    big = tmp_path / "big.csv"
    with open(big, "w", newline="") as f:
        csv.writer(f).writerows([["i"]] + [[str(i)] for i in range(100)])
    sections = [Section("one", "First", ("Some `code` here.",), (Figure(a, "fig A", a.with_suffix(".svg")),),
                        (Table("Small", small), Table("Big", big))),
                Section("two", "Second", figures=(Figure(b, "fig B"),)),
                Section("three", "Third", missing="run `landscape sweep --db x.sqlite`")]
    return write_report(sections, tmp_path / "out", title="Test report", inputs={"db": "x.sqlite"},
                        versions={"python": "3"}, timings_s={"all": 1.234})


def test_report_is_self_contained_and_escaped(page):
    text = page.read_text()
    assert not re.search(r"(src|href)=['\"]https?://", text)
    imgs = re.findall(r"<img src='data:image/png;base64,[^']+' width='(\d+)' height='(\d+)'", text)
    assert [tuple(map(int, x)) for x in imgs] == [png_size(page.parent.parent / "a.png"),
                                                  png_size(page.parent.parent / "b.png")]
    assert "&lt;b&gt;bold&lt;/b&gt;" in text and "<b>bold</b>" not in text
    assert "<code>code</code>" in text
    assert "… 40 more rows in" in text and "../big.csv" in text
    assert "Not enough data: run <code>landscape sweep --db x.sqlite</code>" in text
    assert "1.23 s" in text and "../a.svg" in text


def test_png_size_refuses_other_files(tmp_path):
    f = tmp_path / "x.png"
    f.write_bytes(b"not a png at all, really not")
    with pytest.raises(ValueError, match="not a PNG"):
        png_size(f)


needs_chromium = pytest.mark.skipif(find_chromium() is None, reason="chromium is not installed")


@needs_chromium
def test_report_loads_in_headless_chromium(page, tmp_path):
    res = check_page(page, screenshot=tmp_path / "shot.png")
    assert res.ok, res
    assert (res.images_ok, res.images_total) == (2, 2) and res.console_errors == ()
    assert res.screenshot.stat().st_size > 0 and png_size(res.screenshot) == (1280, 2000)
    assert "Chromium" in res.browser or "Chrome" in res.browser


@needs_chromium
def test_browser_check_catches_broken_images_and_console_errors(tmp_path):
    from landscape.report import SELF_CHECK_JS

    bad = tmp_path / "bad.html"
    bad.write_text(f"<html><head><script>{SELF_CHECK_JS}</script></head><body>"
                   "<img src='data:image/png;base64,AAAA'><script>console.log('just-a-log'); console.error('boom');"
                   "undefinedFunction();</script></body></html>")
    res = check_page(bad)
    assert not res.ok and (res.images_ok, res.images_total) == (0, 1)
    assert any("boom" in e for e in res.console_errors)
    assert any("undefinedFunction" in e for e in res.console_errors)
    assert not any("just-a-log" in e for e in res.console_errors)
