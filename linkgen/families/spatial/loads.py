"""External loads on a spatial mechanism: ``[[force]]`` at a point of a link and ``[[torque]]``
on a link, the planar keys with 3-D vectors (world axes, SI units):

    [[force]]   link, point (a point of that link), force = [Fx, Fy, Fz] [N],
                stroke = [from, to] (optional): the force acts only while the crank angle is in
                [from, to] modulo one turn — the planar convention (``planar.loads.stroke_active``)
    [[torque]]  link, torque = [Tx, Ty, Tz] [N·m]

A load on the ground does nothing, as for planar linkages. Both the closed form
(``spatial.forces``) and MuJoCo (``spatial.mjloads``) read these same records.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

from linkgen.errors import DescriptionError
from linkgen.model import limits
from linkgen.model.schema import string
from linkgen.model.units import bounded, finite, parse_angle, shown

_FORCE = {"link", "point", "force", "stroke"}
_TORQUE = {"link", "torque"}
# A stroke may be one full turn wide and a little more by rounding of "0deg".."360deg".
_TURN_SLACK = 1e-12


@dataclass(frozen=True)
class PointForce3:
    """External force [N] (3,) at ``point`` of ``link``, world axes; only while the crank angle
    is inside ``stroke`` = (from, to) [rad] when given (a process load)."""

    link: str
    point: str
    force: tuple[float, float, float]
    stroke: tuple[float, float] | None = None


@dataclass(frozen=True)
class LinkTorque3:
    """External torque [N·m] (3,) on ``link``, world axes."""

    link: str
    torque: tuple[float, float, float]


def _vector(value: Any, field: str, limit: float, unit: str, names: str) -> tuple[float, float, float]:
    if isinstance(value, bool) or not isinstance(value, (list, tuple)) or len(value) != 3:
        raise DescriptionError(field, f"must be a list of 3 numbers [{names}] [{unit}] in world axes, got {shown(value)}")
    return tuple(bounded(finite(v, f"{field}[{i}]"), f"{field}[{i}]", limit, unit)  # type: ignore[return-value]
                 for i, v in enumerate(value))


def _entries(value: Any, key: str) -> list:
    if not isinstance(value, list) or not all(isinstance(t, dict) for t in value):
        raise DescriptionError(key, f"must be an array of tables ([[{key}]]), got {shown(value)}")
    return value


def _link(spec: dict, where: str, links: dict) -> str:
    if "link" not in spec:
        raise DescriptionError(f"{where}.link", "is required")
    name = spec["link"]
    string(name, f"{where}.link")
    if name not in links:
        raise DescriptionError(f"{where}.link", f"unknown link {shown(name)}; known links: {', '.join(links)}")
    return name


def _keys(spec: dict, allowed: set, required: set, where: str) -> None:
    for k in spec:
        if k not in allowed:
            raise DescriptionError(f"{where}.{k if len(str(k)) <= 60 else shown(k)}",
                                   f"unknown key; allowed: {', '.join(sorted(allowed))}")
    for k in sorted(required):
        if k not in spec:
            raise DescriptionError(f"{where}.{k}", "is required")


def _stroke(value: Any, where: str) -> tuple[float, float]:
    if not isinstance(value, list) or len(value) != 2:
        raise DescriptionError(where, f"must be [from, to] crank angles, got {shown(value)}")
    lo, hi = (bounded(parse_angle(v, f"{where}[{i}]"), f"{where}[{i}]", limits.MAX_ANGLE, "rad")
              for i, v in enumerate(value))
    if not 0.0 < hi - lo <= 2 * math.pi + _TURN_SLACK:
        raise DescriptionError(where, f"must be [from, to] crank angles with from < to <= from + 360deg, "
                                      f"got [{lo!r}, {hi!r}] rad")
    return lo, hi


def read_loads(data: dict, links: dict) -> tuple[tuple[PointForce3, ...], tuple[LinkTorque3, ...]]:
    """The ``[[force]]`` and ``[[torque]]`` entries of a spatial description; ``links`` maps each
    link's name to its points. Errors name the entry's field, its value and what is allowed."""
    forces = []
    for i, spec in enumerate(_entries(data.get("force", []), "force")):
        where = f"force[{i}]"
        _keys(spec, _FORCE, {"link", "point", "force"}, where)
        link = _link(spec, where, links)
        point = spec["point"]
        string(point, f"{where}.point")
        if point not in links[link]:
            raise DescriptionError(f"{where}.point", f"{shown(point)} is not a point of link {link!r} "
                                                     f"({', '.join(links[link])})")
        stroke = _stroke(spec["stroke"], f"{where}.stroke") if "stroke" in spec else None
        forces.append(PointForce3(link, point, _vector(spec["force"], f"{where}.force", limits.MAX_FORCE, "N",
                                                       "Fx, Fy, Fz"), stroke))
    torques = []
    for i, spec in enumerate(_entries(data.get("torque", []), "torque")):
        where = f"torque[{i}]"
        _keys(spec, _TORQUE, _TORQUE, where)
        torques.append(LinkTorque3(_link(spec, where, links), _vector(spec["torque"], f"{where}.torque",
                                                                       limits.MAX_TORQUE, "N·m", "Tx, Ty, Tz")))
    return tuple(forces), tuple(torques)


__all__ = ["LinkTorque3", "PointForce3", "read_loads"]
