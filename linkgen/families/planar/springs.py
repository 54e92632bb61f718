"""Springs and dampers of a linkage: between two points (``[[spring]]``, ``Spring``) and at a
revolute between two links (``[[torsion_spring]]``, ``TorsionSpring``); their checks and loads.

A spring between points P₁ and P₂ (on different links; one may be on the ground) pulls them
together with the tension T = k·(L − L₀) + c·L̇, L = |P₂ − P₁|, L̇ = ω·dL/dφ: the force on P₁ is
T·u and on P₂ −T·u, u = (P₂ − P₁)/L. T < 0 pushes them apart (a compressed or gas spring: a rest
length longer than the points ever get). A point shared by several links (a revolute) loads the
first moving link listing it (the pin passes it on); its distance must change (no link carries
both points) and never vanish (the line of action is then undefined).

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

import numpy as np

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
# A spring's points closer than this fraction of the mechanism's size have no line of action: the
# direction u = d/|d| then rests on the rounding of the points' coordinates (~1e-16 of the size),
# off by up to 1e-16/1e-9 = 1e-7 rad at the limit.
COINCIDE_TOL = 1e-9
# Crank angles over the drive's range on which ``check_apart`` looks for the points' least
# distance before refining it: one every 0.5° over a turn.
SAMPLES = 721


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
            raise DescriptionError(f"{where}.points", f"{p!r} and {q!r} are both on link {(both or ['the same'])[0]!r}, "
                                                      f"so their distance never changes; a spring joins points on two "
                                                      f"different links (one may be on the ground)")
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


def _coincide(mech: Mechanism, spring: Spring, phi: np.ndarray, where: str) -> DescriptionError:
    i = mech.springs.index(spring)
    p, q = spring.points
    at = ", ".join(f"{math.degrees(a):.6g}°" for a in phi[:5]) + (" …" if len(phi) > 5 else "")
    return DescriptionError(f"spring[{i}].points", f"{p!r} and {q!r} coincide {where} (crank angle {at}), where the "
                                                   f"spring has no line of action; attach it to points that stay apart")


def check_apart(asm) -> None:
    """Raise DescriptionError if a spring's two points come within COINCIDE_TOL of the size of
    each other anywhere over the drive's range: the least distance of each spring's points on a
    grid of SAMPLES angles, each local least refined by Brent's method on |d|² (smooth, where |d|
    has a corner at 0). Done once per assembly."""
    from scipy.optimize import minimize_scalar

    from linkgen.families.planar.kinematics import solve
    from linkgen.families.planar.pose import mechanism_size

    if asm.__dict__.get("_linkgen_springs_apart") or not asm.mechanism.springs:
        return
    mech = asm.mechanism
    d = mech.drive
    grid = np.linspace(d.start, d.stop, SAMPLES)
    kin = solve(asm, grid, on_singular="mark")
    tol = COINCIDE_TOL * mechanism_size(mech)
    for spring in mech.springs:
        def dist2(phi, spring=spring):
            k = solve(asm, np.atleast_1d(phi), on_singular="mark")
            r = k.points[spring.points[1]].p - k.points[spring.points[0]].p
            return np.einsum("ij,ij->i", r, r)

        r = kin.points[spring.points[1]].p - kin.points[spring.points[0]].p
        g = np.einsum("ij,ij->i", r, r)
        low = [j for j in range(len(g)) if g[j] <= g[max(j - 1, 0)] and g[j] <= g[min(j + 1, len(g) - 1)]]
        for j in low:
            a, b = grid[max(j - 1, 0)], grid[min(j + 1, len(g) - 1)]
            best = minimize_scalar(lambda x: float(dist2(x)[0]), bounds=(a, b), method="bounded",
                                   options={"xatol": 1e-13}) if b > a else None
            x, v = (best.x, best.fun) if best is not None and best.fun < g[j] else (grid[j], g[j])
            if not math.sqrt(max(v, 0.0)) > tol:
                raise _coincide(mech, spring, np.array([x]), "along the motion")
    asm.__dict__["_linkgen_springs_apart"] = True


def spring_lengths(kin, spring: Spring):
    """L (n,) [m], dL/dφ (n,) [m/rad] and the unit vector u from the first point to the second
    (n, 2) at the angles of ``kin``. Raises DescriptionError where the points (nearly) coincide,
    at these angles or anywhere over the drive's range (``check_apart``)."""
    from linkgen.families.planar.pose import mechanism_size

    p, q = kin.points[spring.points[0]], kin.points[spring.points[1]]
    d = q.p - p.p
    length = np.hypot(d[:, 0], d[:, 1])
    close = ~(length > COINCIDE_TOL * mechanism_size(kin.assembly.mechanism)) & ~kin.singular
    if np.any(close):
        raise _coincide(kin.assembly.mechanism, spring, kin.phi[close], "")
    check_apart(kin.assembly)
    u = d / np.where(close, 1.0, length)[:, None]
    return length, np.einsum("ij,ij->i", u, q.d1 - p.d1), u


