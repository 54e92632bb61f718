"""Kinetostatics of a spatial four-bar: the balancing torque on the crank and the reaction at
every pair, from Newton's and Euler's equations of the three moving links at the closed-form
motion (d'Alembert), with gravity and the description's ``[[force]]``/``[[torque]]`` loads
(``applied_loads``; a force acts only inside its stroke).

Each moving link is a uniform rod over its first two points (a small ball for a one-point
link; ``mass``), axisymmetric about its line, so a coupler's idle spin stays zero and carries
no load. Unknowns per pair: a revolute carries a force (3) and a moment square to its axis
(2); a spherical pair a force (3); a prismatic pair a force square to its line (2) and a moment
(3); a cylindrical pair a force and a moment square to its axis (2 + 2); the drive adds the
torque about its axis (a slider input: the force along its line). Eighteen equations (six per link) are solved for
them at every crank angle by least squares. RCCC has 18 unknowns, all determined. RSSR and RSSP
(PSSR, PSSP) have 17 unknowns and one identity (the
moment about the coupler's line): every reaction is determined. The 4R chains (spherical, planar,
Bennett) have 21 unknowns and rank 18: three components are statically indeterminate, and the
minimum-norm solution is given (``Forces.indeterminate`` = 3); the balancing torque is
determined all the same (it is fixed by the power balance).

``power_balance_torque`` is the same torque from the virtual work of every load alone, with no
reaction: T + Σ (F·c′ + M·Ω′) = 0 over the links, F and M the given plus d'Alembert loads at the
COM c, c′ = dc/dφ and Ω′ = Ω/ω — the planar ``Forces.power_balance_torque``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from linkgen.errors import BalanceError, DescriptionError, MagnitudeError, angle_ranges, format_ranges
from linkgen.model.names import GROUND
from linkgen.model.strokes import stroke_active
from linkgen.families.spatial.chain import Chain
from linkgen.families.spatial.description import SpatialMechanism
from linkgen.families.spatial.jets import Jet, rotate
from linkgen.families.spatial.mass import link_body
from linkgen.families.spatial.kinematics import SpatialMotion, solve

# A load's moment about the line of a coupler on two ball joints, over its scale (|F|·size or
# |T|), above which it is not rounding: nothing can balance it.
LINE_MOMENT_TOL = 1e-9
# The least-squares residual of the 18 equations over their scale (m·|a| + |g|·m summed over
# links) above which the equations are inconsistent: a few thousand roundings of float64.
RESIDUAL_TOL = 1e-9


@dataclass(frozen=True)
class Reaction:
    """The force [N] (n, 3) and moment [N·m] (n, 3) that link ``by`` exerts on link ``on`` at
    pair ``pair``'s point (world axes). The convention of every family (docs/format.md,
    "Conventions"): at a revolute or spherical pair ``on`` is the pair's first link and ``by`` its
    second, in the order of the ``[links.NAME]`` tables; at a prismatic pair ``on`` is the slider
    and ``by`` the guide."""

    pair: str
    on: str
    by: str
    force: np.ndarray
    moment: np.ndarray

    def force_on(self, link: str) -> np.ndarray:
        """The pair's force (n, 3) [N] on ``link``, either of its two links (the other's is its
        opposite)."""
        if link not in (self.on, self.by):
            raise ValueError(f"pair {self.pair} joins {self.on} and {self.by}, not {link}")
        return self.force if link == self.on else -self.force


@dataclass(frozen=True)
class SpatialForces:
    """Balancing torque (n,) [N·m] on the crank about its axis (for a prismatic input the
    balancing force [N] on the slider along its line), the same from the power balance
    (n,) [N·m or N], reactions by pair name, the number of statically indeterminate components (0:
    all determined)."""

    phi: np.ndarray
    balancing_torque: np.ndarray
    power_balance_torque: np.ndarray
    reactions: dict
    indeterminate: int

    def __repr__(self) -> str:
        return f"SpatialForces({self.phi.shape[0]} angles, {len(self.reactions)} pairs)"


def _square_basis(axis: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit vectors (n, 3) square to ``axis`` (n, 3) and to each other."""
    helper = np.where(np.abs(axis[:, :1]) < 0.9, np.array([[1.0, 0, 0]]), np.array([[0, 1.0, 0]]))
    e1 = np.cross(axis, helper)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    return e1, np.cross(axis, e1)


