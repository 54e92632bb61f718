"""Link shapes (local coordinates), guide lines, poses and mass properties.

A link's local frame: origin at its first point, x axis towards its second (see
description.py). Ground's local frame is the world frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkgen.families.planar.description import GROUND, MassProperties, Mechanism
from linkgen.model.defaults import DEFAULT_BLOCK_INERTIA, DEFAULT_BLOCK_MASS, DEFAULT_DENSITY
from linkgen.families.planar.plate import plate_properties
from linkgen.families.planar.primitives import (
    Scalar,
    Vec,
    angle_between_points,
    constant,
    constant_along,
    is_zero,
    rotvec,
    zeros,
)


@dataclass(frozen=True)
class LinkShape:
    """Local coordinates [m] of a link's points, shape (2,) each, and its sketch placement."""

    name: str
    local: dict[str, np.ndarray]
    sketch_origin: np.ndarray
    sketch_angle: float

    def span(self) -> float:
        """Largest distance between two of the link's points [m] (0 for a one-point link)."""
        pts = list(self.local.values())
        return max((float(np.hypot(*(a - b))) for a in pts for b in pts), default=0.0)


@dataclass(frozen=True)
class GuideShape:
    """A prismatic pair in local terms.

    Attributes:
        base: a point of the guide line in the guide's frame [m], (2,).
        alpha: the line's direction in the guide's frame [rad].
        point: the slider's point in the slider's frame [m], (2,).
        relative_angle: slider angle minus guide angle, constant [rad].
    """

    name: str
    slider: str
    guide: str
    base: np.ndarray
    alpha: float
    point: np.ndarray
    relative_angle: float


@dataclass(frozen=True, slots=True)
class LinkPose:
    """A link's placement over φ: its angle and the points its group solved.

    ``known`` pairs local coordinates (2,) [m] with the solved point (Vec); any other point
    of the link follows by turning about the first of them. Points the group solved are
    returned as solved, with no second computation.
    """

    angle: Scalar
    known: tuple[tuple[np.ndarray, Vec], ...]

    @property
    def origin(self) -> Vec:
        """The link frame's origin: its first point."""
        return self.point(np.zeros(2))

    def point(self, local) -> Vec:
        local = np.asarray(local, dtype=float)
        for loc, vec in self.known:
            if loc[0] == local[0] and loc[1] == local[1]:
                return vec
        loc, vec = self.known[0]
        if constant_along(self.angle.v) and constant_along(vec.p) and all(map(is_zero, (vec.d1, vec.d2, vec.d3))):
            th = float(self.angle.v[0])  # a fixed link: one point, broadcast
            c, s = math.cos(th), math.sin(th)
            w = local - loc
            return constant(vec.p[0] + np.array([c * w[0] - s * w[1], s * w[0] + c * w[1]]), vec.p.shape[0])
        return vec + rotvec(self.angle, local - loc)

    def direction(self, alpha: float) -> Vec:
        return rotvec(self.angle, np.array([math.cos(alpha), math.sin(alpha)]))


def _wrapped(angle: Scalar) -> Scalar:
    """The angle reported in [-π, π) (floor is several times faster than np.mod)."""
    turns = np.floor(angle.v * (0.5 / np.pi) + 0.5)
    return Scalar(angle.v - (2.0 * np.pi) * turns, angle.d1, angle.d2, angle.d3, angle.cs)


def pose_from_point(p: Vec, local: np.ndarray, angle: Scalar) -> LinkPose:
    """The pose of a link whose point ``local`` is at ``p`` and whose angle is ``angle``."""
    return LinkPose(_wrapped(angle), ((np.asarray(local, dtype=float), p),))


def pose_from_two_points(p: Vec, p_local: np.ndarray, q: Vec, q_local: np.ndarray) -> LinkPose:
    """The pose of a link whose points ``p_local`` and ``q_local`` are at ``p`` and ``q``."""
    e = q_local - p_local
    angle = angle_between_points(p, q).shifted(-math.atan2(e[1], e[0]))
    return LinkPose(_wrapped(angle), ((p_local, p), (q_local, q)))


def ground_pose(n: int) -> LinkPose:
    zero = zeros(n)
    return LinkPose(Scalar(zero, zero, zero, zero), ((np.zeros(2), constant(np.zeros(2), n)),))


