"""The class-II Assur groups solved in closed form, given the poses of the links they attach to.

Each group kind maps onto one primitive of ``primitives``: RRR on two circles, RRP on a circle
and a line, RPR on a line through a pivot at a fixed distance from another, PRP and RPP on
two lines. Functions are vectorised over crank angles; failures come back as masks.
"""

from __future__ import annotations

import math

import numpy as np

from linkgen.families.planar.description import GROUND, Mechanism
from linkgen.families.planar.geometry import (
    GuideShape,
    LinkPose,
    LinkShape,
    ground_pose,
    pose_from_point,
    pose_from_two_points,
)
from linkgen.families.planar.primitives import (
    Line,
    Result,
    Scalar,
    Vec,
    circle_circle,
    pair,
    constant,
    cross,
    line_circle,
    line_line,
    pivot_line,
    rotvec,
    zeros,
)
from linkgen.families.planar.actuator import solve_actuator
from linkgen.families.planar.cam_pair import follower_pose
from linkgen.families.planar.structure import Group, GroupKind, Structure

# The one rule for singular and near-singular poses. Each group divides by a normalised
# denominator D with |D| <= 1 (the sine or cosine of a transmission angle, or the sine of the
# angle between two guides; 0 at a dead centre), so transfer functions grow as 1/D. Near a
# dead centre the solved point itself comes out of a square root or arcsine whose argument is
# rounded to eps relative: the point is off by ~eps/D of the link size, and dividing by D once
# more gives the first transfer functions a relative error of ~eps/D² and the second ~3·eps/D²
# (and so every velocity, acceleration and load). At |D| >= 1e-4 that is <= 2.2e-8 and 6.6e-8:
# at least 7 correct significant digits (measured: 2.2e-8 and 6.5e-8 at D = 1.01e-4, see
# tests/test_kinematics.py), below the 1e-6 to which MuJoCo is compared. Below it a pose is
# singular.
SINGULAR_TOL = 1e-4


def input_poses(mech: Mechanism, structure: Structure, shapes: dict[str, LinkShape], phi: np.ndarray) -> dict:
    """Poses of the ground, the crank and the links a higher pair ties to it (gear planets, cam
    followers) at crank angles ``phi`` (n,) [rad]."""
    n = phi.shape[0]
    crank = shapes[structure.crank]
    if mech.slide_drive and GROUND not in structure.drive.links:  # an actuator: its group places its links
        return {GROUND: ground_pose(n)}
    if mech.slide_drive:
        return {GROUND: ground_pose(n), structure.crank: slider_pose(mech, shapes, phi)}
    pivot = shapes[GROUND].local[mech.revolute(mech.drive.joint).point]
    angle = Scalar(phi, np.broadcast_to(1.0, (n,)), zeros(n), zeros(n))  # dφ/dφ = 1, d²φ/dφ² = d³φ/dφ³ = 0
    poses = {
        GROUND: ground_pose(n),
        structure.crank: pose_from_point(constant(pivot, n), crank.local[mech.link(structure.crank).points[0]], angle),
    }
    for g in mech.gears:  # the planet turns k times the crank from the sketch: θ = θ0 + k·(φ − φ0)
        planet, centre = shapes[g.planet], mech.link(g.planet).points[0]
        k = g.ratio
        theta = Scalar(planet.sketch_angle + k * (phi - crank.sketch_angle), np.broadcast_to(k, (n,)),
                       zeros(n), zeros(n))
        poses[g.planet] = pose_from_point(poses[structure.crank].point(crank.local[centre]), planet.local[centre], theta)
    for cam in mech.cams:  # the follower moves by the cam's program from the sketch
        poses[cam.follower] = follower_pose(mech, shapes, cam, phi, crank.sketch_angle)
    return poses


def slider_pose(mech: Mechanism, shapes: dict[str, LinkShape], s: np.ndarray) -> LinkPose:
    """The pose of a prismatic drive's slider at strokes ``s`` (n,) [m]: its point at the guide's base
    point plus s along the fixed guide line (ds/ds = 1), its angle its sketch angle."""
    n = s.shape[0]
    pj = mech.prismatic(mech.drive.joint)
    slider = shapes[pj.slider]
    base = shapes[GROUND].local[pj.through] + pj.offset * np.array([-math.sin(pj.angle), math.cos(pj.angle)])
    u = np.array([math.cos(pj.angle), math.sin(pj.angle)])
    zero = zeros(n, 2)
    point = Vec(pair(base[0] + s * u[0], base[1] + s * u[1]), np.broadcast_to(u, (n, 2)), zero, zero)
    angle = Scalar(np.broadcast_to(slider.sketch_angle, (n,)), zeros(n), zeros(n), zeros(n))
    return pose_from_point(point, slider.local[pj.point], angle)


def fail_reason(group: Group) -> str:
    """Why a group of this kind cannot be assembled, in words."""
    return {
        GroupKind.RRR: "the two links cannot reach each other (the distance between the outer pivots "
                       "exceeds the sum or is below the difference of the link lengths)",
        GroupKind.RRP: "the link cannot reach the guide line",
        GroupKind.RPR: "the pivot is closer to the other pivot than the guide's offset",
        GroupKind.ACTUATOR: "the cylinder, at this stroke, and the rocker cannot reach each other (the distance between "
                            "their pivots exceeds the sum or is below the difference of the pivot-to-pin distances)",
    }.get(group.kind, "no intersection")


def place(group: Group, poses: dict, p1: LinkPose, p2: LinkPose, res: Result) -> None:
    """Put a solved group's poses (``solve_group``'s) into ``poses``; an ACTUATOR's rod too."""
    poses[group.links[0]], poses[group.links[1]] = p1, p2
    if group.kind is GroupKind.ACTUATOR:
        poses[group.third] = res.value


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


def solve_group(group: Group, m: int, poses: dict, shapes: dict[str, LinkShape],
                 guides: dict[str, GuideShape], mech: Mechanism, stroke: np.ndarray | None = None
                 ) -> tuple[LinkPose, LinkPose, Result]:
    """Poses of the group's two links given the poses of the links it attaches to, and the
    primitive's Result (failure mask and transfer-function denominator); ``place`` puts them.
    An ACTUATOR needs the drive's ``stroke`` (n,) [m]; its Result's value is the rod's pose."""
    (l1, l2), (o1, inner, o2), (k1, k2) = group.links, group.pairs, group.known
    if group.kind is GroupKind.ACTUATOR:
        return solve_actuator(group, m, poses, shapes, guides, mech, stroke)
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

