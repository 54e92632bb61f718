"""Closed-form kinematics from the Assur groups, vectorised over crank angles.

``solve`` returns positions and first, second and third transfer functions of every link,
named point and slider; ``Kinematics.motion`` turns them into velocities, accelerations and
jerks for a crank speed ω and constant acceleration ε (v = x′ω, a = x″ω² + x′ε,
j = x‴ω³ + 3x″ωε). ``solve_motion`` goes straight to positions, velocities, accelerations and
jerks, keeping no transfer functions: less memory over long arrays of angles. Both run long arrays in cache-sized blocks (``linkgen.blocks``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from linkgen.families.planar.assembly import Assembly, assemble
from linkgen.families.planar.blocks import in_blocks
from linkgen.families.planar.description import Mechanism
from linkgen.errors import ArgumentError, AssemblyError, MagnitudeError, SingularityError, angle_ranges
from linkgen.families.planar.geometry import GuideShape, LinkPose
from linkgen.families.planar.groups import SINGULAR_TOL, fail_reason, input_poses, place, solve_group
from linkgen.families.planar.motion import Motion, all_finite, checked_derivatives, derivatives, rate
from linkgen.families.planar.primitives import Scalar, Vec, constant_along, dot, is_zero
from linkgen.families.planar.structure import Group, GroupKind

# The one rule for singular and near-singular poses: SINGULAR_TOL (linkgen.groups) says why.
ON_SINGULAR = ("raise", "mark")

_REASONS = {
    GroupKind.RRR: "its two links are (nearly) in line, a dead centre",
    GroupKind.RRP: "its link is (nearly) perpendicular to the guide line, a dead centre",
    GroupKind.RPR: "the slot is (nearly) perpendicular to the line joining the two pivots, a dead centre",
    GroupKind.PRP: "its two guides are (nearly) parallel",
    GroupKind.RPP: "its two guides are (nearly) parallel",
    GroupKind.ACTUATOR: "the rod's pin is (nearly) in line with the cylinder's pivot and the rocker's, a dead centre",
}


def singular_cause(group: Group) -> str:
    """Why a group is singular, in a few words (a dead centre, parallel guides)."""
    return _REASONS[group.kind]


def singular_reason(group: Group) -> str:
    """Why a group is singular, in words, with the rule."""
    return (f"{singular_cause(group)} (normalised transfer-function denominator below SINGULAR_TOL = "
            f"{SINGULAR_TOL:g}; transfer functions grow as its inverse)")


@dataclass(frozen=True)
class Kinematics:
    """Positions and transfer functions over crank angles ``phi`` (n,) [rad].

    Attributes:
        links: pose of every link: its angle (n,) [rad] with d/dφ, d²/dφ², d³/dφ³, and the
            points its group solved; ``origin`` and ``point(local)`` place any other point.
        points: every named point, Vec of (n, 2) [m], [m/rad], [m/rad²], [m/rad³].
        sliders: every prismatic pair's displacement along its guide [m] (from the guide's
            base point), with transfer functions.
        near_singular: per group label, (n,) True where that group is singular by the rule
            of SINGULAR_TOL and no earlier group is (all False unless solved with
            ``on_singular="mark"``).
        singular: (n,) True where any group is singular (``on_singular="mark"``); there the
            transfer functions are set to 0 and every value is finite but meaningless.
    """

    def __repr__(self) -> str:
        return f"Kinematics({self.assembly.mechanism.name!r}, {self.phi.shape[0]} angles, {len(self.points)} points)"


    assembly: Assembly
    phi: np.ndarray
    links: dict[str, LinkPose]
    points: dict[str, Vec]
    sliders: dict[str, Scalar]
    near_singular: dict[str, np.ndarray]
    singular: np.ndarray

    def point(self, link: str, local) -> Vec:
        """Any point of any link, given in the link's local frame [m]."""
        return self.links[link].point(np.asarray(local, dtype=float))

    def motion(self, omega, epsilon=0.0) -> Motion:
        """Velocities, accelerations and jerks for crank speed ω [rad/s] and acceleration ε
        [rad/s²] (scalars or arrays of shape (n,); the jerk takes ε constant in time).

        Raises:
            ArgumentError: ω or ε is not finite or not scalar or (n,).
            MagnitudeError: a velocity, acceleration or jerk overflows float64.
        """
        mo = derivatives(self.phi, _series(self.points, self.links, self.sliders), omega, epsilon)
        return replace(mo, singular=self.singular)


