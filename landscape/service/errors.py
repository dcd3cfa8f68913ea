"""The service's bad-input errors: each is a :class:`geometry.errors.UsageError` (so a ``ValueError``) that the
app turns into an HTTP status with the message as ``{"detail": ...}``."""

from __future__ import annotations

from geometry.errors import UsageError


class NotFoundError(UsageError):
    """An unknown robot, job or file (HTTP 404)."""


class TooLargeError(UsageError):
    """An upload over the size limit (HTTP 413)."""


class TooCostlyError(UsageError):
    """A request whose estimated run time or size is over the service's limits (HTTP 422)."""


class ConflictError(UsageError):
    """A request that contradicts what is stored (HTTP 409)."""


class UploadError(UsageError):
    """An uploaded file that is not a usable robot description (HTTP 422)."""


class TimeLimitError(RuntimeError):
    """A computation still running at the request's time limit (HTTP 503); it finishes into the cache."""


STATUS = {NotFoundError: 404, TooLargeError: 413, ConflictError: 409}


def status_of(exc: UsageError) -> int:
    """HTTP status of a bad-input error: 404, 409, 413 for the classes above, 422 for any other."""
    for cls, code in STATUS.items():
        if isinstance(exc, cls):
            return code
    return 422
