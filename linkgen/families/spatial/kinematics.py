"""Closed-form positions and first, second and third transfer functions of a spatial four-bar.

Every kind closes its loop by one scalar equation in the crank angle φ and the output variable
q (the rocker's turn ψ from its sketch, or the slider's travel s along its line):

    F(φ, q) = |B(q) − A(φ)|² − L² = 0,

A(φ) the crank's pair point turned about the drive axis, B(q) the output's pair point turned
about its axis (or moved along its line), L the coupler's length. For RSSR and RSSP that is the
coupler itself; for the spherical chain A and B lie on the coupler's axes through the centre, so
their distance fixes the angle between the axes; for the planar and Bennett chains A and B are
the feet of the coupler's common normal, whose length is its link length. F is
P·cos ψ + Q·sin ψ = C for a turning output and a quadratic in s for a sliding one: q in closed
form, both roots, the branch taken from the sketch and kept. Derivatives by differentiating F
along φ three times (``jets``): F_q·q⁽ᵏ⁾ = −(the rest of F's k-th derivative), F_q = ∂F/∂q ≠ 0
away from dead centres. A Bennett linkage passes two poses where this F_q vanishes though the
linkage moves on (its four joints in line), so its q comes from Bennett's own closure,
tan(θ1/2)·tan(θ2/2) = K, regular over the whole turn (``_bennett_turn``).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import replace

import numpy as np

from linkgen.errors import AssemblyError, SingularityError, StructureError, angle_ranges
from linkgen.model.names import GROUND
from linkgen.families.spatial.chain import Chain, angle_about, build_chain, common_normal
from linkgen.families.spatial.description import SpatialMechanism
from linkgen.families.spatial.jets import Jet, constant, rotate, variable
from linkgen.families.spatial.motion import SpatialMotion

# The same rule as the planar groups (linkgen.families.planar.groups.SINGULAR_TOL): F_q normalised to
# [-1, 1] (2·L·r for a turning output, 2·L for a slider) below this is a dead centre, where the
# transfer functions lose more than ~eps/D² of their digits.
SINGULAR_TOL = 1e-4
# A point of a coupler held by two spherical pairs must lie on the line through them (else
# its position is not defined by the mechanism): to this fraction of the size.
ON_LINE_TOL = 1e-9
# A Bennett sketch must lie on Bennett's closure to this [rad]: a description written to 9
# significant digits (chain.GEOMETRY_TOL) is off by ~1e-9.
BENNETT_SKETCH_TOL = 1e-6


def _crank_a(chain: Chain, phi: Jet) -> Jet:
    if chain.input_slides:  # the input slider's point A moves with it along the line
        return constant(chain.A, phi.d.shape[1]) + phi * constant(chain.ka, phi.d.shape[1])
    return constant(chain.a0, phi.d.shape[1]) + rotate(chain.ka, chain.A - chain.a0, phi - chain.phi_s)


# Input values of a slider's range at which the chain is checked to assemble (the range's ends
# included): 0.05 % of the range apart.
RANGE_SAMPLES = 2001


def _check_range(chain: Chain, mech: SpatialMechanism) -> None:
    """A prismatic input's [drive] start..stop must lie where the coupler reaches the output:
    else a DescriptionError naming the range and the displacements where it does not."""
    s = np.linspace(*chain.input_range, RANGE_SAMPLES)
    fail = _roots(chain, _crank_a(chain, variable(s)).value)[2]
    if fail.any():
        from linkgen.errors import DescriptionError

        ok = s[~fail]
        where = (f"; it assembles only at {chain.input_text(angle_ranges(s, ~fail))} of it" if ok.size
                 else "; it assembles nowhere in it")
        raise DescriptionError("drive.stop" if fail[-1] else "drive.start",
                               f"the input range {chain.input_range[0]:.6g}..{chain.input_range[1]:.6g} m does not "
                               f"assemble: the coupler cannot reach the output at {chain.input_text(angle_ranges(s, fail))}"
                               f"{where}", mech.source)


def _output_b(chain: Chain, q: Jet) -> Jet:
    n = q.d.shape[1]
    if chain.output_slides:
        return constant(chain.B, n) + q * constant(chain.kb, n)
    return constant(chain.b0, n) + rotate(chain.kb, chain.B - chain.b0, q)


def _residual(chain: Chain, phi: Jet, q: Jet) -> Jet:
    e = _output_b(chain, q) - _crank_a(chain, phi)
    return e.dot(e) - chain.length**2


def _roots(chain: Chain, a: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Both roots q (n,) for crank points a (n, 3), the failure mask, and F_q's normaliser."""
    L = chain.length
    if chain.output_slides:
        w = chain.B - a
        uw = w @ chain.kb
        disc = uw**2 - (np.einsum("ij,ij->i", w, w) - L * L)
        fail = disc < 0
        r = np.sqrt(np.where(fail, 0.0, disc))
        return -uw + r, -uw - r, fail, np.full(a.shape[0], 2.0 * L)
    rb = chain.B - chain.b0
    along = chain.kb * float(chain.kb @ rb)
    e1 = rb - along
    e2 = np.cross(chain.kb, e1)
    r2 = float(e1 @ e1)
    d = chain.b0 + along - a
    P, Q = 2.0 * d @ e1, 2.0 * d @ e2
    C = L * L - np.einsum("ij,ij->i", d, d) - r2
    R = np.hypot(P, Q)
    fail = (np.abs(C) > R) | (R == 0)
    base = np.arctan2(Q, P)
    t = np.arccos(np.clip(np.where(R > 0, C / np.where(R > 0, R, 1.0), 0.0), -1.0, 1.0))
    return base + t, base - t, fail, np.full(a.shape[0], 2.0 * L * math.sqrt(r2))