def _series(points: dict[str, Vec], links: dict[str, LinkPose], sliders: dict[str, Scalar]) -> dict:
    return {
        "points": {k: (v.p, v.d1, v.d2, v.d3) for k, v in points.items()},
        "links": {k: (p.angle.v, p.angle.d1, p.angle.d2, p.angle.d3) for k, p in links.items()},
        "sliders": {k: (s.v, s.d1, s.d2, s.d3) for k, s in sliders.items()},
    }


def checked_angles(phi) -> np.ndarray:
    phi = np.atleast_1d(np.asarray(phi, dtype=float))
    if phi.ndim != 1 or phi.shape[0] == 0 or not np.all(np.isfinite(phi)):
        what = "non-finite entries" if phi.ndim == 1 and phi.shape[0] else f"shape {phi.shape}"
        raise ArgumentError(f"phi must be a non-empty, finite 1-D array of crank angles [rad], got {what}")
    return phi


def checked_mode(on_singular) -> bool:
    """True for ``"mark"``, False for ``"raise"``; anything else is an ArgumentError."""
    if on_singular not in ON_SINGULAR:
        raise ArgumentError(f"on_singular must be one of {list(ON_SINGULAR)}, got {on_singular!r}")
    return on_singular == "mark"


def _assembly(mech_or_assembly: Mechanism | Assembly) -> Assembly:
    return mech_or_assembly if isinstance(mech_or_assembly, Assembly) else assemble(mech_or_assembly)


def solve(mech_or_assembly: Mechanism | Assembly, phi, threads: int | None = None, *,
          on_singular: str = "raise") -> Kinematics:
    """Closed-form positions and transfer functions at crank angles ``phi`` [rad], shape (n,).

    Long arrays are solved in cache-sized blocks on ``threads`` threads (default: every core
    this process may use; see ``linkgen.blocks``); the result does not depend on either.
    ``on_singular``: ``"raise"`` (default) or ``"mark"``: return normally, with
    ``Kinematics.singular`` True at the singular angles (see SINGULAR_TOL).

    Raises:
        AssemblyError: some group cannot be assembled at some angles (names the ranges).
        SingularityError: some group is singular by the rule of SINGULAR_TOL at some angles
            (``on_singular="raise"``), naming the group, the angles and the cause.
        MagnitudeError: intermediate values overflow float64.
    """
    mark = checked_mode(on_singular)
    asm, phi = _assembly(mech_or_assembly), checked_angles(phi)
    poses, points, sliders, near, marked = _checked_blocks(
        asm, phi, lambda rows: solve_block(asm, phi[rows], mark), threads, mark)
    return Kinematics(asm, phi, poses, points, sliders, near, marked)


def solve_motion(mech_or_assembly: Mechanism | Assembly, phi, omega, epsilon=0.0,
                 threads: int | None = None, *, on_singular: str = "raise") -> Motion:
    """Positions, velocities, accelerations and jerks at crank angles ``phi`` [rad] (n,), crank
    speed ω [rad/s] and acceleration ε [rad/s²] (scalars or (n,)): ``solve(...).motion(ω, ε)``
    without keeping the transfer functions. Raises as ``solve`` and ``Kinematics.motion`` do."""
    mark = checked_mode(on_singular)
    asm, phi = _assembly(mech_or_assembly), checked_angles(phi)
    n = phi.shape[0]
    w, e = rate("omega", omega, n, "rad/s"), rate("epsilon", epsilon, n, "rad/s²")

    def block(rows: slice):
        (poses, points, sliders, near, marked), ok = solve_block(asm, phi[rows], mark)
        if not ok:
            raise BlockFailed  # named by raise_failure over the whole array
        mo = checked_derivatives(phi[rows], _series(points, poses, sliders),
                                 w if np.ndim(w) == 0 else w[rows], e if np.ndim(e) == 0 else e[rows])
        return (mo.points, mo.links, mo.sliders, mo.jerk, near, marked), ok

    points, links, sliders, jerk, _, marked = _checked_blocks(asm, phi, block, threads, mark)
    return Motion(phi, np.broadcast_to(w, (n,)), np.broadcast_to(e, (n,)), points, links, sliders, marked, jerk)


