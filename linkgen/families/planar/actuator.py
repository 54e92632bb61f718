"""The ACTUATOR group (``structure``) solved in closed form: a hydraulic cylinder pivoted on the
ground, its rod pinned to a rocker pivoted on the ground, driven by the stroke s of the pair
between them — a triangle pivot–pin–rocker pivot whose first side changes with s. Vectorised over
strokes, with transfer functions d/ds, d²/ds², d³/ds³ as ``primitives``' are along φ."""

from __future__ import annotations

import math

import numpy as np

from linkgen.families.planar.description import Mechanism
from linkgen.families.planar.geometry import GuideShape, LinkPose, LinkShape, pose_from_point, pose_from_two_points
from linkgen.families.planar.primitives import (Result, Scalar, Vec, _cross, _dot, circle_circle, cross, dot, pair,
                                                zeros)
from linkgen.families.planar.structure import Group


def direction_of(e: Vec) -> Scalar:
    """Direction angle θ of a vector e whose length may change along the input [rad]: with
    N = e×e′ and D = e·e, θ′ = N/D, θ″ = (e×e″ − θ′D′)/D and
    θ‴ = (e′×e″ + e×e‴ − θ″D′ − θ′D″)/D − (e×e″ − θ′D′)D′/D², D′ = 2e·e′, D″ = 2(e′·e′ + e·e″)."""
    dd = dot(e.p, e.p)
    inv = 1.0 / dd
    d1 = 2.0 * dot(e.p, e.d1)
    d2 = 2.0 * (dot(e.d1, e.d1) + _dot(e.p, e.d2))
    t1 = cross(e.p, e.d1) * inv
    n2 = _cross(e.p, e.d2) - t1 * d1
    t2 = n2 * inv
    t3 = (_cross(e.d1, e.d2) + _cross(e.p, e.d3) - t2 * d1 - t1 * d2) * inv - n2 * d1 * inv * inv
    return Scalar(np.arctan2(e.p[:, 1], e.p[:, 0]), t1, t2, t3)


def length_of(e: Vec) -> Scalar:
    """|e| [m] and its transfer functions: L′ = e·e′/L, L″ = (e′·e′ + e·e″ − L′²)/L,
    L‴ = (3e′·e″ + e·e‴ − 3L′L″)/L."""
    length = np.sqrt(dot(e.p, e.p))
    inv = 1.0 / length
    l1 = dot(e.p, e.d1) * inv
    l2 = (dot(e.d1, e.d1) + _dot(e.p, e.d2) - l1 * l1) * inv
    l3 = (3.0 * _dot(e.d1, e.d2) + _dot(e.p, e.d3) - 3.0 * l1 * l2) * inv
    return Scalar(length, l1, l2, l3)


def solve_actuator(group: Group, m: int, poses: dict, shapes: dict[str, LinkShape], guides: dict[str, GuideShape],
              mech: Mechanism, stroke: np.ndarray) -> tuple[LinkPose, LinkPose, Result]:
    """The ACTUATOR (``structure``): the rod's pin B lies, in the cylinder's frame, at
    c0 + s·e(α) (the guide line's base plus the stroke along it, plus the pin's offset from the
    rod's sliding point turned by the rod's angle to the cylinder), so the pivot A and the pin
    are |B − A|(s) apart; B is on that circle about A and on the rocker's circle about its pivot
    C (``circle_circle`` with a side that changes with s). The cylinder's angle is the angle of
    A→B in the world less its angle in the cylinder's frame; the rod turns with the cylinder."""
    cyl, rocker = group.links
    rod = group.third
    a_pair, b_pair, c_pair = group.pairs
    g = guides[mech.drive.joint]
    a_name, b_name, c_name = (mech.revolute(p.name).point for p in (a_pair, b_pair, c_pair))
    a = poses[group.known[0]].point(shapes[group.known[0]].local[a_name])
    c = poses[group.known[1]].point(shapes[group.known[1]].local[c_name])
    a_l = shapes[cyl].local[a_name]
    cr, sr = math.cos(g.relative_angle), math.sin(g.relative_angle)
    w = shapes[rod].local[b_name] - g.point
    c0 = g.base + np.array([cr * w[0] - sr * w[1], sr * w[0] + cr * w[1]]) - a_l
    u = np.array([math.cos(g.alpha), math.sin(g.alpha)])
    n = stroke.shape[0]
    zero = zeros(n, 2)
    side = Vec(pair(c0[0] + stroke * u[0], c0[1] + stroke * u[1]), np.broadcast_to(u, (n, 2)), zero, zero)
    b_l, c_l = shapes[rocker].local[b_name], shapes[rocker].local[c_name]
    res = circle_circle(a, length_of(side), c, float(np.hypot(*(b_l - c_l))), m)
    b = res.value
    world, local = direction_of(b - a), direction_of(side)
    theta = Scalar(world.v - local.v, world.d1 - local.d1, world.d2 - local.d2, world.d3 - local.d3)
    pose_rod = pose_from_point(b, shapes[rod].local[b_name], theta.shifted(g.relative_angle))
    return (pose_from_point(a, a_l, theta), pose_from_two_points(b, b_l, c, c_l),
            Result(pose_rod, res.fail, res.denominator))


__all__ = ["direction_of", "length_of", "solve_actuator"]
