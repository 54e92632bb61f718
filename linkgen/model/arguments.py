"""Drive angles and rates as a user gives them, to the command line (``--angle 30deg``,
``--omega 120rpm``) and to the API (``linkgen.kinematics(mech, "30deg", omega="120rpm")``): one
parser and one set of messages for both.

An angle is a number in rad (the API; the command line wants the unit) or a string with its
unit ("30deg", "30°", "0.5rad"); a speed a number in rad/s or "120rpm", "10rad/s", "30deg/s"; an
acceleration a number in rad/s² or "2rad/s2", "60rpm/s". The API also takes arrays (or lists)
of them. Each is finite and within linkgen's limits (``linkgen.model.limits``)."""

from __future__ import annotations

import math

import numpy as np

from linkgen.errors import ArgumentError, DescriptionError
from linkgen.model import limits
from linkgen.model.units import LENGTH_UNITS, angular_acceleration, angular_speed, length, parse_angle


class Angle(float):
    """A drive input given with an angle's unit ("30deg"): a crank angle [rad]."""


class Stroke(float):
    """A drive input given with a length's unit ("0.45m", "450mm"): a prismatic drive's stroke [m]."""


def input_kind(value, slides: bool, name: str):
    """``value`` unchanged if its unit (when it had one) suits the drive: an angle for a crank, a
    length for a prismatic drive (``slides``); else an ArgumentError naming ``name``."""
    if slides and isinstance(value, Angle):
        raise ArgumentError(f"{name}: the drive is a prismatic pair: give its stroke with a length's unit "
                            f"(e.g. 0.45m or 450mm), got an angle")
    if not slides and isinstance(value, Stroke):
        raise ArgumentError(f"{name}: the drive turns a crank: give an angle with its unit (e.g. 30deg), got a length")
    return value


def angle_text(text: str) -> float:
    """An angle [rad] (``Angle``) from a string with its unit, or a prismatic drive's stroke [m]
    (``Stroke``) from one with a length's unit; ArgumentError saying what is allowed."""
    try:
        float(text)
    except ValueError:
        pass
    else:
        raise ArgumentError(f"an angle needs its unit: write {text}deg or {text}rad (or {text}°), got {text!r}")
    if any(text.strip().endswith(u) for u in LENGTH_UNITS):
        try:
            return Stroke(_within(length(text, "stroke"), limits.MAX_LENGTH, "m", text))
        except DescriptionError:
            raise ArgumentError(f"expected a stroke like 0.45m or 450mm, got {text!r}") from None
    try:
        x = parse_angle(text, "angle")
    except DescriptionError:
        raise ArgumentError(f"expected an angle like 30deg, 30° or 0.52rad, got {text!r}") from None
    return Angle(_within(x, limits.MAX_ANGLE, "rad", text))


def rate_text(text: str, unit: str, limit: float | None = None) -> float:
    """A speed [rad/s] (``unit`` "rad/s") or an acceleration [rad/s²] (``unit`` "rad/s²") from a
    string: a number in ``unit``, or one with its own unit (100rpm, 60rpm/s)."""
    if limit is None:
        limit = limits.MAX_OMEGA if unit == "rad/s" else limits.MAX_EPSILON
    try:
        x = float(text)
    except ValueError:
        x = math.nan
    if not math.isfinite(x):
        read = angular_speed if unit == "rad/s" else angular_acceleration
        try:
            x = read(text, "rate")
        except DescriptionError:
            raise ArgumentError(f"expected a number in {unit} or one with its unit "
                                f"(e.g. {'100rpm' if unit == 'rad/s' else '60rpm/s'}), got {text!r}") from None
    return _within(x, limit, unit, text)


def _within(x: float, limit: float, unit: str, given) -> float:
    if abs(x) > limit:
        raise ArgumentError(f"expected a number within ±{limit:g} {unit} (linkgen's limits, see the README), "
                            f"got {given!r}" if unit != "rad" else
                            f"expected an angle within ±{limit:g} rad (linkgen's limits, see the README), got {given!r}")
    return x


def _value(value, name: str, unit: str):
    """One number (SI) or string (with its unit) → float [SI]; ArgumentError naming ``name``."""
    try:
        if isinstance(value, str):
            return angle_text(value) if unit == "rad" else rate_text(value, unit)
        if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, float, np.integer, np.floating)):
            raise ArgumentError(f"expected a number in {unit} or a string with its unit, got {value!r}")
        x = float(value)
        if not math.isfinite(x):
            raise ArgumentError(f"expected a finite number, got {value!r}")
        limit = {"rad": limits.MAX_ANGLE, "rad/s": limits.MAX_OMEGA}.get(unit, limits.MAX_EPSILON)
        return _within(x, limit, unit, value)
    except ArgumentError as exc:
        raise ArgumentError(f"{name}: {exc}") from None


def argument(value, name: str, unit: str):
    """``value`` (a number in SI, a string with its unit, or a non-empty array/list of them) in
    SI: a float for a scalar, an array (n,) for a sequence. ``unit``: "rad", "rad/s" or "rad/s²"."""
    if isinstance(value, (list, tuple, np.ndarray)) and np.size(value) == 0:
        raise ArgumentError(f"{name}: expected a number or a non-empty 1-D array of them, got an empty "
                            f"{type(value).__name__}")
    if isinstance(value, np.ndarray) and value.dtype.kind in "iuf":
        x = value.astype(float)
        bad = ~np.isfinite(x)
        if bad.any():
            raise ArgumentError(f"{name}: expected finite numbers, got {float(x[bad][0])!r} at index "
                                f"{int(np.argwhere(bad)[0][0])}")
        if x.ndim > 1:
            raise ArgumentError(f"{name}: expected a number or a 1-D array of them, got shape {x.shape}")
        limit = {"rad": limits.MAX_ANGLE, "rad/s": limits.MAX_OMEGA}.get(unit, limits.MAX_EPSILON)
        big = np.abs(x) > limit
        if big.any():
            _value(float(x[big][0]), f"{name}[{int(np.argwhere(big)[0][0])}]", unit)
        return float(x) if x.ndim == 0 else x
    if isinstance(value, (list, tuple, np.ndarray)):
        return np.array([_value(v, f"{name}[{i}]", unit) for i, v in enumerate(value)], dtype=float)
    return _value(value, name, unit)


def angle_argument(value, name: str = "phi"):
    """A drive angle (or angles) [rad] from the API: numbers in rad or strings like "30deg"."""
    return argument(value, name, "rad")


def rate_argument(value, name: str, unit: str):
    """ω [rad/s] (``unit`` "rad/s") or ε [rad/s²] from the API, or arrays of them; None stays
    None (the drive's)."""
    return None if value is None else argument(value, name, unit)


def one_rate(value, name: str, unit: str) -> float | None:
    """One ω [rad/s] (``unit`` "rad/s") or ε [rad/s²] for every drive angle of a call, as the
    registry's API takes them in every family; None stays None (the drive's). A sequence is an
    ArgumentError naming the argument."""
    if isinstance(value, (list, tuple, np.ndarray)) and np.ndim(value) > 0:
        example = "120rpm" if unit == "rad/s" else "60rpm/s"
        raise ArgumentError(f"{name}: expected one value for every drive angle (a number in {unit} or a string "
                            f"like {example}), got a sequence of {np.size(value)}; for values that vary with the "
                            f"angle, call once per angle")
    return rate_argument(value, name, unit)


__all__ = ["Angle", "Stroke", "input_kind", "angle_argument", "angle_text", "argument", "one_rate", "rate_argument", "rate_text"]
