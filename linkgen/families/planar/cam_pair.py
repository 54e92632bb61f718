"""A cam on the crank driving a follower link of a linkage (``[cam.NAME]``, ``CamPair``).

The follower's pair with the ground makes it oscillating (a revolute at its pivot P) or
translating (a prismatic pair along the unit direction u). It moves from the sketch by
δ(θ) = q(θ) − q(0), q the pair's program and θ = φ − φ_s the crank's angle from the sketch:

    oscillating: the follower's angle is β_s + σ·δ, turning about P;
    translating: each of its points moves by σ·δ·u;

σ = ±1 is the sense in which the roller centre C moves away from the cam's axis O (rising),
taken from the sketch. The cam turns with the crank (counter-clockwise for ω > 0), so in the
cam's frame C traces the pitch curve R(−φ)·(C − O); its tangent, turned back to the world, is
C′ − J·(C − O) (J a quarter turn, ′ = d/dφ), and the contact force acts through C along the
pitch curve's outward normal n — the profile is the pitch curve moved inwards by the roller's
radius, so the common normal at the contact passes through C. The pressure angle is the angle
from the direction in which C rises to n (signed, counter-clockwise positive).
"""

from __future__ import annotations

import math

import numpy as np

from linkgen.errors import DescriptionError
from linkgen.families.planar.description import GROUND, CamPair, Mechanism
from linkgen.families.planar.geometry import GuideShape, LinkPose, LinkShape, pose_from_point
from linkgen.families.planar.primitives import Scalar, Vec, constant, zeros

# |σ-test| below this fraction of the size (squared for the oscillating test) leaves the sense of
# rising undefined: the roller's path at the sketch is tangent to the circle about the cam's axis.
SENSE_TOL = 1e-6


def ground_pair(mech: Mechanism, cam: CamPair):
    """The follower's one lower pair with the ground: ("R", Revolute) or ("P", Prismatic)."""
    pairs = [("R", r) for r in mech.revolutes if set(r.links) == {cam.follower, GROUND}]
    pairs += [("P", p) for p in mech.prismatics if {p.slider, p.guide} == {cam.follower, GROUND}]
    if len(pairs) != 1:
        raise DescriptionError(f"cam.{cam.name}.follower",
                               f"the follower {cam.follower!r} must have exactly one pair with the ground (a revolute "
                               f"at its pivot, or a prismatic pair), has {len(pairs)}")
    return pairs[0]


def oscillating(mech: Mechanism, cam: CamPair) -> bool:
    return ground_pair(mech, cam)[0] == "R"


def _direction(mech: Mechanism, shapes: dict[str, LinkShape], cam: CamPair) -> np.ndarray:
    """A translating follower's line direction u in the world (2,)."""
    pj = ground_pair(mech, cam)[1]
    a = pj.angle + shapes[pj.guide].sketch_angle
    return np.array([math.cos(a), math.sin(a)])


def sense(mech: Mechanism, shapes: dict[str, LinkShape], cam: CamPair) -> float:
    """σ = ±1: the sense of the follower's coordinate in which the roller leaves the cam's axis."""
    o = np.asarray(mech.points[mech.revolute(mech.drive.joint).point], dtype=float)
    c = np.asarray(mech.points[cam.roller], dtype=float)
    r = c - o
    size = float(np.hypot(*r))
    kind, pair = ground_pair(mech, cam)
    if kind == "R":
        arm = c - np.asarray(mech.points[pair.point], dtype=float)
        test = (r[0] * -arm[1] + r[1] * arm[0]) / max(size * float(np.hypot(*arm)), np.finfo(float).tiny)
    else:
        test = float(r @ _direction(mech, shapes, cam)) / max(size, np.finfo(float).tiny)
    if not abs(test) > SENSE_TOL:
        raise DescriptionError(f"points.{cam.roller}",
                               f"cam {cam.name!r}: at the sketch the roller centre moves square to the line from the "
                               f"cam's axis (cosine {test:.3g}), so rising cannot be told from falling; sketch the "
                               f"follower where its roller moves away from the cam's axis as it rises")
    return 1.0 if test > 0 else -1.0


