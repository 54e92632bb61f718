"""The RCCC spatial four-bar in closed form: a crank on a revolute A0 and three cylindrical pairs
(each turning about and sliding along its axis): A between the crank and the coupler, B between
the coupler and the output, B0 between the output and the ground.

The coupler is a rigid body carrying two lines, the axes L1 of A and L2 of B; two lines on one
body keep two invariants, the angle between them (the twist α) and their distance along the
common normal. The crank turns L1 about the drive axis (φ); the output turns L2 about B0's axis
k by θ and slides it along k by d. So

    twist:     F(φ, θ) = u1(φ)·u2(θ) − cos α = 0, i.e. P·cos θ + Q·sin θ = C,
    distance:  (p2(θ) + d·k − p1(φ))·(u1 × u2) = D,  D = (B − A)·(ua × ub) at the sketch,

u1, u2 the axes' directions, p1 (the crank's A) and p2 (the output's B at d = 0) points on them.
θ comes from the first in closed form (both roots, the sketch's branch kept; its derivatives by
differentiating F along φ, F_θ·θ⁽ᵏ⁾ = −(the rest), as the other kinds), then d from the second,
which is linear in d: d = (D − (p2 − p1)·n)/(k·n), n = u1 × u2, a quotient of jets. The coupler's
pose follows: its frame [u1, n/|n|, u1 × n/|n|] and the foot of the common normal on L1. These
two steps are the paper's implicit differentiation of F(X, Y, Q) = 0 taken one equation at a
time. Dead centres: the twist equation's F_θ, normalised by |ub × k|, or k·n/|n| (the output's
slide square to the common normal: d undetermined) below ``SINGULAR_TOL``.

A point of a cylindrical pair belongs to both links at the sketch and then parts: ``points``
gives each point as the first of its links in the order ground, crank, coupler, output carries
it (A the crank's, B the coupler's, B0 the ground's), ``own`` the later links' copies, and
``slides`` each cylindrical pair's slide (the second link's along the axis, from the sketch).
"""

from __future__ import annotations

import math

import numpy as np

from linkgen.errors import AssemblyError, SingularityError, angle_ranges
from linkgen.model.names import GROUND
from linkgen.families.spatial.chain import Chain, angle_about
from linkgen.families.spatial.jets import Jet, constant, rotate, variable
from linkgen.families.spatial.motion import SpatialMotion

# The normalised denominators below this are a dead centre (the other kinds' rule).
SINGULAR_TOL = 1e-4


def _axis1(chain: Chain, pj: Jet) -> Jet:
    return rotate(chain.ka, chain.ua, pj - chain.phi_s)


def _crank_a(chain: Chain, pj: Jet) -> Jet:
    return constant(chain.a0, pj.d.shape[1]) + rotate(chain.ka, chain.A - chain.a0, pj - chain.phi_s)


def _twist(chain: Chain, pj: Jet, q: Jet) -> Jet:
    return _axis1(chain, pj).dot(rotate(chain.kb, chain.ub, q)) - float(chain.ua @ chain.ub)


def _roots(chain: Chain, u1: np.ndarray):
    """Both roots θ (n,) of the twist equation for axes u1 (n, 3), the failure mask, |e1|."""
    k, ub = chain.kb, chain.ub
    along = k * float(k @ ub)
    e1 = ub - along
    e2 = np.cross(k, e1)
    P, Q = u1 @ e1, u1 @ e2
    C = float(chain.ua @ ub) - u1 @ along
    R = np.hypot(P, Q)
    fail = (np.abs(C) > R) | (R == 0)
    base = np.arctan2(Q, P)
    t = np.arccos(np.clip(np.where(R > 0, C / np.where(R > 0, R, 1.0), 0.0), -1.0, 1.0))
    return base + t, base - t, fail, float(np.linalg.norm(e1))


def branch(chain: Chain) -> int:
    """+1 or −1: the twist root nearest θ = 0 at the sketch."""
    u1 = _axis1(chain, variable(np.array([chain.phi_s]))).value
    q1, q2, _, _ = _roots(chain, u1)
    return 1 if abs(math.remainder(q1[0], 2 * math.pi)) <= abs(math.remainder(q2[0], 2 * math.pi)) else -1


def _frame(u1: Jet, u2: Jet) -> list[Jet]:
    x = u1.cross(u2).unit()
    return [u1, x, u1.cross(x)]