def _bennett_error(chain: Chain, phi: np.ndarray, q: np.ndarray) -> np.ndarray:
    """How far a root is from keeping the coupler's twist and its normal square to both axes."""
    n = phi.shape[0]
    pj, qj = variable(phi), variable(q)
    a, b = _crank_a(chain, pj).value, _output_b(chain, qj).value
    ua = rotate(chain.ka, chain.ua, pj - chain.phi_s).value
    ub = rotate(chain.kb, chain.ub, qj).value if not chain.output_slides else np.broadcast_to(chain.ub, (n, 3))
    x = (b - a) / chain.length
    twist0 = float(chain.ua @ chain.ub)
    sense0 = float(np.cross(chain.ua, chain.ub) @ (chain.B - chain.A))
    sense = np.einsum("ij,ij->i", np.cross(ua, ub), x)
    return (np.abs(np.einsum("ij,ij->i", x, ua)) + np.abs(np.einsum("ij,ij->i", x, ub))
            + np.abs(np.einsum("ij,ij->i", ua, ub) - twist0) + (np.sign(sense) != np.sign(sense0)) * 1.0)


def _branch(chain: Chain) -> int:
    """+1 or −1: the root that puts the output nearest its sketch at the sketch's crank angle."""
    a = _crank_a(chain, variable(np.array([chain.phi_s]))).value
    q1, q2, fail, _ = _roots(chain, a)
    if fail[0]:
        raise AssemblyError(f"{chain.kind} [{chain.coupler}, {chain.output}]", [(chain.phi_s, chain.phi_s)],
                            "the sketch cannot be assembled: the coupler cannot reach the output")
    dist = [abs(math.remainder(q, 2 * math.pi)) if not chain.output_slides else abs(q) for q in (q1[0], q2[0])]
    return 1 if dist[0] <= dist[1] else -1


def assembled_chain(mech: SpatialMechanism) -> Chain:
    """The chain with its output placed exactly on the loop at the sketch's crank angle (the
    root nearest the described output point; for Bennett the one that keeps the coupler)."""
    chain = build_chain(mech)
    if chain.kind == "RCCC":  # the sketch lies on the loop by construction (families.spatial.rccc)
        return chain
    a = _crank_a(chain, variable(np.array([chain.phi_s]))).value
    q1, q2, fail, _ = _roots(chain, a)
    if fail[0]:
        raise AssemblyError(f"{chain.kind} [{chain.crank}, {chain.coupler}, {chain.output}]",
                            [(chain.phi_s, chain.phi_s)], "the sketch cannot be assembled: the coupler of length "
                            f"{chain.length:g} m cannot reach the output")
    if chain.kind == "Bennett":
        phi = np.array([chain.phi_s])
        qs = q1[0] if _bennett_error(chain, phi, q1)[0] <= _bennett_error(chain, phi, q2)[0] else q2[0]
    else:
        near = [abs(math.remainder(q, 2 * math.pi)) if not chain.output_slides else abs(q) for q in (q1[0], q2[0])]
        qs = q1[0] if near[0] <= near[1] else q2[0]
    qj = variable(np.array([qs]))
    b = _output_b(chain, qj).value[0]
    ub = chain.ub
    if ub is not None and not chain.output_slides:
        ub = rotate(chain.kb, ub, qj).value[0]
    chain = replace(chain, B=b, ub=ub)
    if chain.input_slides:
        _check_range(chain, mech)
    return chain