def _checked_blocks(asm: Assembly, phi: np.ndarray, block, threads: int | None, mark: bool):
    """``blocks.in_blocks`` over ``phi``; if any block failed (returned False, or raised
    BlockFailed), raise with the failing angles."""
    try:
        tree, oks = in_blocks(block, phi.shape[0], threads)
    except BlockFailed:
        oks = [False]
    if not all(oks):
        raise_failure(asm, phi, mark)
    return tree


class BlockFailed(Exception):
    """A block found a failure; ``raise_failure`` names it over the whole array."""


@np.errstate(invalid="ignore", divide="ignore", over="ignore")  # per call, so per thread
def solve_block(asm: Assembly, phi: np.ndarray, mark: bool = False, report: list | None = None) -> tuple[tuple, bool]:
    """Solve one block of angles. Returns (poses, points, sliders, per-group singular masks,
    singular mask) and whether everything is assembled, finite and, unless ``mark``, not
    singular; ``report``, if given, receives each group's (fail, overflow, singular) masks,
    each outside the angles where an earlier group is already singular. With ``mark`` the
    transfer functions at singular angles are set to 0. Failures are reported by angle, not
    as NumPy warnings."""
    mech = asm.mechanism
    poses = input_poses(mech, asm.structure, asm.shapes, phi)
    n = phi.shape[0]
    near, marked, ok = {}, np.zeros(n, dtype=bool), True
    for group, m in zip(asm.structure.groups, asm.branches):
        p1, p2, res = solve_group(group, m, poses, asm.shapes, asm.guides, mech, phi)
        den = np.abs(np.broadcast_to(res.denominator, (n,)))
        fail = res.fail & ~marked
        overflow = ~np.isfinite(den) & ~marked & ~res.fail
        singular = (den < SINGULAR_TOL) & ~marked & ~res.fail
        ok = ok and not (fail.any() or overflow.any() or (not mark and singular.any()))
        if report is not None:
            report.append((group, fail, overflow, singular))
        near[group.label] = singular
        marked |= singular
        place(group, poses, p1, p2, res)
    points = {}
    for link in mech.links:
        for p in link.points:
            if p not in points:
                points[p] = poses[link.name].point(asm.shapes[link.name].local[p])
    sliders = {name: slider_motion(poses, g) for name, g in asm.guides.items()}
    if mech.slide_drive:  # the driven pair's stroke is the input itself: s, ds/ds = 1, 0, 0 exactly
        sliders[mech.drive.joint] = Scalar(phi.copy(), np.ones(n), np.zeros(n), np.zeros(n))
    if mark and marked.any():
        _clear([*points.values(), *poses.values(), *sliders.values()], marked)
    ok = ok and all(all_finite(a) for v in points.values() for a in (v.p, v.d1, v.d2, v.d3))
    return (poses, points, sliders, near, marked), ok


def _clear(trees: list, rows: np.ndarray) -> None:
    """At ``rows``: transfer functions to 0, non-finite values to 0 (singular angles)."""
    seen: set[int] = set()

    def fix(a: np.ndarray, derivative: bool) -> None:
        if id(a) in seen or constant_along(a):
            return
        seen.add(id(a))
        if derivative:
            a[rows] = 0.0
        else:
            sub = a[rows]
            a[rows] = np.where(np.isfinite(sub), sub, 0.0)

    for t in trees:
        if isinstance(t, LinkPose):
            t = [t.angle, *(vec for _, vec in t.known)]
        for x in t if isinstance(t, list) else [t]:
            value = x.p if isinstance(x, Vec) else x.v
            fix(value, False)
            fix(x.d1, True)
            fix(x.d2, True)
            fix(x.d3, True)
            if isinstance(x, Scalar):
                object.__setattr__(x, "cs", None)  # cached cos/sin of values just changed


