"""The ``[machine.schedule]`` and ``[machine.brake]`` tables: when the motor runs, and a brake that
stops the crank (the textbook's ``Dvig_t`` with its ``tstart``/``tfinish`` and ``stop()``).

    [machine.schedule]
    motor_on = "0.2s"        # the motor is switched on here (default 0: from the start)
    motor_off = "3s"         # and off here (default: never); after motor_on

    [machine.brake]
    kind = "constant"        # "constant": torque [N·m] > 0; "viscous": coefficient [N·m·s/rad] > 0
    torque = 50.0
    from_time = "3.5s"       # applied from this time, or
    # from_angle = "720deg"  # from when the crank first reaches this angle (as start_angle)

Times are seconds, as a number or a string with its unit ("0.2s", "200ms"). The brake's moment on
the crank opposes the motion it finds when applied (−T·s, s = sgn ω then; or −c·ω) and never
drives the crank backwards: the run ends when the crank comes to rest with the brake applied
(the brake holds it from then). The machine's equations and what a run reports are in
docs/machine.md.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from linkgen.errors import DescriptionError
from linkgen.model import limits
from linkgen.model.units import bounded, finite, parse_angle, seconds, shown

# Each brake law and the key of its one parameter, with its unit.
BRAKE_KEYS = {"constant": ("torque", "N·m"), "viscous": ("coefficient", "N·m·s/rad")}
SCHEDULE_KEYS = ("motor_on", "motor_off")


@dataclass(frozen=True)
class Schedule:
    """The motor runs from ``motor_on`` to ``motor_off`` [s] (inf: never switched off)."""

    motor_on: float = 0.0
    motor_off: float = math.inf


@dataclass(frozen=True)
class Brake:
    """A brake on the crank: ``kind`` (BRAKE_KEYS), its torque [N·m] or coefficient [N·m·s/rad]
    (``value``), applied from the time ``from_time`` [s] or from the crank angle ``from_angle``
    [rad] (one of them, the other None)."""

    kind: str
    value: float
    from_time: float | None = None
    from_angle: float | None = None


def _only(t: dict, allowed, where: str) -> None:
    for k in t:
        if k not in allowed:
            raise DescriptionError(f"{where}.{k}", f"unknown key; allowed keys: {sorted(allowed)}")


def _time(t: dict, key: str, where: str, duration: float) -> float:
    x = seconds(t[key], f"{where}.{key}")
    if not 0.0 <= x <= duration:
        raise DescriptionError(f"{where}.{key}", f"must be a time within the run, 0 to machine.duration = "
                               f"{duration:g} s, got {shown(t[key])}")
    return x


def schedule_from_dict(t, duration: float) -> Schedule:
    """``[machine.schedule]`` of a run lasting ``duration`` [s]."""
    where = "machine.schedule"
    if not isinstance(t, dict):
        raise DescriptionError(where, f"must be a table, got {shown(t)}")
    _only(t, SCHEDULE_KEYS, where)
    on = _time(t, "motor_on", where, duration) if "motor_on" in t else 0.0
    off = _time(t, "motor_off", where, duration) if "motor_off" in t else math.inf
    if not off > on:
        raise DescriptionError(f"{where}.motor_off", f"must come after motor_on ({on:g} s), got {shown(t['motor_off'])}")
    return Schedule(on, off)


def brake_from_dict(t, duration: float) -> Brake:
    """``[machine.brake]`` of a run lasting ``duration`` [s]."""
    where = "machine.brake"
    if not isinstance(t, dict):
        raise DescriptionError(where, f"must be a table, got {shown(t)}")
    kind = t.get("kind")
    if kind not in BRAKE_KEYS:
        raise DescriptionError(f"{where}.kind", f"must be one of {sorted(BRAKE_KEYS)}, got {shown(kind)}")
    key, unit = BRAKE_KEYS[kind]
    _only(t, {"kind", key, "from_time", "from_angle"}, where)
    if key not in t:
        raise DescriptionError(f"{where}.{key}", f"is required for a {kind} brake ({unit})")
    value = finite(t[key], f"{where}.{key}")
    if not value > 0:
        raise DescriptionError(f"{where}.{key}", f"must be > 0 {unit} (the brake opposes the motion whatever its "
                               f"direction), got {shown(t[key])}")
    bounded(value, f"{where}.{key}", limits.MAX_TORQUE, unit)
    if ("from_time" in t) == ("from_angle" in t):
        raise DescriptionError(where, "needs exactly one of from_time (a time [s]) and from_angle (a crank angle) "
                               f"to say when it is applied, got {'both' if 'from_time' in t else 'neither'}")
    if "from_time" in t:
        return Brake(kind, value, from_time=_time(t, "from_time", where, duration))
    angle = bounded(parse_angle(t["from_angle"], f"{where}.from_angle"), f"{where}.from_angle", limits.MAX_ANGLE, "rad")
    return Brake(kind, value, from_angle=angle)


__all__ = ["BRAKE_KEYS", "Brake", "Schedule", "brake_from_dict", "schedule_from_dict"]
