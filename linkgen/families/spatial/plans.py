"""The velocity and acceleration plans of a spatial four-bar (``model.plans``), in 3-D: every
point's vector from the pole, and each link reached from a point already known by the rigid body's
relative vectors,

    v_Q = v_R + ω × RQ,       a_Q = a_R + ω × (ω × RQ) + α × RQ   (normal part, then tangential),

ω and α the link's angular velocity and acceleration from the closed form's spins; a sliding
output also from the pole along its line (v_B = ṡ k). The chains end at the closed form's point
velocities and accelerations; drawings show the plan's projections (``draw.polygons``)."""

from __future__ import annotations

import numpy as np

from linkgen.model.names import GROUND
from linkgen.model.plans import POLES, Chain, VectorPlan, check_kind


def spatial_plan(mech, phi: float, kind: str) -> VectorPlan:
    """The ``kind`` ("velocity" or "acceleration") plan of the spatial four-bar ``mech`` at crank
    angle ``phi`` [rad], at the drive's ω and ε."""
    from linkgen.families.spatial.kinematics import assembled_chain, solve

    check_kind(kind)
    chain = assembled_chain(mech)
    mo = solve(mech, np.array([float(phi)]), chain)
    w, e = float(mech.drive.omega), float(getattr(mech.drive, "epsilon", 0.0))
    acc = kind == "acceleration"
    pole = POLES[kind]
    fixed = set(mech.link(GROUND).points)
    xyz = {p: j.d[0][0] for p, j in mo.points.items()}
    vec = {p: (np.zeros(3) if p in fixed else (j.d[2][0] * w * w + j.d[1][0] * e if acc else j.d[1][0] * w))
           for p, j in mo.points.items()}
    known = set(fixed)
    chains = []
    for link in (chain.crank, chain.coupler, chain.output):
        pts = mech.link(link).points
        spin, spin_d = (np.asarray(s)[0] for s in mo.spin[link])
        om, al = spin * w, spin_d * w * w + spin * e
        ref = next((p for p in pts if p in known), pts[0])
        for q in pts:
            if q == ref:
                continue
            r = xyz[q] - xyz[ref]
            start = vec[ref]
            if acc:
                n = start + np.cross(om, np.cross(om, r))
                xy = np.array([np.zeros(3), start, n, n + np.cross(al, r)])
                names, kinds = (pole, ref.lower(), f"n_{q.lower()}{ref.lower()}", q.lower()), ("absolute", "normal", "tangential")
            else:
                xy = np.array([np.zeros(3), start, start + np.cross(om, r)])
                names, kinds = (pole, ref.lower(), q.lower()), ("absolute", "relative")
            chains.append(Chain(link, q.lower(), names, xy, kinds))
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


__all__ = ["spatial_plan"]
