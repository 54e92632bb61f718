"""Springs and dampers of a linkage: between two points (``[[spring]]``, ``Spring``) and at a
revolute between two links (``[[torsion_spring]]``, ``TorsionSpring``); their checks and loads.

A spring between points P₁ and P₂ (on different links; one may be on the ground) pulls them
together with the tension T = k·(L − L₀) + c·L̇, L = |P₂ − P₁|, L̇ = ω·dL/dφ: the force on P₁ is
T·u and on P₂ −T·u, u = (P₂ − P₁)/L. T < 0 pushes them apart (a compressed or gas spring: a rest
length longer than the points ever get). A point shared by several links (a revolute) loads the
first moving link listing it (the pin passes it on); its distance must change (no link carries
both points) and never vanish (the line of action is then undefined: ``spring_loads``).

A torsion spring at a revolute between links (a, b) turns b against a by the torque
τ = −k·(θ − θ₀) − c·θ̇ on b and −τ on a, θ = θ_b − θ_a the angle between the links' x axes
(ground: its sketch angle, fixed), counted continuously from the sketch along the motion, and
θ₀ the ``rest_angle`` (default: the sketch's θ, unloaded there); the sketch is the assembled one
(the closed form's pose at the sketch's crank angle).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

from linkgen.errors import DescriptionError
from linkgen.model import limits
from linkgen.model.names import GROUND
from linkgen.model.units import bounded, shown

if TYPE_CHECKING:
    from linkgen.families.planar.description import Mechanism

# Bounds that keep every spring force and torque within linkgen's limits (linkgen.model.limits):
# a stiffness times the largest length is at most MAX_FORCE (and MAX_TORQUE per MAX_ANGLE), a
# damping times the largest speed (MAX_OMEGA·MAX_LENGTH, or MAX_OMEGA) likewise.
MAX_STIFFNESS = limits.MAX_FORCE / limits.MAX_LENGTH  # N/m
MAX_DAMPING = limits.MAX_FORCE / (limits.MAX_OMEGA * limits.MAX_LENGTH)  # N·s/m
MAX_TORSION_STIFFNESS = limits.MAX_TORQUE / limits.MAX_ANGLE  # N·m/rad
MAX_TORSION_DAMPING = limits.MAX_TORQUE / limits.MAX_OMEGA  # N·m·s/rad


@dataclass(frozen=True)
class Spring:
    """A spring and damper between two points: stiffness k [N/m] ≥ 0, rest length L₀ [m] ≥ 0,
    damping c [N·s/m] ≥ 0 (module docstring)."""

    points: tuple[str, str]
    stiffness: float
    rest_length: float
    damping: float = 0.0


@dataclass(frozen=True)
class TorsionSpring:
    """A torsion spring and damper at the revolute ``joint`` acting between ``links`` (a, b):
    stiffness [N·m/rad] ≥ 0, ``rest_angle`` θ₀ [rad] of b against a (None: the sketch's),
    damping [N·m·s/rad] ≥ 0 (module docstring)."""

    joint: str
    links: tuple[str, str]
    stiffness: float
    rest_angle: float | None = None
    damping: float = 0.0


def carrier(mech: Mechanism, point: str) -> str:
    """The link a spring's end at ``point`` loads: the first moving link listing it, else ground."""
    names = [link.name for link in mech.links if point in link.points]
    moving = [n for n in names if n != GROUND]
    return moving[0] if moving else names[0]


def _coefficients(where: str, k: float, c: float, k_max: float, c_max: float, units: tuple[str, str]) -> None:
    for key, x, top, unit in (("stiffness", k, k_max, units[0]), ("damping", c, c_max, units[1])):
        bounded(x, f"{where}.{key}", top, unit)
        if x < 0:
            raise DescriptionError(f"{where}.{key}", f"must be >= 0 {unit}, got {shown(x)}")


def check_springs(m: Mechanism) -> None:
    """Raise DescriptionError for the first bad spring or torsion spring of ``m``."""
    for i, s in enumerate(m.springs):
        where = f"spring[{i}]"
        if len(s.points) != 2:
            raise DescriptionError(f"{where}.points", f"must be two point names, got {shown(list(s.points))}")
        for j, p in enumerate(s.points):
            if p not in m.points:
                raise DescriptionError(f"{where}.points[{j}]", f"unknown point {p!r}; known points: {sorted(m.points)}")
        p, q = s.points
        both = [link.name for link in m.links if p in link.points and q in link.points]
        if p == q or both:
            on = f"link {both[0]!r}" if both else "one point"
            raise DescriptionError(f"{where}.points", f"{p!r} and {q!r} are both on {on}, so their distance never "
                                                      f"changes; a spring joins points on two different links (one "
                                                      f"may be on the ground)")
        _coefficients(where, s.stiffness, s.damping, MAX_STIFFNESS, MAX_DAMPING, ("N/m", "N·s/m"))
        bounded(s.rest_length, f"{where}.rest_length", limits.MAX_LENGTH, "m")
        if s.rest_length < 0:
            raise DescriptionError(f"{where}.rest_length", f"must be >= 0 m, got {shown(s.rest_length)}")
        if math.dist(m.points[p], m.points[q]) < limits.MIN_LENGTH:
            raise DescriptionError(f"{where}.points", f"{p!r} and {q!r} coincide in the sketch: a spring needs two "
                                                      f"distinct points for its line of action")
    for i, t in enumerate(m.torsion_springs):
        where = f"torsion_spring[{i}]"
        joints = {r.name: r for r in m.revolutes}
        if t.joint not in joints:
            raise DescriptionError(f"{where}.joint", f"unknown revolute {t.joint!r}; revolutes: {sorted(joints)}")
        point = joints[t.joint].point
        carriers = [link.name for link in m.links if point in link.points]
        if len(t.links) != 2 or t.links[0] == t.links[1] or any(n not in carriers for n in t.links):
            raise DescriptionError(f"{where}.links", f"must be two different links that carry the revolute "
                                                     f"{t.joint!r} (at point {point!r}: {carriers}), got "
                                                     f"{shown(list(t.links))}")
        _coefficients(where, t.stiffness, t.damping, MAX_TORSION_STIFFNESS, MAX_TORSION_DAMPING,
                      ("N·m/rad", "N·m·s/rad"))
        if t.rest_angle is not None:
            bounded(t.rest_angle, f"{where}.rest_angle", limits.MAX_ANGLE, "rad")


__all__ = ["MAX_DAMPING", "MAX_STIFFNESS", "MAX_TORSION_DAMPING", "MAX_TORSION_STIFFNESS", "Spring", "TorsionSpring",
           "carrier", "check_springs"]
