"""The velocity and acceleration plans of a spatial four-bar (``model.plans``), in 3-D: every
point's vector from the pole, and each link reached from a point already known by the rigid body's
relative vectors,

    v_Q = v_R + ω × RQ,       a_Q = a_R + ω × (ω × RQ) + α × RQ   (normal part, then tangential),

ω and α the link's angular velocity and acceleration from the closed form's spins; a sliding
output also from the pole along its line (v_B = ṡ k). A cylindrical pair's point parts between its
two links (RCCC: ``SpatialMotion.own``): the later link's copy P₂ = P₁ + s·u lies on the pair's
axis u (fixed in the first link, 1) at the pair's slide s, so a chain passes from one copy to the
other through the first link's point under P₂ and the slide,

    v_P₂ = v_P₁ + ω₁ × s·u + ṡ·u,    a_P₂ = a_P₁ + ω₁ × (ω₁ × s·u) + α₁ × s·u + 2·ω₁ × ṡ·u + s̈·u.
 The chains end at the closed form's point
velocities and accelerations; drawings show the plan's projections (``draw.polygons``)."""

from __future__ import annotations

import numpy as np

from linkgen.model.names import GROUND
from linkgen.model.plans import Chain, VectorPlan, check_kind, pole_name


def spatial_plan(mech, phi: float, kind: str) -> VectorPlan:
    """The ``kind`` ("velocity" or "acceleration") plan of the spatial four-bar ``mech`` at crank
    angle ``phi`` [rad], at the drive's ω and ε."""
    from linkgen.families.spatial.kinematics import assembled_chain, solve

    check_kind(kind)
    chain = assembled_chain(mech)
    mo = solve(mech, np.array([float(phi)]), chain)
    w, e = float(mech.drive.omega), float(getattr(mech.drive, "epsilon", 0.0))
    acc = kind == "acceleration"
    pole = pole_name(kind, mech.points)  # not a point's vertex name
    fixed = set(mech.link(GROUND).points)
    vec = {p: (np.zeros(3) if p in fixed else (j.d[2][0] * w * w + j.d[1][0] * e if acc else j.d[1][0] * w))
           for p, j in mo.points.items()}
    known = set(fixed)
    chains = []
    order = (GROUND, chain.crank, chain.coupler, chain.output)
    numbers = {link: i for i, link in enumerate(order)}
    firsts = {link: set(mech.link(link).points) for link in order}  # the points each link carries
    rates = {GROUND: (np.zeros(3), np.zeros(3))}
    for link in order[1:]:
        spin, spin_d = (np.asarray(s)[0] for s in mo.spin[link])
        rates[link] = (spin * w, spin_d * w * w + spin * e)
    for link in order[1:]:
        pts = mech.link(link).points
        om, al = rates[link]
        ref = next((p for p in pts if p in known), pts[0])
        for q in pts:
            if q == ref:
                continue
            path = _Path(pole, acc, [np.zeros(3), vec[ref]], (pole, ref.lower()), ["absolute"])
            at_ref, at_q = _pair(mo, chain, firsts, ref, link), _pair(mo, chain, firsts, q, link)
            frm = ref.lower()
            if at_ref and at_ref[1]:  # from the vertex (the first link's point) to this link's copy
                _part(path, mo, chain, numbers, *at_ref, rates, ref, link, w, e, +1.0)
                frm = f"{ref.lower()}{numbers[link]}"
            r = _at(mo, link, q) - _at(mo, link, ref)
            parts = bool(at_q and at_q[1])
            path.rigid(om, al, r, frm, f"{q.lower()}{numbers[link]}" if parts else q.lower())
            if parts:  # back from this link's copy to the vertex
                _part(path, mo, chain, numbers, *at_q, rates, q, link, w, e, -1.0)
            chains.append(Chain(link, q.lower(), path.names, np.array(path.pts), tuple(path.kinds)))
        known |= set(pts)
    if chain.output_slides:
        b = mech.link(chain.output).points[0]
        rate = mo.turn.d[2][0] * w * w + mo.turn.d[1][0] * e if acc else mo.turn.d[1][0] * w
        k = np.asarray(chain.kb, dtype=float)
        chains.append(Chain(chain.output, b.lower(), (pole, b.lower()), np.array([np.zeros(3), rate * k / np.linalg.norm(k)]),
                            ("sliding",)))
    vertices = {pole: np.zeros(3)}
    vertices.update({p.lower(): v for p, v in vec.items()})
    return VectorPlan(kind, float(phi), w, e, pole, vertices, tuple(chains), tuple(sorted(fixed)))