def solve(mech_or_chain: SpatialMechanism | Chain, phi, chain: Chain | None = None) -> SpatialMotion:
    """Positions and transfer functions of every point at crank angles ``phi`` (n,) [rad]
    (of the pair points only when given a Chain; ``chain``: the mechanism's, already assembled).

    Raises:
        AssemblyError: where the coupler cannot reach the output (the ranges named).
        SingularityError: at or near a dead centre (|normalised F_q| < SINGULAR_TOL).
    """
    mech = None if isinstance(mech_or_chain, Chain) else mech_or_chain
    if chain is None:
        chain = mech_or_chain if isinstance(mech_or_chain, Chain) else assembled_chain(mech_or_chain)
    phi = np.atleast_1d(np.asarray(phi, dtype=float)).reshape(-1)
    n = phi.shape[0]
    label = f"{chain.kind} [{chain.crank}, {chain.coupler}, {chain.output}]"
    pj = variable(phi)
    if chain.kind == "RCCC":
        from linkgen.families.spatial.rccc import solve_rccc

        return solve_rccc(chain, mech, phi, label)
    if chain.kind == "Bennett":  # Bennett's closed form: regular over the whole turn
        q, den = _bennett_turn(chain, pj)
        bad = ~(np.abs(den) >= SINGULAR_TOL)
        if bad.any():
            raise SingularityError(label, angle_ranges(phi, bad), "opposite twists nearly equal or opposite "
                                   f"(the closure's normalised denominator below {SINGULAR_TOL:g})")
        return _motion(chain, mech, phi, pj, q, den)
    a = _crank_a(chain, pj).value
    q1, q2, fail, scale = _roots(chain, a)
    if fail.any():
        raise chain.worded(AssemblyError(label, angle_ranges(phi, fail), "the coupler cannot reach the output (the "
                                         "distance it must span leaves the range the output's point can take)"),
                           "cannot be assembled")
    q0 = q1 if _branch(chain) > 0 else q2
    # implicit derivatives: F's k-th derivative is F_q·q⁽ᵏ⁾ + (terms in lower derivatives)
    fq = _residual(chain, variable(phi, (0.0, 0.0, 0.0)), variable(q0)).d[1]
    den = fq / scale
    bad = ~(np.abs(den) >= SINGULAR_TOL)
    if bad.any():
        raise chain.worded(SingularityError(label, angle_ranges(phi, bad), "a dead centre: the coupler is square to "
                                            f"the output's path (|F_q| normalised below {SINGULAR_TOL:g})"), "is singular")
    qd = [q0, np.zeros(n), np.zeros(n), np.zeros(n)]
    for k in (1, 2, 3):
        rk = _residual(chain, pj, variable(qd[0], tuple(qd[1:]))).d[k]
        qd[k] = -rk / fq
    q = Jet(np.stack(qd))
    return _motion(chain, mech, phi, pj, q, den)