def spring_tension(kin, spring: Spring, omega) -> tuple[np.ndarray, np.ndarray]:
    """The tension T (n,) [N] (positive pulls the points together) at crank speed ω (scalar or
    (n,)), and u (n, 2)."""
    length, rate, u = spring_lengths(kin, spring)
    return spring.stiffness * (length - spring.rest_length) + spring.damping * rate * omega, u


def winding(asm, a: str, b: str) -> int:
    """How many turns link b makes against link a while the crank turns once (0 if the crank
    does not turn fully): what keeps θ_b − θ_a continuous across turns. Cached on the assembly."""
    from linkgen.errors import LinkgenError
    from linkgen.families.planar.kinematics import solve

    cache = asm.__dict__.setdefault("_linkgen_winding", {})
    if (a, b) not in cache:
        d = asm.mechanism.drive
        k = 0
        if d.stop - d.start >= 2 * math.pi - 1e-9:
            phi = asm.sketch_phi + np.linspace(0.0, 2 * math.pi, 257)
            try:
                kin = solve(asm, phi)
                rel = np.unwrap(kin.links[b].angle.v - kin.links[a].angle.v)
                k = int(round((rel[-1] - rel[0]) / (2 * math.pi)))
            except LinkgenError:
                k = 0
        cache[(a, b)] = k
    return cache[(a, b)]


def sketch_relative(asm, a: str, b: str) -> float:
    """θ_b − θ_a [rad] in the assembled sketch (the pose at the sketch's crank angle, where a
    MuJoCo model's joints are 0). Cached on the assembly."""
    from linkgen.families.planar.kinematics import solve

    cache = asm.__dict__.setdefault("_linkgen_sketch_relative", {})
    if (a, b) not in cache:
        kin = solve(asm, np.array([asm.sketch_phi]))
        cache[(a, b)] = float(kin.links[b].angle.v[0] - kin.links[a].angle.v[0])
    return cache[(a, b)]


def torsion_deflection(kin, t: TorsionSpring) -> tuple[np.ndarray, np.ndarray]:
    """θ − θ₀ (n,) [rad], continuous from the assembled sketch, and dθ/dφ (n,) at the angles of
    ``kin``."""
    asm = kin.assembly
    a, b = t.links
    sketch = sketch_relative(asm, a, b)
    rest = sketch if t.rest_angle is None else t.rest_angle
    k = winding(asm, a, b)
    turned = k * (kin.phi - asm.sketch_phi)
    rel = kin.links[b].angle.v - kin.links[a].angle.v
    wrapped = np.mod(rel - sketch - turned + math.pi, 2 * math.pi) - math.pi
    return sketch - rest + wrapped + turned, kin.links[b].angle.d1 - kin.links[a].angle.d1


def torsion_torque(kin, t: TorsionSpring, omega) -> np.ndarray:
    """The torque τ (n,) [N·m] the torsion spring applies to its second link (−τ on the first)."""
    dev, rate = torsion_deflection(kin, t)
    return -t.stiffness * dev - t.damping * rate * omega


__all__ = ["MAX_DAMPING", "MAX_STIFFNESS", "MAX_TORSION_DAMPING", "MAX_TORSION_STIFFNESS", "Spring", "TorsionSpring",
           "carrier", "check_apart", "check_springs", "sketch_relative", "spring_lengths", "spring_tension", "torsion_deflection", "torsion_torque",
           "winding"]