class _Path:
    """A chain being built: its vertices, their names and its edges' kinds."""

    def __init__(self, pole: str, acc: bool, pts: list, names: tuple, kinds: list):
        self.pole, self.acc, self.pts, self.names, self.kinds = pole, acc, pts, names, kinds

    def add(self, step: np.ndarray, name: str, kind: str) -> None:
        self.pts.append(self.pts[-1] + step)
        self.names += (name,)
        self.kinds.append(kind)

    def rigid(self, om: np.ndarray, al: np.ndarray, r: np.ndarray, frm: str, to: str, sign: float = 1.0) -> None:
        """The rigid body's relative vector of ``to`` from ``frm`` (``r`` between them)."""
        if self.acc:
            self.add(sign * np.cross(om, np.cross(om, r)), f"n_{to}{frm}", "normal")
            self.add(sign * np.cross(al, r), to, "tangential")
        else:
            self.add(sign * np.cross(om, r), to, "relative")


def _at(mo, link: str, p: str) -> np.ndarray:
    return mo.at(link, p).d[0][0]


def _pair(mo, chain, firsts: dict, p: str, link: str) -> tuple[str, str] | None:
    """(the first link carrying ``p``, the cylindrical pair) where ``link``'s copy of ``p`` parts
    from the first link's point; None where they are one point (a revolute, a spherical pair)."""
    if (link, p) not in mo.own:
        return None
    first = next(k for k in firsts if p in firsts[k])
    return first, {frozenset((chain.crank, chain.coupler)): chain.pair_a,
                   frozenset((chain.coupler, chain.output)): chain.pair_b,
                   frozenset((GROUND, chain.output)): chain.pair_out}.get(frozenset((first, link)))


def _part(path: _Path, mo, chain, numbers: dict, first: str, pair: str, rates: dict, p: str, link: str, w: float,
          e: float, sign: float) -> None:
    """Along the cylindrical pair ``pair`` at ``p`` between ``first`` and ``link``: from the
    first link's point to ``link``'s copy (``sign`` +1), or back (−1)."""
    axis = (mo.frames[chain.crank][0] @ chain.ua if pair == chain.pair_a else
            mo.frames[chain.output][0] @ chain.ub if pair == chain.pair_b else np.asarray(chain.kb, dtype=float))
    u = axis / np.linalg.norm(axis)
    s, s1, s2 = (float(mo.slides[pair].d[k][0]) for k in range(3))
    ds, dds = s1 * w, s2 * w * w + s1 * e
    om, al = rates[first]
    under = f"{p.lower()}{numbers[first]}'"  # the first link's point under the copy
    copy = f"{p.lower()}{numbers[link]}"
    if path.acc:
        steps = [(np.cross(om, np.cross(om, s * u)), f"n_{under}", "normal"), (np.cross(al, s * u), under, "tangential"),
                 (2.0 * np.cross(om, ds * u), f"k_{copy}", "coriolis"), (dds * u, copy, "sliding")]
    else:
        steps = [(np.cross(om, s * u), under, "relative"), (ds * u, copy, "sliding")]
    if first == GROUND:  # the ground's point under the copy stays at the pole: the slide alone
        steps = steps[-1:]
    if sign < 0:  # back: the same parts in reverse, ending at the first link's point
        names = [n for _, n, _ in steps][-2::-1] + [p.lower()]  # the same vertices, back to the first link's
        steps = [(-x, n, k) for (x, _, k), n in zip(steps[::-1], names)]
    for x, n, k in steps:
        path.add(x, n, k)


__all__ = ["spatial_plan"]