def _bennett_turn(chain: Chain, pj: Jet) -> tuple[Jet, np.ndarray]:
    """The rocker's turn q of a Bennett linkage in closed form, and the closure's normalised
    denominator (n,).

    The distance equation |B − A| = L does not serve here: at the two poses where the four joint
    points lie on one line (the crank's and the ground's common normals parallel) its two roots
    meet and F_q = 0, though the linkage moves through them. Bennett's closure does: with the
    joint angles θ1 (from the ground's common normal to the crank's, about the drive axis) and θ4
    (from the rocker's normal to the ground's, about the output axis), and the axes oriented so
    that opposite twists are equal and a1·sin α2 = a2·sin α1 (turning an axis over adds π to its
    two twists and negates its joint angle), θ4 = −θ2 with tan(θ1/2)·tan(θ2/2) = K =
    sin((α2 + α1)/2) / sin((α2 − α1)/2); θ2 = 2·atan2(K·cos(θ1/2), sin(θ1/2)) is smooth in θ1, and
    dθ2/dθ1 = −K / (sin²(θ1/2) + K²·cos²(θ1/2)), whose denominator over max(1, K²) is returned."""
    axes = [(chain.a0, chain.ka), (chain.A, chain.ua), (chain.B, chain.ub), (chain.b0, chain.kb)]
    links = [common_normal(*axes[i], *axes[(i + 1) % 4]) for i in range(4)]
    a = [l[0] for l in links]
    x = [(l[3] - l[2]) / l[0] for l in links]

    def turn(u, v, axis):  # the angle from u to v about axis
        return math.atan2(float(np.cross(u, v) @ axis), float(u @ v))

    th1, th4 = turn(x[3], x[0], chain.ka), turn(x[2], x[3], chain.kb)
    best = (math.inf, (), ())
    for flips in itertools.product((0, 1), repeat=3):  # turn over axes 2..4, the drive's kept
        f = (0, *flips)
        al = [links[i][1] + math.pi * (f[i] + f[(i + 1) % 4]) for i in range(4)]
        err = (abs(math.remainder(al[2] - al[0], 2 * math.pi)) + abs(math.remainder(al[3] - al[1], 2 * math.pi))
               + abs(a[0] * math.sin(al[1]) - a[1] * math.sin(al[0])) / max(a))
        if err < best[0]:
            best = (err, al, f)
    _, al, f = best
    k = math.sin((al[1] + al[0]) / 2) / math.sin((al[1] - al[0]) / 2)
    s4 = -1.0 if f[3] else 1.0
    u = (pj + (th1 - chain.phi_s)) * 0.5
    c, s = u.cos(), u.sin()
    th2 = 2.0 * np.arctan2(k * c.value, s.value)
    q_s = math.remainder(th4 + s4 * 2.0 * math.atan2(k * math.cos(th1 / 2), math.sin(th1 / 2)), 2 * math.pi)
    if abs(q_s) > BENNETT_SKETCH_TOL:
        raise StructureError(f"Bennett [{chain.crank}, {chain.coupler}, {chain.output}]: the sketch is {q_s:.3g} rad "
                             "off Bennett's closure tan(θ1/2)·tan(θ2/2) = K")
    den = s * s + c * c * (k * k)
    rate = den.reciprocal() * (-k * s4)  # dq/dφ = s4·dθ2/dφ and its derivatives
    q0 = np.remainder(th4 + s4 * th2 + math.pi, 2 * math.pi) - math.pi
    return Jet(np.stack([q0, rate.d[0], rate.d[1], rate.d[2]])), den.value / max(1.0, k * k)


def _frames_of(chain: Chain, pj: Jet, q: Jet, points: dict) -> tuple[dict, dict, dict]:
    """Orientation jets (three column Jets) of the moving links, their spins, and frames."""
    n = pj.d.shape[1]
    cols = {}
    eye = np.eye(3)
    if chain.input_slides:  # the input slider translates
        cols[chain.crank] = [constant(eye[i], n) for i in range(3)]
    else:
        cols[chain.crank] = [rotate(chain.ka, eye[i], pj - chain.phi_s) for i in range(3)]
    if chain.output_slides:
        cols[chain.output] = [constant(eye[i], n) for i in range(3)]
    else:
        cols[chain.output] = [rotate(chain.kb, eye[i], q) for i in range(3)]
    a, b = points[chain.pair_a], points[chain.pair_b]
    x = (b - a).unit()
    spin = {}
    if chain.ua is not None:  # a coupler on two revolutes: its frame from A, B and A's axis
        ua = rotate(chain.ka, chain.ua, pj - chain.phi_s)
        y = ua.cross(x).unit()
        z = x.cross(y)
        xs, ys, zs = (c.value[0] for c in _sketch_frame(chain))
        sk = np.stack([xs, ys, zs], axis=1)  # sketch frame, columns
        # R_c = F(φ)·F_sᵀ: its columns are F(φ)·(row i of F_s)
        cols[chain.coupler] = [x * sk[i, 0] + y * sk[i, 1] + z * sk[i, 2] for i in range(3)]
    for link, c in cols.items():
        w1 = 0.5 * sum(np.cross(ci.d[0], ci.d[1]) for ci in c)
        w2 = 0.5 * sum(np.cross(ci.d[0], ci.d[2]) for ci in c)
        spin[link] = (w1, w2)
    if chain.ua is None:  # two spherical pairs: the rod turns without spin about its own line
        spin[chain.coupler] = (np.cross(x.d[0], x.d[1]), np.cross(x.d[0], x.d[2]))
        x0 = (chain.B - chain.A) / chain.length
        frames_c = np.stack([_min_rotation(x0, xi) for xi in x.d[0]])
    frames = {link: np.stack([ci.d[0] for ci in c], axis=-1) for link, c in cols.items()}
    if chain.ua is None:
        frames[chain.coupler] = frames_c
    return cols, spin, frames


