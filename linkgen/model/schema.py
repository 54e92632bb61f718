"""The type of every key of every family's description, checked before a reader looks anything
up: a name where a name belongs, a number where a number belongs, a table or a list where one
belongs. A list or a table where a name is expected (``slider = ["slider"]``) would otherwise
reach a dictionary lookup or a set and fail there as a TypeError; here it is a DescriptionError
naming the field, the value and the type expected.

A schema is a dict of key -> check: a function ``check(value, field)`` that raises
DescriptionError (the readers' own parsers: ``length``, ``parse_angle``, ...), a nested dict
(a table with those keys), ``Each(check)`` (a table whose keys are the user's names, each value
checked alike) or ``Items(check)`` (a list, each item checked). Keys a schema does not list are
left to the reader, which names the allowed keys.
"""

from __future__ import annotations

import unicodedata
from dataclasses import dataclass
from typing import Any

from linkgen.errors import DescriptionError
from linkgen.model.units import (FIELD_SHOWN, angular_acceleration, angular_speed, finite, length, linear_acceleration,
                                 linear_speed, parse_angle, point2, seconds, shown, vector2)


@dataclass(frozen=True)
class Each:
    """A table of the user's names, each value checked by ``check``."""

    check: Any


@dataclass(frozen=True)
class Items:
    """A list, each item checked by ``check``."""

    check: Any


def string(value: object, field: str) -> None:
    if not isinstance(value, str):
        raise DescriptionError(field, f"must be a string, got {shown(value)}")


def title(value: object, field: str) -> None:
    """One line of printable text: a title reaches terminals, drawings, reports and MJCF comments,
    and a control character (a bell, an escape sequence, a line end) has no place in any."""
    string(value, field)
    bad = next((i for i, c in enumerate(value) if unicodedata.category(c) in ("Cc", "Cs")
                or c in "\ufffe\uffff\u2028\u2029"), None)
    if bad is not None:
        raise DescriptionError(field, f"must be one line of printable text; it holds the control character "
                                      f"U+{ord(value[bad]):04X} at position {bad + 1}")


def boolean(value: object, field: str) -> None:
    if not isinstance(value, bool):
        raise DescriptionError(field, f"must be true or false, got {shown(value)}")


def whole(value: object, field: str) -> None:
    if isinstance(value, bool) or not isinstance(value, int):
        # TOML reads 60.0 and 1e18 as floats: say how to write the number, not that it is not whole
        how = " written as an integer (60, not 60.0 or 6e1)" if isinstance(value, float) and value.is_integer() else ""
        raise DescriptionError(field, f"must be a whole number{how}, got {shown(value)}")


def quantity(value: object, field: str) -> None:
    """A number in SI or a string with its unit (the family reader knows which units)."""
    if isinstance(value, bool) or not isinstance(value, (int, float, str)):
        raise DescriptionError(field, f"must be a number or a string with its unit, got {shown(value)}")


def _lengths3(value: object, field: str) -> None:
    if not isinstance(value, list) or len(value) != 3:
        raise DescriptionError(field, f"must be a list of 3 lengths [x, y, z], got {shown(value)}")
    for i, v in enumerate(value):
        length(v, f"{field}[{i}]")


def _numbers3(value: object, field: str) -> None:
    if not isinstance(value, list) or len(value) != 3:
        raise DescriptionError(field, f"must be a list of 3 numbers [x, y, z], got {shown(value)}")
    for i, v in enumerate(value):
        finite(v, f"{field}[{i}]")


def _angles2(value: object, field: str) -> None:
    if not isinstance(value, list) or len(value) != 2:
        raise DescriptionError(field, f"must be [from, to], got {shown(value)}")
    for i, v in enumerate(value):
        parse_angle(v, f"{field}[{i}]")


def check(value: object, spec: Any, field: str) -> None:
    """``value`` against ``spec`` (see the module docstring); DescriptionError at the first
    mismatch, naming its field."""
    if isinstance(spec, dict):
        if not isinstance(value, dict):
            raise DescriptionError(field, f"must be a table, got {shown(value)}")
        for key, item in value.items():
            if key in spec:
                check(item, spec[key], f"{field}.{key}" if field else key)  # the schema's keys are short
    elif isinstance(spec, Each):
        if not isinstance(value, dict):
            raise DescriptionError(field, f"must be a table, got {shown(value)}")
        for key, item in value.items():
            name = key if len(key) <= FIELD_SHOWN else shown(key)  # a hostile file's key may be megabytes long
            check(item, spec.check, f"{field}.{name}")
    elif isinstance(spec, Items):
        if not isinstance(value, list):
            raise DescriptionError(field, f"must be a list, got {shown(value)}")
        for i, item in enumerate(value):
            check(item, spec.check, f"{field}[{i}]")
    else:
        spec(value, field)