def _skew(r: np.ndarray) -> np.ndarray:
    """[r]× (n, 3, 3): [r]×·f = r × f."""
    z = np.zeros(r.shape[0])
    return np.stack([np.stack([z, -r[:, 2], r[:, 1]], -1), np.stack([r[:, 2], z, -r[:, 0]], -1),
                     np.stack([-r[:, 1], r[:, 0], z], -1)], 1)


def body_loads(mech: SpatialMechanism, motion: SpatialMotion, omega, epsilon) -> dict:
    """Per moving link: (mass [kg], COM position (n, 3), the d'Alembert force m·(a − g) (n, 3)
    [N] and moment about the COM I·α + Ω × I·Ω (n, 3) [N·m], COM velocity (n, 3), Ω (n, 3))."""
    chain = motion.chain
    w = np.asarray(omega, dtype=float).reshape(-1, 1) * np.ones((motion.phi.shape[0], 1))
    e = np.asarray(epsilon, dtype=float).reshape(-1, 1) * np.ones((motion.phi.shape[0], 1))
    g = np.array(mech.gravity)
    out = {}
    for link in (chain.crank, chain.coupler, chain.output):
        mass, c, inertia = link_body(mech, motion, link)
        vel = c.d[1] * w
        acc = c.d[2] * w**2 + c.d[1] * e
        w1, w2 = motion.spin[link]
        Om = w1 * w
        al = w2 * w**2 + w1 * e
        moment = np.einsum("nij,nj->ni", inertia, al) + np.cross(Om, np.einsum("nij,nj->ni", inertia, Om))
        out[link] = (mass, c.d[0], mass * (acc - g), moment, vel, Om)
    return out


def applied_loads(mech: SpatialMechanism, motion: SpatialMotion) -> dict:
    """The given loads per moving link other than gravity: (force (n, 3) [N], moment about the
    link's COM (n, 3) [N·m]) from the ``[[force]]`` entries (inside their strokes) and the
    ``[[torque]]`` entries; links without loads are left out."""
    n = motion.phi.shape[0]
    out: dict = {}
    for f in mech.forces:
        if f.link == GROUND:
            continue
        force, moment = out.setdefault(f.link, (np.zeros((n, 3)), np.zeros((n, 3))))
        vec = np.where(stroke_active(f, motion.phi)[:, None], np.asarray(f.force, dtype=float), 0.0)
        arm = motion.at(f.link, f.point).d[0] - link_body(mech, motion, f.link)[1].d[0]
        force += vec
        moment += np.cross(arm, vec)
    for t in mech.torques:
        if t.link != GROUND:
            out.setdefault(t.link, (np.zeros((n, 3)), np.zeros((n, 3))))[1][:] += np.asarray(t.torque, dtype=float)
    return out


def check_line_moments(mech: SpatialMechanism, motion: SpatialMotion) -> None:
    """A coupler on two ball joints (RSSR, RSSP) is held by forces through its line A–B only: a
    load with a moment about that line would spin it freely. Named by field and crank angles."""
    chain = motion.chain
    if chain.ua is not None or chain.ub is not None:
        return
    a = motion.points[chain.pair_a].d[0]
    u = motion.points[chain.pair_b].d[0] - a
    u /= np.linalg.norm(u, axis=1, keepdims=True)
    loads = [(f"force[{i}]", np.einsum("ij,ij->i", np.cross(motion.points[f.point].d[0] - a, f.force), u)
              * stroke_active(f, motion.phi), float(np.linalg.norm(f.force)) * chain.size)
             for i, f in enumerate(mech.forces) if f.link == chain.coupler]
    loads += [(f"torque[{i}]", u @ np.asarray(t.torque, dtype=float), float(np.linalg.norm(t.torque)))
              for i, t in enumerate(mech.torques) if t.link == chain.coupler]
    for field, moment, scale in loads:
        bad = np.abs(moment) > LINE_MOMENT_TOL * scale
        if bad.any():
            raise DescriptionError(
                field, f"has a moment about the line {chain.pair_a}–{chain.pair_b} of the coupler {chain.coupler!r} (up to "
                       f"{float(np.abs(moment).max()):.6g} N·m, at crank angles {format_ranges(angle_ranges(motion.phi, bad))}): "
                       "the coupler turns on two ball joints, which carry no moment about that line, so nothing balances "
                       "it and the coupler would spin freely; put a force's point on the line, or a torque square to it",
                mech.source)


