"""Closed-form kinematics from the Assur groups, vectorised over crank angles.

``solve`` returns positions and first/second transfer functions of every link, named point
and slider; ``Kinematics.motion`` turns them into velocities and accelerations for a crank
speed ω and acceleration ε (v = x′ω, a = x″ω² + x′ε). ``solve_motion`` goes straight to
positions, velocities and accelerations, keeping no transfer functions: less memory over long
arrays of angles. Both run long arrays in cache-sized blocks (``linkgen.blocks``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .assembly import Assembly, assemble
from .blocks import in_blocks
from .description import Mechanism
from .errors import ArgumentError, AssemblyError, SingularityError, angle_ranges
from .geometry import GuideShape, LinkPose
from .groups import fail_reason, input_poses, solve_group
from .motion import Motion, checked_derivatives, derivatives, rate
from .primitives import Scalar, Vec, constant_along, dot

# A group is flagged near-singular where its normalised transfer-function denominator
# (the sine or cosine of a transmission angle) is below this: 1e-3 rad from a dead centre,
# where transfer functions grow past ~1e3 times their typical size.
NEAR_SINGULAR = 1e-3


@dataclass(frozen=True)
class Kinematics:
    """Positions and transfer functions over crank angles ``phi`` (n,) [rad].

    Attributes:
        links: pose of every link: its angle (n,) [rad] with d/dφ, d²/dφ², and the points its
            group solved; ``origin`` and ``point(local)`` place any other point.
        points: every named point, Vec of (n, 2) [m], [m/rad], [m/rad²].
        sliders: every prismatic pair's displacement along its guide [m] (from the guide's
            base point), with transfer functions.
        near_singular: per group label, (n,) True where the group is near a dead centre.
    """

    assembly: Assembly
    phi: np.ndarray
    links: dict[str, LinkPose]
    points: dict[str, Vec]
    sliders: dict[str, Scalar]
    near_singular: dict[str, np.ndarray]

    def point(self, link: str, local) -> Vec:
        """Any point of any link, given in the link's local frame [m]."""
        return self.links[link].point(np.asarray(local, dtype=float))

    def motion(self, omega, epsilon=0.0) -> Motion:
        """Velocities and accelerations for crank speed ω [rad/s] and acceleration ε [rad/s²]
        (scalars or arrays of shape (n,))."""
        return derivatives(self.phi, _series(self.points, self.links, self.sliders), omega, epsilon)


def _series(points: dict[str, Vec], links: dict[str, LinkPose], sliders: dict[str, Scalar]) -> dict:
    return {
        "points": {k: (v.p, v.d1, v.d2) for k, v in points.items()},
        "links": {k: (p.angle.v, p.angle.d1, p.angle.d2) for k, p in links.items()},
        "sliders": {k: (s.v, s.d1, s.d2) for k, s in sliders.items()},
    }


def _angles(phi) -> np.ndarray:
    phi = np.atleast_1d(np.asarray(phi, dtype=float))
    if phi.ndim != 1 or phi.shape[0] == 0 or not np.all(np.isfinite(phi)):
        what = "non-finite entries" if phi.ndim == 1 and phi.shape[0] else f"shape {phi.shape}"
        raise ArgumentError(f"phi must be a non-empty, finite 1-D array of crank angles [rad], got {what}")
    return phi


def _assembly(mech_or_assembly: Mechanism | Assembly) -> Assembly:
    return mech_or_assembly if isinstance(mech_or_assembly, Assembly) else assemble(mech_or_assembly)


def solve(mech_or_assembly: Mechanism | Assembly, phi, threads: int | None = None) -> Kinematics:
    """Closed-form positions and transfer functions at crank angles ``phi`` [rad], shape (n,).

    Long arrays are solved in cache-sized blocks on ``threads`` threads (default: every core
    this process may use; see ``linkgen.blocks``); the result does not depend on either.

    Raises:
        AssemblyError: some group cannot be assembled at some angles (names the ranges).
        SingularityError: a transfer-function denominator is exactly zero at some angles.
    """
    asm, phi = _assembly(mech_or_assembly), _angles(phi)
    poses, points, sliders, near = _checked_blocks(asm, phi, lambda rows: _solve_block(asm, phi[rows]), threads)
    return Kinematics(asm, phi, poses, points, sliders, near)


