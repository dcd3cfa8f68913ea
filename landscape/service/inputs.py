"""The service's numbers: every query parameter, form field and request field that holds a number is read through
its stated range (:class:`geometry.bounds.Bounds`), as the command line's options are.

:func:`ranged` makes the annotated type of a query parameter or form field: its OpenAPI description states the
range in the command line's words, its schema carries it (``minimum``, ``exclusiveMaximum``, ``x-unit``...), and a
value outside it answers 422 with the command line's message, the value named as the parameter (``cv 10 is
outside [0, 1]: ...`` where the command line says ``--cv 10 is outside [0, 1]: ...``). :func:`request_numbers`
does the same for a JSON body's fields (a sweep's options). Values that look like a slip of units are answered
in a ``warnings`` list (:func:`angle_warnings`).
"""

from __future__ import annotations

from typing import Annotated

from fastapi import Query
from pydantic import AfterValidator, BeforeValidator
from pydantic_core import PydanticCustomError

from geometry.bounds import Bounds, joint_angle_slips
from geometry.errors import UsageError
from landscape.params import parse_bounded

OUT_OF_RANGE = "out_of_range"
"""The pydantic error type of a value outside its range: the app answers its message as the 422's detail."""


def read_number(value, bounds: Bounds, name: str, *, many: bool = False):
    """A request's value (a string as typed, or a JSON number; with ``many`` a list '70,72' or range '70:76:2')
    inside ``bounds``, else :class:`UsageError` in the command line's words, naming ``name``."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str, list)):
        kind = "numbers" if many else ("a whole number" if bounds.integer else "a number")
        raise UsageError(f"{name} must be {kind}; got {value!r}")
    if many:
        return parse_bounded(value, bounds, name)
    return bounds.parse(value, name)


def _validator(bounds: Bounds, name: str, many: bool):
    def check(value):
        if value is None:
            return None
        try:
            return read_number(value, bounds, name, many=many)
        except UsageError as exc:
            raise PydanticCustomError(OUT_OF_RANGE, "{message}", {"message": str(exc)}) from None

    check.bounds, check.name, check.many = bounds, name, many  # what the range walk of the tests reads
    return check


def ranged(bounds: Bounds, name: str, description: str, *, many: bool = False, kind=float, where=Query):
    """The annotated type of a query parameter (``where=Form``: a form field) named ``name`` that holds a number
    of kind ``kind`` (with ``many`` a list or range of them, given as one string) inside ``bounds``.

    ``{range}`` in ``description`` becomes the range as stated (``in [0, 1) s``); without it the range follows
    the description."""
    text = (
        description.replace("{range}", bounds.text)
        if "{range}" in description
        else f"{description}, {bounds.text}"
    )
    schema = {"x-range": bounds.text, **({} if many else bounds.json_schema())}
    if many:  # a string, read after it is one; the handler gets the list, also of the default
        return Annotated[
            str,
            where(description=text, json_schema_extra=schema, validate_default=True),
            AfterValidator(_validator(bounds, name, many)),
        ]
    # read before pydantic does: '2.5' for a whole number or 'nan' get the command line's words
    return Annotated[
        kind,
        where(description=text, json_schema_extra=schema),
        BeforeValidator(_validator(bounds, name, many)),
    ]


def request_numbers(request: dict, bounds: dict[str, tuple[Bounds, bool]]) -> dict:
    """The request's numeric fields read and checked (:func:`read_number`); ``bounds`` maps each field to its
    range and whether it takes a list. A field given as null keeps None."""
    out = dict(request)
    for key, (b, many) in bounds.items():
        if out.get(key) is not None:
            out[key] = read_number(out[key], b, key, many=many)
    return out


def angle_warnings(robot, **angles) -> list[str]:
    """What to say of the wing and leg angles ``theta_w=...``, ``theta_l=...`` (values or lists) that look like
    radians for this robot's joints (:func:`geometry.bounds.joint_angle_slips`), as the command line warns of
    them."""
    return joint_angle_slips(robot, angles, {"theta_w": "theta_w", "theta_l": "theta_l"})