def solve_rccc(chain: Chain, mech, phi: np.ndarray, label: str) -> SpatialMotion:
    """The motion at crank angles ``phi`` (n,) (``mech`` None: of the pair points only); errors
    name the group ``label``."""
    n = phi.shape[0]
    pj = variable(phi)
    u1v = _axis1(chain, pj).value
    q1, q2, fail, e1 = _roots(chain, u1v)
    if fail.any():
        raise chain.worded(AssemblyError(label, angle_ranges(phi, fail), "the coupler's twist cannot be kept: the "
                                         "output's axis cannot turn to the angle the coupler keeps with the crank's"),
                           "cannot be assembled")
    q0 = q1 if branch(chain) > 0 else q2
    fq = _twist(chain, variable(phi, (0.0, 0.0, 0.0)), variable(q0)).d[1]
    qd = [q0, np.zeros(n), np.zeros(n), np.zeros(n)]
    for k in (1, 2, 3):
        qd[k] = -_twist(chain, pj, variable(qd[0], tuple(qd[1:]))).d[k] / fq
    q = Jet(np.stack(qd))
    u1, u2 = _axis1(chain, pj), rotate(chain.kb, chain.ub, q)
    nvec = u1.cross(u2)
    sin_a = math.sqrt(max(1.0 - float(chain.ua @ chain.ub) ** 2, 0.0))
    kn = nvec.dot(chain.kb)
    den = np.where(np.abs(fq / e1) <= np.abs(kn.value / sin_a), fq / e1, kn.value / sin_a)
    bad = ~(np.abs(den) >= SINGULAR_TOL)
    if bad.any():
        raise chain.worded(SingularityError(label, angle_ranges(phi, bad), "a dead centre: the output's axis turns "
                                            "square to the coupler's twist, or slides square to its common normal (a "
                                            f"normalised denominator below {SINGULAR_TOL:g})"), "is singular")
    p1 = _crank_a(chain, pj)
    p2 = constant(chain.b0, n) + rotate(chain.kb, chain.B - chain.b0, q)
    D = float((chain.B - chain.A) @ np.cross(chain.ua, chain.ub))
    d = ((p2 - p1).dot(nvec) * -1.0 + D) * kn.reciprocal()
    b_out = p2 + d * constant(chain.kb, n)  # the output's B
    # the coupler: its frame and the foot of the common normal on L1
    nn = nvec.dot(nvec)
    f1 = p1 + u1 * ((b_out - p1).cross(u2).dot(nvec) * nn.reciprocal())
    us, vs = constant(chain.ua, 1), constant(chain.ub, 1)
    sk = np.stack([c.value[0] for c in _frame(us, vs)], axis=1)
    ns = np.cross(chain.ua, chain.ub)
    f1s = chain.A + chain.ua * float(np.cross(chain.B - chain.A, chain.ub) @ ns / (ns @ ns))
    frame = _frame(u1, u2)
    eye = np.eye(3)
    cols = {chain.crank: [rotate(chain.ka, eye[i], pj - chain.phi_s) for i in range(3)],
            chain.coupler: [frame[0] * sk[i, 0] + frame[1] * sk[i, 1] + frame[2] * sk[i, 2] for i in range(3)],
            chain.output: [rotate(chain.kb, eye[i], q) for i in range(3)]}

    def carried(link: str, x: np.ndarray) -> Jet:
        c = cols[link]
        if link == chain.crank:
            origin, base = p1, chain.A
        elif link == chain.coupler:
            origin, base = f1, f1s
        else:
            origin, base = b_out, chain.B
        r = x - base
        return origin + c[0] * r[0] + c[1] * r[1] + c[2] * r[2]

    a_cpl, b_cpl = carried(chain.coupler, chain.A), carried(chain.coupler, chain.B)
    known = {(chain.crank, chain.pair_a): p1, (chain.coupler, chain.pair_a): a_cpl,
             (chain.coupler, chain.pair_b): b_cpl, (chain.output, chain.pair_b): b_out}
    slides = {chain.pair_a: (a_cpl - p1).dot(u1), chain.pair_b: (b_out - b_cpl).dot(u2), chain.pair_out: d}
    if mech is None:
        points = {chain.pair_a: p1, chain.pair_b: b_cpl, chain.drive_point: constant(chain.a0, n)}
        own = {(chain.coupler, chain.pair_a): a_cpl, (chain.output, chain.pair_b): b_out}
    else:
        points, own = {}, {}
        for name in (GROUND, chain.crank, chain.coupler, chain.output):  # a bare name: its first link's point
            for p in mech.link(name).points:
                x = constant(mech.point(p), n) if name == GROUND else known.get((name, p)) or carried(name, mech.point(p))
                if p in points:
                    own[(name, p)] = x
                else:
                    points[p] = x
    spin = {link: (0.5 * sum(np.cross(ci.d[0], ci.d[1]) for ci in c), 0.5 * sum(np.cross(ci.d[0], ci.d[2]) for ci in c))
            for link, c in cols.items()}  # Ω = ½·Σ cᵢ × ċᵢ over the frame's columns, and its derivative
    frames = {link: np.stack([ci.d[0] for ci in c], axis=-1) for link, c in cols.items()}
    r = chain.B - chain.b0
    out = q + float(angle_about(chain.kb, r - chain.kb * (chain.kb @ r)))  # the absolute angle, as RSSR's
    return SpatialMotion(chain, phi, points, out, q, spin, frames, den, own, slides)