def solve_motion(mech_or_assembly: Mechanism | Assembly, phi, omega, epsilon=0.0,
                 threads: int | None = None) -> Motion:
    """Positions, velocities and accelerations at crank angles ``phi`` [rad] (n,), crank speed
    ω [rad/s] and acceleration ε [rad/s²] (scalars or (n,)): ``solve(...).motion(ω, ε)``
    without keeping the transfer functions. Raises as ``solve`` does."""
    asm, phi = _assembly(mech_or_assembly), _angles(phi)
    n = phi.shape[0]
    w, e = rate("omega", omega, n, "rad/s"), rate("epsilon", epsilon, n, "rad/s²")

    def block(rows: slice):
        (poses, points, sliders, near), ok = _solve_block(asm, phi[rows])
        mo = checked_derivatives(phi[rows], _series(points, poses, sliders),
                                 w if np.ndim(w) == 0 else w[rows], e if np.ndim(e) == 0 else e[rows])
        return (mo.points, mo.links, mo.sliders, near), ok

    points, links, sliders, _ = _checked_blocks(asm, phi, block, threads)
    return Motion(phi, np.broadcast_to(w, (n,)), np.broadcast_to(e, (n,)), points, links, sliders)


def _checked_blocks(asm: Assembly, phi: np.ndarray, block, threads: int | None):
    """``blocks.in_blocks`` over ``phi``; if any block failed, raise with the failing angles."""
    tree, oks = in_blocks(block, phi.shape[0], threads)
    if not all(oks):
        _raise_failure(asm, phi)
    return tree


@np.errstate(invalid="ignore", divide="ignore", over="ignore")  # per call, so per thread
def _solve_block(asm: Assembly, phi: np.ndarray, report: list | None = None) -> tuple[tuple, bool]:
    """Solve one block of angles. Returns (poses, points, sliders, near-singular masks) and
    whether everything is assembled, non-singular and finite; ``report``, if given, receives
    each group's (fail, singular) masks. Failures are reported by angle, not as NumPy warnings."""
    mech = asm.mechanism
    poses = input_poses(mech, asm.structure, asm.shapes, phi)
    near, ok = {}, True
    for group, m in zip(asm.structure.groups, asm.branches):
        p1, p2, res = solve_group(group, m, poses, asm.shapes, asm.guides, mech)
        den = np.abs(res.denominator)
        singular = ~(den > 0.0)
        ok = ok and not (res.fail.any() or singular.any())
        if report is not None:
            report.append((group, res.fail, singular))
        near[group.label] = den < NEAR_SINGULAR
        poses[group.links[0]], poses[group.links[1]] = p1, p2
    points = {}
    for link in mech.links:
        for p in link.points:
            if p not in points:
                points[p] = poses[link.name].point(asm.shapes[link.name].local[p])
    sliders = {name: slider_motion(poses, g) for name, g in asm.guides.items()}
    # one pass per array: a NaN or inf anywhere makes the sum non-finite (constants: one row)
    ok = ok and all(np.isfinite((a[0] if constant_along(a) else a).sum())
                    for v in points.values() for a in (v.p, v.d1, v.d2))
    return (poses, points, sliders, near), ok


def _raise_failure(asm: Assembly, phi: np.ndarray) -> None:
    """Solve ``phi`` in one piece to name the angles where the first failing group fails."""
    report: list = []
    _, points, _, _ = _solve_block(asm, phi, report)[0]
    for group, fail, singular in report:
        if np.any(fail):
            raise AssemblyError(group.label, angle_ranges(phi, fail), fail_reason(group))
        if np.any(singular):
            raise SingularityError(group.label, angle_ranges(phi, singular))
    for name, v in points.items():
        bad = ~np.all(np.isfinite(v.p) & np.isfinite(v.d1) & np.isfinite(v.d2), axis=1)
        if np.any(bad):
            raise SingularityError(f"at point {name}", angle_ranges(phi, bad))
    raise RuntimeError("a block reported a failure that the whole array does not reproduce")


def slider_motion(poses: dict[str, LinkPose], g: GuideShape) -> Scalar:
    """Displacement of the slider point along the guide from the guide's base point [m]."""
    guide = poses[g.guide]
    base, u = guide.point(g.base), guide.direction(g.alpha)
    r = poses[g.slider].point(g.point) - base
    return Scalar(
        dot(r.p, u.p),
        dot(r.d1, u.p) + dot(r.p, u.d1),
        dot(r.d2, u.p) + 2.0 * dot(r.d1, u.d1) + dot(r.p, u.d2),
    )


__all__ = ["Kinematics", "Motion", "solve", "solve_motion", "slider_motion"]
