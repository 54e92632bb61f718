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


_NUMBER = r"([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)"
_ANGLE = re.compile(r"^\s*" + _NUMBER + r"\s*(deg|°|rad)\s*$")


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
            return finite(math.radians(x) if m.group(2) in ("deg", "°") else x, field)
    raise DescriptionError(
        field, f"must be an angle: a number in rad or a string like '30deg', '30°' or '0.5rad', got {shown(value)}"
    )


# Units a description may give, each as its factor to SI.
LENGTH_UNITS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3}
SPEED_UNITS = {"rad/s": 1.0, "rpm": 2 * math.pi / 60, "deg/s": math.pi / 180}
TIME_UNITS = {"s": 1.0, "ms": 1e-3, "min": 60.0}
ACCELERATION_UNITS = {"rad/s2": 1.0, "rad/s²": 1.0, "rpm/s": 2 * math.pi / 60, "deg/s2": math.pi / 180,
                      "deg/s²": math.pi / 180}


def _with_unit(value: object, field: str, units: dict[str, float], what: str, examples: str) -> float:
    """A number in SI, or a string "<number><unit>" (spaces allowed) with one of ``units``."""
    if isinstance(value, (int, float)) and not isinstance(value, bool):
        return finite(value, field)
    if isinstance(value, str):
        m = re.match(r"^\s*" + _NUMBER + r"\s*(\S+)\s*$", value)
        if m and m.group(2) in units:
            return finite(float(m.group(1)) * units[m.group(2)], field)
    raise DescriptionError(field, f"must be {what}: a number in SI or a string like {examples}, got {shown(value)}")


def length(value: object, field: str) -> float:
    """A length [m] from a number (metres) or "200mm", "20cm", "0.2m"."""
    return _with_unit(value, field, LENGTH_UNITS, "a length", "'200mm', '20cm' or '0.2m'")


def seconds(value: object, field: str) -> float:
    """A time [s] from a number (seconds) or "0.2s", "200ms", "1.5min"."""
    return _with_unit(value, field, TIME_UNITS, "a time", "'0.2s', '200ms' or '1.5min'")


def angular_speed(value: object, field: str) -> float:
    """An angular speed [rad/s] from a number (rad/s) or "100rpm", "10rad/s", "30deg/s"."""
    return _with_unit(value, field, SPEED_UNITS, "an angular speed", "'100rpm' or '10rad/s'")


def angular_acceleration(value: object, field: str) -> float:
    """An angular acceleration [rad/s²] from a number or "2rad/s2", "2rad/s²", "60rpm/s"."""
    return _with_unit(value, field, ACCELERATION_UNITS, "an angular acceleration", "'2rad/s2' or '60rpm/s'")


LINEAR_SPEED_UNITS = {"m/s": 1.0, "mm/s": 1e-3, "cm/s": 1e-2}
LINEAR_ACCELERATION_UNITS = {"m/s2": 1.0, "m/s²": 1.0, "mm/s2": 1e-3, "mm/s²": 1e-3}


def linear_speed(value: object, field: str) -> float:
    """A speed [m/s] from a number (m/s) or "50mm/s", "0.05m/s" (a prismatic drive's)."""
    return _with_unit(value, field, LINEAR_SPEED_UNITS, "a speed", "'50mm/s' or '0.05m/s'")


def linear_acceleration(value: object, field: str) -> float:
    """An acceleration [m/s²] from a number or "0.1m/s2", "100mm/s²" (a prismatic drive's)."""
    return _with_unit(value, field, LINEAR_ACCELERATION_UNITS, "an acceleration", "'0.1m/s2' or '100mm/s²'")


def point2(value: object, field: str) -> tuple[float, float]:
    """A 2-vector of lengths [m], each a number (metres) or a string with a length unit."""
    if not isinstance(value, (list, tuple)) or len(value) != 2:
        raise DescriptionError(field, f"must be a list of 2 lengths [x, y], got {shown(value)}")
    return (length(value[0], f"{field}[0]"), length(value[1], f"{field}[1]"))


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


def bounded(x: float, where: str, limit: float, unit: str) -> float:
    """``x``, a finite number with |x| <= limit (linkgen.model.limits says where each limit comes from)."""
    if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x):
        raise DescriptionError(where, f"must be a finite number, got {shown(x)}")
    if abs(x) > limit:
        raise DescriptionError(where, f"must be within ±{limit:g} {unit} (linkgen's limits, see the README), "
                               f"got {x!r}")
    return x