SEGMENT = {"kind": string, "span": parse_angle, "law": string, "height": quantity}
LAW = {"kind": string, "amplitude": quantity, "mean": quantity, "phase": parse_angle}
MECHANISM = {"name": string, "title": title, "space": string}

MACHINE = {
    "rotor_inertia": finite, "gear_ratio": finite, "gear_efficiency": finite, "flywheel_inertia": finite,
    "start_angle": parse_angle, "start_speed": angular_speed, "duration": finite, "turns": finite,
    "rtol": finite, "tables": boolean,
    "motor": {"kind": string, "torque": finite, "stall_torque": finite, "no_load_speed": angular_speed,
              "rated_power": finite, "synchronous_speed": angular_speed, "rated_slip": finite,
              "breakdown_ratio": finite, "voltage": finite, "resistance": finite, "inductance": finite,
              "torque_constant": finite, "emf_constant": finite},
    "shaft": {"stiffness": finite, "damping": finite, "backlash": finite},
    "process_load": {"angles": Items(parse_angle), "torque": Items(finite)},
    "schedule": {"motor_on": seconds, "motor_off": seconds},
    "brake": {"kind": string, "torque": finite, "coefficient": finite, "from_time": seconds, "from_angle": parse_angle},
}

PLANAR = {
    "mechanism": {**MECHANISM, "gravity": vector2},
    "points": Each(point2),
    "links": Each({"points": Items(string), "length": length, "density": finite, "areal_density": finite,
                   "inertial": {"mass": finite, "com": point2, "inertia": finite}, "shape": Each(point2)}),
    "prismatic": Each({"slider": string, "guide": string, "point": string, "through": string, "angle": parse_angle,
                       "offset": length}),
    "drive": {"joint": string, "omega": angular_speed, "epsilon": angular_acceleration, "range": _angles2,
              "velocity": linear_speed, "acceleration": linear_acceleration, "start": length, "stop": length},
    "force": Items({"link": string, "point": string, "force": vector2, "stroke": _angles2}),
    "torque": Items({"link": string, "torque": finite}),
    "gear": Each({"planet": string, "kind": string, "module": length, "teeth": Items(whole),
                  "pressure_angle": parse_angle}),
    "cam": Each({"follower": string, "roller": string, "roller_radius": length, "spring_rate": finite,
                 "spring_preload": finite, "segment": Items(SEGMENT), "law": LAW}),
    "spring": Items({"points": Items(string), "stiffness": finite, "rest_length": length, "damping": finite}),
    "torsion_spring": Items({"joint": string, "links": Items(string), "stiffness": finite, "rest_angle": parse_angle,
                             "damping": finite}),
    "friction": Items({"pair": string, "coefficient": finite, "pin_radius": length, "block_length": length}),
    "machine": MACHINE,
}

CAM_FILE = {
    "mechanism": {**MECHANISM, "gravity": vector2},
    "cam": {"base_radius": length, "omega": angular_speed},
    "follower": {"kind": string, "face": string, "roller_radius": length, "offset": length, "mass": finite,
                 "pivot_distance": length, "arm_length": length, "inertia": finite, "lowest_angle": parse_angle,
                 "spring_rate": finite, "spring_preload": finite},
    "segment": Items(SEGMENT),
    "law": LAW,
}

SPATIAL = {
    "mechanism": {**MECHANISM, "gravity": _numbers3},
    "points": Each(_lengths3),
    "links": Each({"points": Items(string), "length": length, "mass": finite, "density": finite}),
    "joints": Each({"kind": string, "axis": _numbers3}),
    "prismatic": Each({"slider": string, "guide": string, "point": string, "direction": _numbers3}),
    "drive": {"joint": string, "omega": angular_speed, "epsilon": angular_acceleration, "velocity": finite,
              "acceleration": finite, "start": length, "stop": length},
}

__all__ = ["CAM_FILE", "Each", "Items", "boolean", "MACHINE", "PLANAR", "SPATIAL", "check", "quantity", "string", "title", "whole"]
