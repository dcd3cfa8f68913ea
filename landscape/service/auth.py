"""Who may call a service started with a token.

Every ``/api`` request sends ``Authorization: Bearer TOKEN``. A page cannot put that header on a link it opens in
a new tab (a sweep's report and the tables the report links to), so a caller holding the token may ask for a
*link cookie*: ``POST /api/link-access`` answers ``Set-Cookie: landscape_link=EXPIRY.SIGNATURE`` (HMAC-SHA256 of
the expiry under the token; HttpOnly, SameSite=Strict, Path=/api/sweeps/, one hour). The cookie opens nothing but
``GET`` (and ``HEAD``) of ``/api/sweeps/{id}/report`` and ``/api/sweeps/{id}/report/{file}``: every other request,
and every request whatsoever without the cookie, still needs the bearer token.
"""

from __future__ import annotations

import hashlib
import hmac
import re
import time

LINK_COOKIE = "landscape_link"
LINK_COOKIE_PATH = "/api/sweeps/"
LINK_TTL_S = 3600
"""Lifetime of a link cookie, s; the page renews it while it is open."""
_LINK_PATHS = re.compile(r"/api/sweeps/[^/]+/report(?:/[^/]+)?")
_PURPOSE = b"landscape-link-cookie\0"


def bearer_ok(authorization: str, token: bytes) -> bool:
    """Whether an ``Authorization`` header carries the token as a bearer credential."""
    scheme, _, value = authorization.partition(" ")
    return scheme.lower() == "bearer" and hmac.compare_digest(value.strip().encode(), token)


def _signature(token: bytes, expires_s: int) -> str:
    return hmac.new(token, _PURPOSE + str(expires_s).encode(), hashlib.sha256).hexdigest()


def link_cookie(token: bytes, *, now_s: float | None = None, ttl_s: int = LINK_TTL_S) -> str:
    """A link cookie value ``EXPIRY.SIGNATURE`` valid for ``ttl_s`` seconds from ``now_s`` (default: now).

    Examples
    --------
    >>> v = link_cookie(b"T", now_s=1000.0, ttl_s=60)
    >>> v.split(".")[0], link_cookie_ok(v, b"T", now_s=1059.0), link_cookie_ok(v, b"T", now_s=1061.0)
    ('1060', True, False)
    >>> link_cookie_ok(v, b"other token", now_s=1000.0)
    False
    """
    expires_s = int((time.time() if now_s is None else now_s) + ttl_s)
    return f"{expires_s}.{_signature(token, expires_s)}"


def link_cookie_ok(value: str, token: bytes, *, now_s: float | None = None) -> bool:
    """Whether a link cookie value was signed with ``token`` and has not expired."""
    expiry, _, sig = (value or "").partition(".")
    if not expiry.isdigit() or len(expiry) > 12:
        return False
    if not hmac.compare_digest(sig.encode(), _signature(token, int(expiry)).encode()):
        return False
    return (time.time() if now_s is None else now_s) < int(expiry)


def opened_by_link(method: str, path: str) -> bool:
    """Whether a request is one a link cookie may open: GET or HEAD of a sweep report or a file it links."""
    return method in ("GET", "HEAD") and _LINK_PATHS.fullmatch(path) is not None
