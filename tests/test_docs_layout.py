"""The built documentation in a real browser, 1400 px wide: the header (the brand, every top-level page, the search
and the colour switch) fits in one row, every code block fits the content's width (a long command wraps instead of
hiding behind a scrollbar), neither the page nor a sidebar scrolls sideways, and the left sidebar is not empty.

Needs the built site: the README's ``sphinx-build ... docs docs/_build/html``, which ``.ci/run`` runs before
``pytest -m docs_layout``. Skips without the site or without Chromium. A screenshot of each page is kept in
``docs/_build/layout/`` for a person to look at.
"""

from __future__ import annotations

import base64
import time
from pathlib import Path

import pytest

from tests.browser import devtools_chromium, page

ROOT = Path(__file__).resolve().parents[1]
HTML = ROOT / "docs" / "_build" / "html"
SHOTS = ROOT / "docs" / "_build" / "layout"
WIDTH_PX, HEIGHT_PX = 1400, 1000
PAGES = ("index.html", "getting_started.html", "api/index.html")
"""The front page, the page a newcomer opens first (two long set-up commands) and the API reference's index (long
tables of long names)."""

pytestmark = pytest.mark.docs_layout

LAYOUT = """(() => {
  const box = (el) => el.getBoundingClientRect();
  const nav = document.querySelector('.bd-header .navbar-nav');
  const items = [...nav.querySelectorAll(':scope > li')];
  const header = ['.navbar-header-items__start', '.navbar-nav', '.navbar-header-items__end .search-button',
                  '.theme-switch-button'].map((s) => document.querySelector('.bd-header ' + s));
  const sidebar = document.querySelector('.bd-sidebar-primary');
  return {
    nav_height: box(nav).height,
    item_heights: items.map((li) => box(li).height),
    item_tops: items.map((li) => box(li).top),
    header_middles: header.map((el) => (el ? (box(el).top + box(el).bottom) / 2 : null)),
    nav_top: box(nav).top,
    nav_bottom: box(nav).bottom,
    wide_blocks: [...document.querySelectorAll('.bd-article pre')]
      .filter((pre) => pre.scrollWidth > pre.clientWidth)
      .map((pre) => [pre.scrollWidth, pre.clientWidth, pre.textContent.slice(0, 60)]),
    wide_sidebars: [...document.querySelectorAll('.bd-sidebar-primary, .bd-sidebar-secondary')]
      .filter((el) => el.scrollWidth > el.clientWidth)
      .map((el) => [el.scrollWidth, el.clientWidth, el.className]),
    page_width: document.documentElement.scrollWidth,
    view_width: document.documentElement.clientWidth,
    sidebar_links: sidebar  // the links a reader sees there (it also holds the header's, for narrow screens)
      ? [...sidebar.querySelectorAll('a[href]')].filter((a) => box(a).width > 0 && box(a).height > 0).length
      : 0,
  };
})()"""
"""What the test measures on a page, in CSS pixels."""


@pytest.fixture(scope="module")
def chromium(tmp_path_factory):
    if not (HTML / "index.html").is_file():
        pytest.skip(
            f"the documentation is not built ({HTML}); build it with the README's sphinx-build command"
        )
    with devtools_chromium(tmp_path_factory.mktemp("chromium") / "profile") as port:
        yield port


@pytest.fixture(scope="module")
def layouts(chromium) -> dict[str, dict]:
    """Each page of :data:`PAGES` opened at 1400 x 1000 px: its :data:`LAYOUT` measures (and a screenshot)."""
    SHOTS.mkdir(parents=True, exist_ok=True)
    out = {}
    with page(chromium) as cdp:
        cdp.send("Emulation.setDeviceMetricsOverride", width=WIDTH_PX, height=HEIGHT_PX, deviceScaleFactor=1,
                 mobile=False)  # fmt: skip
        for name in PAGES:
            cdp.send("Page.navigate", url=(HTML / name).as_uri())
            cdp.wait_for(f"document.readyState === 'complete' && location.href.endsWith('{name}')")
            cdp.wait_for("document.fonts.status === 'loaded'")
            time.sleep(0.3)  # the theme's scripts place the header's buttons after the load event
            out[name] = cdp.eval(LAYOUT)
            png = base64.b64decode(cdp.send("Page.captureScreenshot", format="png")["data"])
            (SHOTS / name.replace("/", "_").replace(".html", ".png")).write_bytes(png)
    return out


@pytest.mark.parametrize("name", PAGES)
def test_the_header_is_one_row(layouts, name):
    m = layouts[name]
    assert len(m["item_tops"]) == 8 and len(set(m["item_tops"])) == 1, f"{name}: the navigation wraps"
    assert m["nav_height"] == pytest.approx(max(m["item_heights"]), abs=1.0), f"{name}: the navigation wraps"
    # the brand, the navigation, the search button and the colour switch share the navigation's row
    assert all(m["nav_top"] <= y <= m["nav_bottom"] for y in m["header_middles"]), (name, m)


@pytest.mark.parametrize("name", PAGES)
def test_code_blocks_fit_the_content_width(layouts, name):
    m = layouts[name]
    assert m["wide_blocks"] == [], f"{name}: code blocks wider than the content (scroll, client, text)"
    assert m["wide_sidebars"] == [], f"{name}: a sidebar scrolls sideways (scroll, client, class)"
    assert m["page_width"] <= m["view_width"], f"{name}: the page scrolls sideways"


def test_getting_started_has_a_left_sidebar(layouts):
    assert layouts["getting_started.html"]["sidebar_links"] >= 3
