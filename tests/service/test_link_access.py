"""With a token, links the page opens in a new tab (a sweep's report) cannot send the Authorization header: the
page gets a link cookie from POST /api/link-access. The cookie opens report pages and nothing else; it cannot be
forged, outlives no hour, and is minted only for a caller holding the token."""

from __future__ import annotations

import time

import pytest

TOKEN = "s3cret"
AUTH = {"Authorization": f"Bearer {TOKEN}"}


@pytest.fixture
def tclient(make_app):
    from fastapi.testclient import TestClient

    with TestClient(make_app(token=TOKEN), raise_server_exceptions=False) as c:
        yield c


def _cookie(tclient) -> str:
    r = tclient.post("/api/link-access", headers=AUTH)
    assert r.status_code == 200, r.text
    tclient.cookies.clear()  # each request below says which cookie it sends
    return r.cookies["landscape_link"]


def test_link_cookie_is_minted_only_with_the_token(tclient):
    assert tclient.post("/api/link-access").status_code == 401
    assert tclient.post("/api/link-access", headers={"Authorization": "Bearer wrong"}).status_code == 401
    r = tclient.post("/api/link-access", headers=AUTH)
    assert r.status_code == 200 and r.json()["expires_s"] == 3600
    header = r.headers["set-cookie"].lower()
    for attribute in ("httponly", "samesite=strict", "path=/api/sweeps/", "max-age=3600"):
        assert attribute in header, header
    # the cookie does not mint a new one (nor does anything but the bearer token)
    cookie = r.cookies["landscape_link"]
    tclient.cookies.clear()
    assert tclient.post("/api/link-access", headers={"Cookie": f"landscape_link={cookie}"}).status_code == 401


def test_link_cookie_opens_report_pages(tclient):
    """Past the token check: the report's own answer (404 for an unknown job), not 401."""
    c = {"Cookie": f"landscape_link={_cookie(tclient)}"}
    assert tclient.get("/api/sweeps/abc123/report").status_code == 401  # no cookie, no header
    for url in ("/api/sweeps/abc123/report", "/api/sweeps/abc123/report/trials.csv"):
        r = tclient.get(url, headers=c)
        assert r.status_code == 404 and "unknown sweep job" in r.json()["detail"], (url, r.text)


@pytest.mark.parametrize(
    "method, url",
    [
        ("GET", "/api/robots"),
        ("GET", "/api/robots/builtin"),
        ("GET", "/api/landscape?theta_w=74"),
        ("GET", "/api/robot-pose"),
        ("GET", "/api/barrier-map"),
        ("GET", "/api/sweeps"),
        ("GET", "/api/sweeps/abc123"),
        ("GET", "/api/health"),
        ("POST", "/api/sweeps"),
        ("POST", "/api/robots"),
        ("DELETE", "/api/sweeps/abc123"),
        ("DELETE", "/api/sweeps/abc123/report"),
        ("POST", "/api/sweeps/abc123/report"),
        ("GET", "/api/sweeps/abc123/report/a/b"),
        ("GET", "/api/sweeps/abc123/reportx"),
    ],
)
def test_link_cookie_opens_nothing_else(tclient, method, url):
    c = {"Cookie": f"landscape_link={_cookie(tclient)}"}
    r = tclient.request(method, url, headers=c)
    assert r.status_code == 401 and "missing or wrong token" in r.json()["detail"]


def test_forged_expired_or_foreign_cookies_are_refused(tclient, make_app, tmp_path):
    from landscape.service.auth import link_cookie

    good = _cookie(tclient)
    expiry, sig = good.split(".")
    later = str(int(expiry) + 86_400)
    bad = [
        f"{later}.{sig}",  # a longer life under the old signature
        f"{expiry}.{sig[:-1]}{'0' if sig[-1] != '0' else '1'}",  # one hex digit changed
        link_cookie(b"another token"),  # signed by another server's token
        link_cookie(TOKEN.encode(), now_s=time.time() - 7200),  # expired an hour ago
        f"{expiry}",
        "",
        "garbage",
        f"-{expiry}.{sig}",
    ]
    url = "/api/sweeps/abc123/report"
    assert tclient.get(url, headers={"Cookie": f"landscape_link={good}"}).status_code == 404
    for value in bad:
        r = tclient.get(url, headers={"Cookie": f"landscape_link={value}"})
        assert r.status_code == 401, value


def test_without_a_token_there_is_no_cookie(client):
    r = client.post("/api/link-access")
    assert r.status_code == 200 and r.json()["cookie"] is None and "set-cookie" not in r.headers