def forces(mech: SpatialMechanism, phi, omega: float | None = None, epsilon: float | None = None,
           motion: SpatialMotion | None = None) -> SpatialForces:
    """Balancing torque and pair reactions at crank angles ``phi`` (n,) [rad], crank speed ω
    [rad/s] and acceleration ε [rad/s²] (default the drive's)."""
    motion = solve(mech, phi) if motion is None else motion
    chain = motion.chain
    phi = motion.phi
    n = phi.shape[0]
    w = mech.drive.omega if omega is None else omega
    eps = mech.drive.epsilon if epsilon is None else epsilon
    loads = body_loads(mech, motion, w, eps)
    check_line_moments(mech, motion)
    given = applied_loads(mech, motion)
    bodies = [chain.crank, chain.coupler, chain.output]
    row = {b: 6 * i for i, b in enumerate(bodies)}
    pts = motion.points
    ua = rotate(chain.ka, chain.ua, _angle(motion) - chain.phi_s).value if chain.ua is not None else None
    ub = None
    if chain.ub is not None:
        ub = rotate(chain.kb, chain.ub, motion.turn).value
    ka = np.broadcast_to(chain.ka, (n, 3))
    kb = np.broadcast_to(chain.kb, (n, 3))
    # pairs as (name, on, by, point (n,3), force basis [(n,3)...], moment basis [(n,3)...]); a
    # revolute or spherical pair acts on its first link by its second (description order), a
    # prismatic one on the slider by the guide (Reaction)
    eye = [np.broadcast_to(v, (n, 3)) for v in np.eye(3)]
    order = {j.name: j.links for j in mech.joints}
    if chain.input_slides:  # the input's prismatic pair: on the slider by the ground, as the output's
        first = (chain.drive, chain.crank, GROUND, pts[chain.drive_point].d[0], list(_square_basis(ka)), eye)
    else:
        first = (chain.drive, *order[chain.drive], pts[chain.drive].d[0], eye, list(_square_basis(ka)))
    # a cylindrical pair (RCCC) carries a force and a moment square to its axis, about a point of it
    cyl = chain.kind == "RCCC"
    pairs = [first,
             (chain.pair_a, *order[chain.pair_a], pts[chain.pair_a].d[0], list(_square_basis(ua)) if cyl else eye,
              list(_square_basis(ua)) if ua is not None else []),
             (chain.pair_b, *order[chain.pair_b], pts[chain.pair_b].d[0], list(_square_basis(ub)) if cyl else eye,
              list(_square_basis(ub)) if ub is not None else [])]
    if chain.output_slides:
        pairs.append((chain.pair_out, chain.output, GROUND, pts[chain.pair_b].d[0], list(_square_basis(kb)), eye))
    else:
        pairs.append((chain.pair_out, *order[chain.pair_out], pts[chain.pair_out].d[0],
                      list(_square_basis(kb)) if cyl else eye, list(_square_basis(kb))))
    columns, rhs = [], np.zeros((n, 18))
    com = {b: loads[b][1] for b in bodies}
    layout = []
    for name, on, by, point, fbasis, mbasis in pairs:
        start = len(columns)
        for f in fbasis:
            col = np.zeros((n, 18))
            for body, sign in ((on, 1.0), (by, -1.0)):
                if body in row:
                    col[:, row[body]:row[body] + 3] = sign * f
                    col[:, row[body] + 3:row[body] + 6] = sign * np.cross(point - com[body], f)
            columns.append(col)
        for m in mbasis:
            col = np.zeros((n, 18))
            for body, sign in ((on, 1.0), (by, -1.0)):
                if body in row:
                    col[:, row[body] + 3:row[body] + 6] = sign * m
            columns.append(col)
        layout.append((name, on, by, start, len(fbasis), len(mbasis), fbasis, mbasis))
    drive_col = np.zeros((n, 18))
    if chain.input_slides:  # the driving force along the line, at the slider's point
        drive_col[:, row[chain.crank]:row[chain.crank] + 3] = ka
        drive_col[:, row[chain.crank] + 3:row[chain.crank] + 6] = np.cross(pts[chain.drive_point].d[0] - com[chain.crank], ka)
    else:
        drive_col[:, row[chain.crank] + 3:row[chain.crank] + 6] = ka
    columns.append(drive_col)
    # The pair reactions balance the d'Alembert load less the given one; the power balance is the
    # virtual work of the given and d'Alembert loads with the crank turned by δφ.
    power = np.zeros(n)
    zero = (np.zeros((n, 3)), np.zeros((n, 3)))
    for b in bodies:
        gf, gm = given.get(b, zero)
        rhs[:, row[b]:row[b] + 3] = loads[b][2] - gf
        rhs[:, row[b] + 3:row[b] + 6] = loads[b][3] - gm
        c1, spin1 = link_body(mech, motion, b)[1].d[1], motion.spin[b][0]  # c′ [m/rad], Ω′ [1]
        power -= np.einsum("ij,ij->i", gf - loads[b][2], c1) + np.einsum("ij,ij->i", gm - loads[b][3], spin1)
    A = np.stack(columns, axis=-1)  # (n, 18, unknowns)
    inf = ~np.isfinite(A).all(axis=(1, 2)) | ~np.isfinite(rhs).all(axis=1)
    if inf.any():  # the loads or the geometry overflowed: named by angle, never a NaN handed on
        raise MagnitudeError("the spatial kinetostatics", angle_ranges(phi, inf))
    x = np.einsum("nij,nj->ni", np.linalg.pinv(A, rcond=1e-10), rhs)
    if not np.isfinite(x).all():
        raise MagnitudeError("the spatial kinetostatics", angle_ranges(phi, ~np.isfinite(x).all(axis=1)))
    scale = 1.0 + sum(np.abs(rhs[:, row[b]:row[b] + 6]).max() + np.abs(loads[b][2]).max() + np.abs(loads[b][3]).max()
                      for b in bodies)
    resid = np.abs(np.einsum("nij,nj->ni", A, x) - rhs).max(axis=1) / scale
    if (resid > RESIDUAL_TOL).any():
        bad = resid > RESIDUAL_TOL
        raise BalanceError(angle_ranges(phi, bad), float(resid.max()), RESIDUAL_TOL)
    rank = int(np.linalg.matrix_rank(A[0], tol=1e-9 * np.abs(A[0]).max()))
    reactions = {}
    for name, on, by, start, nf, nm, fbasis, mbasis in layout:
        f = sum(x[:, start + i:start + i + 1] * fbasis[i] for i in range(nf))
        m = sum((x[:, start + nf + i:start + nf + i + 1] * mbasis[i] for i in range(nm)), np.zeros((n, 3)))
        reactions[name] = Reaction(name, on, by, f, m)
    return SpatialForces(phi, x[:, -1], power, reactions, A.shape[2] - rank)


def _angle(motion: SpatialMotion) -> Jet:
    from linkgen.families.spatial.jets import variable
    return variable(motion.phi)


__all__ = ["Reaction", "SpatialForces", "applied_loads", "body_loads", "check_line_moments", "forces"]
