"""Closed-form kinematics from the Assur groups, vectorised over crank angles.

``assemble`` fixes each group's assembly mode (m = ±1) from the sketch pose;
``solve`` returns positions and first/second transfer functions of every link, named
point and slider; ``Kinematics.motion`` turns them into velocities and accelerations
for a crank speed ω and acceleration ε (v = x′ω, a = x″ω² + x′ε).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .description import GROUND, Mechanism
from .errors import AssemblyError, DescriptionError, SingularityError, angle_ranges
from .geometry import (
    GuideShape,
    LinkPose,
    LinkShape,
    ground_pose,
    guide_shapes,
    link_shapes,
    pose_from_point,
    pose_from_two_points,
)
from .primitives import Line, Result, Scalar, Vec, circle_circle, dot, line_circle, line_line, pivot_line, rotvec, cross
from .structure import Group, GroupKind, Structure, analyze

# A group is flagged near-singular where its normalised transfer-function denominator
# (the sine or cosine of a transmission angle) is below this: 1e-3 rad from a dead centre,
# where transfer functions grow past ~1e3 times their typical size.
NEAR_SINGULAR = 1e-3
# The sketch must agree with the assembled pose to this fraction of the mechanism's size:
# loose enough for a sketch drawn to three digits, tight enough to catch a wrong branch or typo.
SKETCH_TOLERANCE = 0.02
_BRANCHED = (GroupKind.RRR, GroupKind.RRP, GroupKind.RPR)


@dataclass(frozen=True)
class Assembly:
    """A mechanism with its structure, shapes and each group's assembly mode."""

    mechanism: Mechanism
    structure: Structure
    shapes: dict[str, LinkShape]
    guides: dict[str, GuideShape]
    branches: tuple[int, ...]
    sketch_phi: float