def lift(cam: CamPair, theta: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """δ(θ) = q(θ) − q(0) and dδ/dθ, d²δ/dθ², d³δ/dθ³, each (n,) [rad or m]."""
    y = cam.program.displacement(theta)
    y0 = cam.program.displacement(np.zeros(1))[0][0]
    return y[0] - y0, y[1], y[2], y[3]


def above_lowest(cam: CamPair, theta: np.ndarray) -> np.ndarray:
    """q(θ) − q_lowest (n,) [rad or m]: what the spring's rate multiplies."""
    return cam.program.displacement(theta)[0] - cam.program.lowest


def follower_pose(mech: Mechanism, shapes: dict[str, LinkShape], cam: CamPair, phi: np.ndarray,
                  phi_s: float) -> LinkPose:
    """The follower's pose over crank angles ``phi`` (n,) [rad]; ``phi_s`` the crank's sketch angle."""
    n = phi.shape[0]
    sig = sense(mech, shapes, cam)
    d = lift(cam, phi - phi_s)
    f = shapes[cam.follower]
    kind, pair = ground_pair(mech, cam)
    if kind == "R":
        angle = Scalar(f.sketch_angle + sig * d[0], sig * d[1], sig * d[2], sig * d[3])
        return pose_from_point(constant(np.asarray(mech.points[pair.point], dtype=float), n), f.local[pair.point],
                               angle)
    u = _direction(mech, shapes, cam)
    c0 = np.asarray(mech.points[cam.roller], dtype=float)
    c = Vec(c0 + sig * d[0][:, None] * u, sig * d[1][:, None] * u, sig * d[2][:, None] * u, sig * d[3][:, None] * u)
    angle = Scalar(np.full(n, f.sketch_angle), zeros(n), zeros(n), zeros(n))
    return pose_from_point(c, f.local[cam.roller], angle)


def contact(kin, cam: CamPair) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """At the angles of ``kin``: the roller centre C (n, 2) [m], the unit outward normal n (n, 2)
    of the pitch curve (the contact force's line, through C) and the pressure angle (n,) [rad]."""
    c = kin.points[cam.roller]
    return (c.p, *contact_geometry(kin.assembly.mechanism, kin.assembly.shapes, cam, c))


def contact_geometry(mech: Mechanism, shapes: dict[str, LinkShape], cam: CamPair, c: Vec) -> tuple[np.ndarray, np.ndarray]:
    """The pitch curve's unit outward normal n (n, 2) and the pressure angle (n,) [rad] for the
    roller centre's positions and transfer functions ``c``: the angle from the direction u in
    which the roller rises to n, signed as u × n (counter-clockwise positive)."""
    o = np.asarray(mech.points[mech.revolute(mech.drive.joint).point], dtype=float)
    r = c.p - o
    t = c.d1 - np.stack([-r[:, 1], r[:, 0]], axis=1)  # C′ − J·(C − O): the pitch curve's tangent
    nrm = np.stack([t[:, 1], -t[:, 0]], axis=1)
    nrm /= np.hypot(*nrm.T)[:, None]
    nrm *= np.where(np.einsum("ij,ij->i", nrm, r) < 0, -1.0, 1.0)[:, None]
    sig = sense(mech, shapes, cam)
    kind, pair = ground_pair(mech, cam)
    if kind == "P":
        rise = np.broadcast_to(sig * _direction(mech, shapes, cam), r.shape)
    else:
        arm = c.p - np.asarray(mech.points[pair.point], dtype=float)
        rise = sig * np.stack([-arm[:, 1], arm[:, 0]], axis=1) / np.hypot(*arm.T)[:, None]
    alpha = np.arctan2(rise[:, 0] * nrm[:, 1] - rise[:, 1] * nrm[:, 0], np.einsum("ij,ij->i", nrm, rise))
    return nrm, alpha


def spring_load(kin, cam: CamPair) -> tuple[np.ndarray, np.ndarray]:
    """The spring's load on the follower: force (n, 2) [N] through C and moment (n,) [N·m] about
    P (oscillating: a torque against the rise; translating: a force along −σ·u)."""
    mech = kin.assembly.mechanism
    theta = kin.phi - kin.assembly.sketch_phi
    k = cam.spring_preload + cam.spring_rate * above_lowest(cam, theta)
    n = kin.phi.shape[0]
    sig = sense(mech, kin.assembly.shapes, cam)
    if oscillating(mech, cam):
        return np.zeros((n, 2)), -sig * k
    return -k[:, None] * sig * _direction(mech, kin.assembly.shapes, cam), np.zeros(n)


__all__ = ["SENSE_TOL", "above_lowest", "contact", "contact_geometry", "follower_pose", "ground_pair", "lift",
           "oscillating", "sense", "spring_load"]