def link_shapes(mech: Mechanism) -> dict[str, LinkShape]:
    shapes = {}
    for link in mech.links:
        xy = {p: np.asarray(mech.points[p], dtype=float) for p in link.points}
        if link.name == GROUND:
            shapes[link.name] = LinkShape(link.name, xy, np.zeros(2), 0.0)
            continue
        p0 = xy[link.points[0]]
        if len(link.points) == 1:
            shapes[link.name] = LinkShape(link.name, {link.points[0]: np.zeros(2)}, p0, 0.0)
            continue
        e = xy[link.points[1]] - p0
        angle = math.atan2(e[1], e[0])
        if link.length is not None:
            local = {link.points[0]: np.zeros(2), link.points[1]: np.array([link.length, 0.0])}
        else:
            src = {p: np.asarray(v, dtype=float) for p, v in (link.shape or xy).items()}
            s0 = src[link.points[0]]
            es = src[link.points[1]] - s0
            a = math.atan2(es[1], es[0])
            c, s = math.cos(a), math.sin(a)
            local = {p: np.array([c * (src[p] - s0)[0] + s * (src[p] - s0)[1],
                                  -s * (src[p] - s0)[0] + c * (src[p] - s0)[1]]) for p in link.points}
        shapes[link.name] = LinkShape(link.name, local, p0, angle)
    return shapes


def guide_shapes(mech: Mechanism, shapes: dict[str, LinkShape]) -> dict[str, GuideShape]:
    out = {}
    for pj in mech.prismatics:
        g, s = shapes[pj.guide], shapes[pj.slider]
        normal = np.array([-math.sin(pj.angle), math.cos(pj.angle)])
        out[pj.name] = GuideShape(
            name=pj.name,
            slider=pj.slider,
            guide=pj.guide,
            base=g.local[pj.through] + pj.offset * normal,
            alpha=pj.angle,
            point=s.local[pj.point],
            relative_angle=s.sketch_angle - g.sketch_angle,
        )
    return out


def sketch_input(mech: Mechanism, shapes: dict[str, LinkShape]) -> float:
    """The drive's input in the sketch: the crank's angle [rad], or a prismatic drive's stroke s [m]
    (the slider's point along the guide line from its base point, as ``kinematics.slider_motion``)."""
    if not mech.slide_drive:
        return shapes[mech.crank].sketch_angle
    g = guide_shapes(mech, shapes)[mech.drive.joint]
    p = np.asarray(mech.points[mech.prismatic(mech.drive.joint).point], dtype=float)
    frame = shapes[g.guide]  # the guide's sketch frame: its first point, its sketch angle
    c, s = math.cos(frame.sketch_angle), math.sin(frame.sketch_angle)
    base = frame.sketch_origin + np.array([c * g.base[0] - s * g.base[1], s * g.base[0] + c * g.base[1]])
    return float(np.dot(p - base, [math.cos(frame.sketch_angle + g.alpha), math.sin(frame.sketch_angle + g.alpha)]))


def mass_properties(mech: Mechanism, shapes: dict[str, LinkShape], name: str) -> MassProperties | None:
    """Explicit mass properties, or those of a uniform bar from its density, or None."""
    link = mech.link(name)
    if link.inertial is not None:
        return link.inertial
    if link.areal_density is not None:
        return MassProperties(*plate_properties([shapes[name].local[p] for p in link.points], link.areal_density))
    if link.density is not None:
        a, b = (shapes[name].local[p] for p in link.points)
        length = float(np.hypot(*(b - a)))
        mass = link.density * length
        mid = 0.5 * (a + b)
        return MassProperties(mass=mass, com=(float(mid[0]), float(mid[1])), inertia=mass * length**2 / 12.0)
    return None




def effective_mass_properties(mech: Mechanism, shapes: dict[str, LinkShape], name: str) -> MassProperties:
    """The description's mass properties, or the stated defaults above."""
    found = mass_properties(mech, shapes, name)
    if found is not None:
        return found
    link = mech.link(name)
    if len(link.points) == 1:
        return MassProperties(DEFAULT_BLOCK_MASS, (0.0, 0.0), DEFAULT_BLOCK_INERTIA)
    a, b = (shapes[name].local[p] for p in link.points[:2])
    length = float(np.hypot(*(b - a)))
    mass = DEFAULT_DENSITY * length
    mid = 0.5 * (a + b)
    return MassProperties(mass, (float(mid[0]), float(mid[1])), mass * length**2 / 12.0)
