"""The forces of a linkage's springs and dampers over crank angles (``planar.springs`` describes
them): a spring's length, its rate and its tension, a torsion spring's deflection (continuous
from the assembled sketch) and torque, and the check that a spring's points stay apart.
"""

from __future__ import annotations

import math

import numpy as np

from linkgen.errors import DescriptionError, LinkgenError
from linkgen.families.planar.description import Mechanism
from linkgen.families.planar.kinematics import solve
from linkgen.families.planar.pose import mechanism_size
from linkgen.families.planar.springs import Spring, TorsionSpring

# A spring's points closer than this fraction of the mechanism's size have no line of action: the
# direction u = d/|d| then rests on the rounding of the points' coordinates (~1e-16 of the size),
# off by up to 1e-16/1e-9 = 1e-7 rad at the limit.
COINCIDE_TOL = 1e-9
# Crank angles over the drive's range on which ``check_apart`` looks for the points' least
# distance before refining it: one every 0.5° over a turn.
SAMPLES = 721


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


__all__ = ["COINCIDE_TOL", "SAMPLES", "check_apart", "sketch_relative", "spring_lengths", "spring_tension",
           "torsion_deflection", "torsion_torque", "winding"]