def _sketch_frame(chain: Chain) -> list[Jet]:
    a = constant(chain.A, 1)
    b = constant(chain.B, 1)
    x = (b - a).unit()
    y = constant(chain.ua, 1).cross(x).unit()
    return [x, y, x.cross(y)]


def _min_rotation(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """The smallest rotation taking unit u to unit v (3, 3)."""
    c = float(u @ v)
    w = np.cross(u, v)
    s2 = float(w @ w)
    if s2 < 1e-30:
        if c > 0:
            return np.eye(3)
        p = np.cross(u, np.eye(3)[int(np.argmin(np.abs(u)))])
        p /= np.linalg.norm(p)
        return 2 * np.outer(p, p) - np.eye(3)
    k = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    return np.eye(3) + k + k @ k * ((1 - c) / s2)


def _motion(chain: Chain, mech: SpatialMechanism | None, phi: np.ndarray, pj: Jet, q: Jet, den: np.ndarray) -> SpatialMotion:
    n = phi.shape[0]
    pts = {chain.pair_a: _crank_a(chain, pj), chain.pair_b: _output_b(chain, q)}
    cols, spin, frames = _frames_of(chain, pj, q, pts)
    if mech is not None:
        for link in mech.links:
            for p in link.points:
                if p in pts:
                    continue
                if link.name == GROUND:
                    pts[p] = constant(mech.point(p), n)
                    continue
                pts[p] = _carried(chain, mech, link.name, p, cols, pts)
    else:
        pts[chain.drive_point] = constant(chain.a0, n) if not chain.input_slides else _crank_a(chain, pj) + (
            chain.a0 - chain.A)
    if chain.output_slides:
        out = q
    else:
        r = chain.B - chain.b0
        out = q + float(angle_about(chain.kb, r - chain.kb * (chain.kb @ r)))
    return SpatialMotion(chain, phi, pts, out, q, spin, frames, den)


def _carried(chain: Chain, mech: SpatialMechanism, link: str, p: str, cols: dict, pts: dict) -> Jet:
    """A further point of a moving link, carried rigidly with it."""
    x = mech.point(p)
    if link == chain.coupler and chain.ua is None:
        a, b = chain.A, chain.B
        t = float((x - a) @ (b - a)) / chain.length**2
        off = np.linalg.norm(x - a - t * (b - a))
        if off > ON_LINE_TOL * chain.size:
            from linkgen.errors import DescriptionError
            raise DescriptionError(f"links.{link}.points", f"point {p} is {off:.3g} m off the line {chain.pair_a}"
                                   f"{chain.pair_b}: a link between two spherical pairs spins freely about that line "
                                   "(an idle freedom), so only points on it have a defined position")
        return pts[chain.pair_a] + (pts[chain.pair_b] - pts[chain.pair_a]) * t
    if link == chain.crank:
        origin, base = pts[chain.pair_a], chain.A
    elif link == chain.output:
        origin, base = pts[chain.pair_b], chain.B
    else:
        origin, base = pts[chain.pair_a], chain.A
    r = x - base
    c = cols[link]
    return origin + c[0] * r[0] + c[1] * r[1] + c[2] * r[2]
