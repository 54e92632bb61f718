"""Reading physical values from a description: angles with units, finite numbers."""

from __future__ import annotations

import math
import re

from .errors import DescriptionError

_ANGLE = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(deg|rad)\s*$")


def parse_angle(value: object, field: str) -> float:
    """An angle [rad] from a float (radians) or a string ``"38.117deg"`` / ``"0.5rad"``."""
    if isinstance(value, bool):
        raise DescriptionError(field, f"must be an angle (number in rad or '<x>deg'), got {value!r}")
    if isinstance(value, (int, float)):
        return finite(value, field)
    if isinstance(value, str):
        m = _ANGLE.match(value)
        if m:
            x = float(m.group(1))
            return finite(math.radians(x) if m.group(2) == "deg" else x, field)
    raise DescriptionError(
        field, f"must be an angle: a number in rad or a string like '30deg' or '0.5rad', got {value!r}"
    )


def finite(value: object, field: str) -> float:
    """A finite float, else a DescriptionError naming the field."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise DescriptionError(field, f"must be a number, got {value!r}")
    x = float(value)
    if not math.isfinite(x):
        raise DescriptionError(field, f"must be finite, got {value!r}")
    return x


def positive(value: object, field: str, unit: str) -> float:
    """A finite float > 0."""
    x = finite(value, field)
    if x <= 0.0:
        raise DescriptionError(field, f"must be > 0 {unit}, got {value!r}")
    return x


def non_negative(value: object, field: str, unit: str) -> float:
    """A finite float >= 0."""
    x = finite(value, field)
    if x < 0.0:
        raise DescriptionError(field, f"must be >= 0 {unit}, got {value!r}")
    return x


def vector2(value: object, field: str) -> tuple[float, float]:
    """A 2-vector of finite floats."""
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise DescriptionError(field, f"must be a list of 2 numbers [x, y], got {value!r}")
    return (finite(value[0], f"{field}[0]"), finite(value[1], f"{field}[1]"))
