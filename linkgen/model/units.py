"""Reading physical values from a description: angles with units, finite numbers."""

from __future__ import annotations

import math
import re
import reprlib

from linkgen.errors import DescriptionError

_SHOWN = reprlib.Repr()
_SHOWN.maxstring, _SHOWN.maxother, _SHOWN.maxlevel = 60, 60, 3
_SHOWN.maxlist = _SHOWN.maxtuple = _SHOWN.maxdict = 6


def shown(value: object) -> str:
    """``repr(value)`` cut to a readable length (a hostile file may hold huge or deeply
    nested values; a message quotes only their beginning)."""
    if isinstance(value, float):
        return repr(value)  # full precision: the user compares it with the limit
    return _SHOWN.repr(value)


# Longest field path a message quotes in full [characters], as long as a value is quoted; a
# longer one (a huge name in it) keeps its beginning and says how much was left out.
FIELD_SHOWN = 60


def shown_field(field: str) -> str:
    """A field path cut to FIELD_SHOWN characters (with the count of those left out)."""
    if len(field) <= FIELD_SHOWN:
        return field
    return f"{field[:FIELD_SHOWN]}... ({len(field) - FIELD_SHOWN} more characters)"


_ANGLE = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(deg|rad)\s*$")


def parse_angle(value: object, field: str) -> float:
    """An angle [rad] from a float (radians) or a string ``"38.117deg"`` / ``"0.5rad"``."""
    if isinstance(value, bool):
        raise DescriptionError(field, f"must be an angle (number in rad or '<x>deg'), got {shown(value)}")
    if isinstance(value, (int, float)):
        return finite(value, field)
    if isinstance(value, str):
        m = _ANGLE.match(value)
        if m:
            x = float(m.group(1))
            return finite(math.radians(x) if m.group(2) == "deg" else x, field)
    raise DescriptionError(
        field, f"must be an angle: a number in rad or a string like '30deg' or '0.5rad', got {shown(value)}"
    )


def finite(value: object, field: str) -> float:
    """A finite float, else a DescriptionError naming the field."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise DescriptionError(field, f"must be a number, got {shown(value)}")
    try:
        x = float(value)
    except OverflowError:  # a TOML integer beyond float64's range
        x = math.inf
    if not math.isfinite(x):
        raise DescriptionError(field, f"must be finite, got {shown(value)}")
    return x


def positive(value: object, field: str, unit: str) -> float:
    """A finite float > 0."""
    x = finite(value, field)
    if x <= 0.0:
        raise DescriptionError(field, f"must be > 0 {unit}, got {shown(value)}")
    return x


def non_negative(value: object, field: str, unit: str) -> float:
    """A finite float >= 0."""
    x = finite(value, field)
    if x < 0.0:
        raise DescriptionError(field, f"must be >= 0 {unit}, got {shown(value)}")
    return x


def vector2(value: object, field: str) -> tuple[float, float]:
    """A 2-vector of finite floats."""
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise DescriptionError(field, f"must be a list of 2 numbers [x, y], got {shown(value)}")
    return (finite(value[0], f"{field}[0]"), finite(value[1], f"{field}[1]"))