@dataclass(frozen=True)
class Kinematics:
    """Positions and transfer functions over crank angles ``phi`` (n,) [rad].

    Attributes:
        links: pose of every link (origin (n, 2) [m], angle (n,) [rad], with d/dφ, d²/dφ²).
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

    def motion(self, omega, epsilon=0.0) -> "Motion":
        """Velocities and accelerations for crank speed ω [rad/s] and acceleration ε [rad/s²]
        (scalars or arrays of shape (n,))."""
        w = np.broadcast_to(np.asarray(omega, dtype=float), self.phi.shape)
        e = np.broadcast_to(np.asarray(epsilon, dtype=float), self.phi.shape)
        wc, ec = w[:, None], e[:, None]
        pts = {k: (v.p, v.d1 * wc, v.d2 * wc**2 + v.d1 * ec) for k, v in self.points.items()}
        lks = {k: (p.angle.v, p.angle.d1 * w, p.angle.d2 * w**2 + p.angle.d1 * e) for k, p in self.links.items()}
        sld = {k: (s.v, s.d1 * w, s.d2 * w**2 + s.d1 * e) for k, s in self.sliders.items()}
        return Motion(self.phi, w, e, pts, lks, sld)


@dataclass(frozen=True)
class Motion:
    """Time derivatives at crank speed ``omega`` and acceleration ``epsilon`` (each (n,)).

    ``points[name]`` = (position (n,2) [m], velocity [m/s], acceleration [m/s²]);
    ``links[name]`` = (angle (n,) [rad], angular velocity [rad/s], angular acceleration [rad/s²]);
    ``sliders[name]`` = (displacement [m], velocity [m/s], acceleration [m/s²]).
    """

    phi: np.ndarray
    omega: np.ndarray
    epsilon: np.ndarray
    points: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]
    links: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]
    sliders: dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]


def assemble(mech: Mechanism) -> Assembly:
    """Analyse the structure and take each group's assembly mode from the sketch pose.

    Raises:
        AssemblyError: a group cannot be assembled at the sketch's crank angle.
        DescriptionError: the assembled pose is far from the sketch on every branch.
    """
    structure = analyze(mech)
    shapes = link_shapes(mech)
    guides = guide_shapes(mech, shapes)
    crank = shapes[structure.crank]
    phi0 = np.array([crank.sketch_angle])
    poses = _input_poses(mech, structure, shapes, phi0)
    branches = []
    for group in structure.groups:
        best = None
        with np.errstate(invalid="ignore", divide="ignore"):
            trials = [(m, *_solve_group(group, m, poses, shapes, guides, mech))
                      for m in ((1, -1) if group.kind in _BRANCHED else (1,))]
        for m, p1, p2, res in trials:
            if res.fail[0]:
                continue
            err = _sketch_error(mech, shapes, {group.links[0]: p1, group.links[1]: p2})
            if best is None or err < best[0]:
                best = (err, m, p1, p2)
        if best is None:
            raise AssemblyError(
                group.label, [(float(phi0[0]), float(phi0[0]))], "the sketch pose cannot be assembled"
            )
        branches.append(best[1])
        poses[group.links[0]], poses[group.links[1]] = best[2], best[3]
    _check_sketch(mech, shapes, poses)
    return Assembly(mech, structure, shapes, guides, tuple(branches), float(phi0[0]))


def _sketch_error(mech: Mechanism, shapes: dict[str, LinkShape], poses: dict[str, LinkPose]) -> float:
    err = 0.0
    for name, pose in poses.items():
        for p, local in shapes[name].local.items():
            err += float(np.hypot(*(pose.point(local).p[0] - np.asarray(mech.points[p]))))
    return err


def _check_sketch(mech: Mechanism, shapes: dict[str, LinkShape], poses: dict[str, LinkPose]) -> None:
    xy = np.array(list(mech.points.values()))
    size = float(np.hypot(*(xy.max(axis=0) - xy.min(axis=0))))
    tol = SKETCH_TOLERANCE * size
    for link in mech.links:
        for p in link.points:
            got = poses[link.name].point(shapes[link.name].local[p]).p[0]
            want = np.asarray(mech.points[p])
            dev = float(np.hypot(*(got - want)))
            if dev > tol:
                raise DescriptionError(
                    f"points.{p}",
                    f"the sketch puts it at ({want[0]:.6g}, {want[1]:.6g}) m but link {link.name!r} assembles it at "
                    f"({got[0]:.6g}, {got[1]:.6g}) m on the nearest branch, {dev:.3g} m away (allowed {tol:.3g} m = "
                    f"{SKETCH_TOLERANCE:g} of the sketch's size); correct the sketch or the link lengths",
                )


def _input_poses(mech: Mechanism, structure: Structure, shapes: dict[str, LinkShape], phi: np.ndarray) -> dict:
    n = phi.shape[0]
    crank = shapes[structure.crank]
    pivot = shapes[GROUND].local[mech.revolute(mech.drive.joint).point]
    one, zero = np.ones(n), np.zeros(n)
    angle = Scalar(phi.copy(), one, zero)
    return {
        GROUND: ground_pose(n),
        structure.crank: pose_from_point(
            Vec(np.broadcast_to(pivot, (n, 2)).copy(), np.zeros((n, 2)), np.zeros((n, 2))),
            crank.local[mech.link(structure.crank).points[0]],
            angle,
        ),
    }


def solve(mech_or_assembly: Mechanism | Assembly, phi) -> Kinematics:
    """Closed-form positions and transfer functions at crank angles ``phi`` [rad], shape (n,).

    Raises:
        AssemblyError: some group cannot be assembled at some angles (names the ranges).
        SingularityError: a transfer-function denominator is exactly zero at some angles.
    """
    asm = mech_or_assembly if isinstance(mech_or_assembly, Assembly) else assemble(mech_or_assembly)
    mech = asm.mechanism
    phi = np.atleast_1d(np.asarray(phi, dtype=float))
    if phi.ndim != 1 or not np.all(np.isfinite(phi)):
        raise ValueError(f"phi must be a finite 1-D array of crank angles [rad], got shape {phi.shape}")
    with np.errstate(invalid="ignore", divide="ignore"):  # failures are reported below, by angle
        return _solve(asm, phi)


def _solve(asm: Assembly, phi: np.ndarray) -> Kinematics:
    mech = asm.mechanism
    poses = _input_poses(mech, asm.structure, asm.shapes, phi)
    near = {}
    for group, m in zip(asm.structure.groups, asm.branches):
        p1, p2, res = _solve_group(group, m, poses, asm.shapes, asm.guides, mech)
        if np.any(res.fail):
            raise AssemblyError(group.label, angle_ranges(phi, res.fail), _fail_reason(group))
        den = np.abs(res.denominator)
        if np.any(~(den > 0.0)):
            raise SingularityError(group.label, angle_ranges(phi, ~(den > 0.0)))
        near[group.label] = den < NEAR_SINGULAR
        poses[group.links[0]], poses[group.links[1]] = p1, p2
    points = {}
    for link in mech.links:
        for p in link.points:
            if p not in points:
                points[p] = poses[link.name].point(asm.shapes[link.name].local[p])
    sliders = {name: slider_motion(poses, g) for name, g in asm.guides.items()}
    kin = Kinematics(asm, phi, poses, points, sliders, near)
    _check_finite(kin)
    return kin


def _fail_reason(group: Group) -> str:
    return {
        GroupKind.RRR: "the two links cannot reach each other (the distance between the outer pivots "
                       "exceeds the sum or is below the difference of the link lengths)",
        GroupKind.RRP: "the link cannot reach the guide line",
        GroupKind.RPR: "the pivot is closer to the other pivot than the guide's offset",
    }.get(group.kind, "no intersection")


def _check_finite(kin: Kinematics) -> None:
    for name, v in kin.points.items():
        for arr in (v.p, v.d1, v.d2):
            if np.isfinite(arr.sum()):  # one pass; a NaN or inf anywhere makes the sum non-finite
                continue
            bad = ~np.all(np.isfinite(arr), axis=1)
            if np.any(bad):
                raise SingularityError(f"at point {name}", angle_ranges(kin.phi, bad))


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


# --- groups -------------------------------------------------------------------------

def _locked_angle(link: str, pair_name: str, known: LinkPose, guides: dict[str, GuideShape]) -> Scalar:
    """Angle of ``link`` locked by a prismatic pair to a link whose pose is known."""
    g = guides[pair_name]
    return known.angle.shifted(g.relative_angle if link == g.slider else -g.relative_angle)


def _line_of(link: str, local: np.ndarray, angle: Scalar, pair_name: str, other: LinkPose,
             guides: dict[str, GuideShape]) -> Line:
    """The line on which point ``local`` of ``link`` (angle known, position not) must lie,
    through the prismatic pair ``pair_name`` with the known link ``other``."""
    g = guides[pair_name]
    if link == g.slider:
        return Line(other.point(g.base) + rotvec(angle, local - g.point), other.direction(g.alpha))
    slider_point = other.point(g.point)
    u = rotvec(angle, np.array([math.cos(g.alpha), math.sin(g.alpha)]))
    return Line(slider_point + rotvec(angle, local - g.base), u)


def _solve_group(group: Group, m: int, poses: dict, shapes: dict[str, LinkShape],
                 guides: dict[str, GuideShape], mech: Mechanism) -> tuple[LinkPose, LinkPose, Result]:
    (l1, l2), (o1, inner, o2), (k1, k2) = group.links, group.pairs, group.known
    s1, s2 = shapes[l1], shapes[l2]

    def pin(pair, link):  # (local coords on link, world Vec from the known link)
        point = mech.revolute(pair.name).point
        known = pair.other(link)
        return shapes[link].local[point], poses[known].point(shapes[known].local[point])

    kind = group.kind
    if kind is GroupKind.RRR:
        a_l, a = pin(o1, l1)
        c_l, c = pin(o2, l2)
        b_name = mech.revolute(inner.name).point
        b1_l, b2_l = s1.local[b_name], s2.local[b_name]
        res = circle_circle(a, float(np.hypot(*(b1_l - a_l))), c, float(np.hypot(*(b2_l - c_l))), m)
        b = res.value
        return pose_from_two_points(a, a_l, b, b1_l), pose_from_two_points(b, b2_l, c, c_l), res
    if kind is GroupKind.RRP:
        a_l, a = pin(o1, l1)
        b_name = mech.revolute(inner.name).point
        b1_l, b2_l = s1.local[b_name], s2.local[b_name]
        th2 = _locked_angle(l2, o2.name, poses[k2], guides)
        line = _line_of(l2, b2_l, th2, o2.name, poses[k2], guides)
        res = line_circle(line, a, float(np.hypot(*(b1_l - a_l))), m)
        b = res.value
        return pose_from_two_points(a, a_l, b, b1_l), pose_from_point(b, b2_l, th2), res
    if kind is GroupKind.RPR:
        a_l, a = pin(o1, l1)
        c_l, c = pin(o2, l2)
        g = guides[inner.name]
        if g.guide == l1:
            pg_l, pg, ps_l, ps = a_l, a, c_l, c
        else:
            pg_l, pg, ps_l, ps = c_l, c, a_l, a
        ca, sa = math.cos(g.relative_angle), math.sin(g.relative_angle)
        rel = g.point - ps_l
        w = np.array([ca * rel[0] - sa * rel[1], sa * rel[0] + ca * rel[1]]) - (g.base - pg_l)
        k = -float(cross(np.array([math.cos(g.alpha), math.sin(g.alpha)]), w))
        res = pivot_line(ps, pg, k, m)
        th_g = res.value.shifted(-g.alpha)
        th_s = th_g.shifted(g.relative_angle)
        pose_g, pose_s = pose_from_point(pg, pg_l, th_g), pose_from_point(ps, ps_l, th_s)
        return (pose_g, pose_s, res) if g.guide == l1 else (pose_s, pose_g, res)
    if kind is GroupKind.PRP:
        b_name = mech.revolute(inner.name).point
        b1_l, b2_l = s1.local[b_name], s2.local[b_name]
        th1 = _locked_angle(l1, o1.name, poses[k1], guides)
        th2 = _locked_angle(l2, o2.name, poses[k2], guides)
        res = line_line(_line_of(l1, b1_l, th1, o1.name, poses[k1], guides),
                        _line_of(l2, b2_l, th2, o2.name, poses[k2], guides))
        b = res.value
        return pose_from_point(b, b1_l, th1), pose_from_point(b, b2_l, th2), res
    # RPP
    a_l, a = pin(o1, l1)
    th2 = _locked_angle(l2, o2.name, poses[k2], guides)
    g = guides[inner.name]
    th1 = th2.shifted(g.relative_angle if l1 == g.slider else -g.relative_angle)
    pose1 = pose_from_point(a, a_l, th1)
    origin = np.zeros(2)
    res = line_line(_line_of(l2, origin, th2, inner.name, pose1, guides),
                    _line_of(l2, origin, th2, o2.name, poses[k2], guides))
    return pose1, pose_from_point(res.value, origin, th2), res


__all__ = ["Assembly", "Kinematics", "Motion", "assemble", "solve", "slider_motion"]