def raise_failure(asm: Assembly, phi: np.ndarray, mark: bool = False) -> None:
    """Solve ``phi`` in one piece to name the angles where the first failing group fails."""
    report: list = []
    (_, points, _, _, _), _ = solve_block(asm, phi, mark, report)
    for group, fail, overflow, singular in report:
        if np.any(fail):
            slides = asm.mechanism.slide_drive  # a stroke has no turn to scan
            raise AssemblyError(group.label, angle_ranges(phi, fail), fail_reason(group),
                                None if slides else lambda: _where_it_assembles(asm), slides)
        if np.any(overflow):
            raise MagnitudeError(f"group {group.label}'s solution", angle_ranges(phi, overflow))
        if np.any(singular) and not mark:
            raise SingularityError(group.label, angle_ranges(phi, singular), singular_reason(group),
                                   asm.mechanism.slide_drive)
    for name, v in points.items():
        bad = ~np.all(np.isfinite(v.p) & np.isfinite(v.d1) & np.isfinite(v.d2) & np.isfinite(v.d3), axis=1)
        if np.any(bad):
            raise MagnitudeError(f"point {name}", angle_ranges(phi, bad))
    raise RuntimeError("a block reported a failure that the whole array does not reproduce")


def planar_turn(asm: Assembly):
    """The linkage's assembly over the turn [0, 2π) of its crank (``linkgen.model.turn``, the
    same scan and bisection as for spatial four-bars), from the block solver's own failure and
    dead-centre masks: some group cannot be assembled, or all are but one is at or too near a
    dead centre (``SINGULAR_TOL``) or its values overflow."""
    from linkgen.model.turn import turn_assembly

    def status(phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        report: list = []
        with np.errstate(all="ignore"):  # failures come back as masks, not warnings
            solve_block(asm, np.asarray(phi, dtype=float), True, report)
        fails = np.zeros(phi.shape[0], dtype=bool)
        rough = np.zeros(phi.shape[0], dtype=bool)
        for _, fail, overflow, singular in report:
            fails |= fail
            rough |= overflow | singular
        return fails, rough & ~fails

    return turn_assembly(status)


def _where_it_assembles(asm: Assembly) -> tuple[list, str | None]:
    """For an assembly error: the crank angles where the chain does assemble over a turn, and
    the ``[drive] range`` a user can paste to run over the widest regular part of them."""
    from linkgen.model.turn import drive_range_text

    turn = planar_turn(asm)
    best = turn.suggestion()
    return list(turn.assembles), drive_range_text(best) if best is not None else None


def slider_motion(poses: dict[str, LinkPose], g: GuideShape) -> Scalar:
    """Displacement s = r·u of the slider point along the guide from the guide's base point [m]
    and its transfer functions (Leibniz: s‴ = r‴·u + 3r″·u′ + 3r′·u″ + r·u‴)."""
    guide = poses[g.guide]
    base, u = guide.point(g.base), guide.direction(g.alpha)
    r = poses[g.slider].point(g.point) - base
    return Scalar(
        dot(r.p, u.p),
        dot(r.d1, u.p) + dot(r.p, u.d1),
        dot(r.d2, u.p) + 2.0 * dot(r.d1, u.d1) + dot(r.p, u.d2),
        dot(r.d3, u.p) + _dot3(r.d2, u.d1) + _dot3(r.d1, u.d2) + _dot(r.p, u.d3),
    )


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray | float:
    """a·b row by row; 0 where b is known to be zero (a guide fixed to ground)."""
    return 0.0 if is_zero(b) else dot(a, b)


def _dot3(a: np.ndarray, b: np.ndarray) -> np.ndarray | float:
    return 0.0 if is_zero(b) else 3.0 * dot(a, b)


__all__ = ["Kinematics", "Motion", "solve", "solve_motion", "slider_motion"]
