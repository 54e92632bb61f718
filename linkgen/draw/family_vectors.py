"""The vectors of ``draw.vectors`` for the other families, as the same ``Arrows``: a cam's follower
point B (the roller's centre, or the contact point on a flat face) with its velocity or
acceleration, the cam's point B₁ under it, and the contact force on the follower (the cam's
reaction at O the opposite); a spatial four-bar's moving points (3-D vectors) and the reaction in
each pair on its first link (``linkgen forces``'s convention). Spatial arrows are drawn in every
view of ``draw.spatial`` (``draw_spatial_arrows``)."""

from __future__ import annotations

import numpy as np

from linkgen.draw.vectors import Arrow, Arrows, check_vectors


def cam_arrows(cm, theta: float, what: str, parts: bool = False) -> Arrows:
    """The ``what`` arrows of the cam mechanism ``cm`` at cam angle θ [rad] (constant ω)."""
    from linkgen.families.cam.kinetics import state

    check_vectors(what)
    f, w = cm.follower, cm.omega
    th = np.array([float(theta)])
    c, c1, c2, _ = (x[0] for x in f.centre(th))
    if what == "forces":
        st = state(cm, th)
        n = f.normal(th)[0]
        contact = c - n * f.roller_radius if not f.flat else c
        force = float(st.contact_force[0]) * n
        return Arrows(what, float(theta), (Arrow("N on follower", "follower", contact, force, "reaction"),
                                           Arrow("R_O on cam", "cam", np.zeros(2), -force, "reaction")))
    if what == "velocity":
        return Arrows(what, float(theta), (Arrow("v_B", "follower", c, c1 * w, "velocity"),
                                           Arrow("v_B1", "cam", c, w * np.array([-c[1], c[0]]), "velocity")))
    a, v = c2 * w * w, c1 * w
    speed = float(np.linalg.norm(v))
    if parts and speed > 0.0:
        t = v / speed
        return Arrows(what, float(theta), (Arrow("a_B^t", "follower", c, float(a @ t) * t, "tangential"),
                                           Arrow("a_B^n", "follower", c, a - float(a @ t) * t, "normal")))
    return Arrows(what, float(theta), (Arrow("a_B", "follower", c, a, "acceleration"),))


def spatial_arrows(mech, phi: float, what: str, parts: bool = False) -> Arrows:
    """The ``what`` arrows (3-D) of the spatial four-bar ``mech`` at crank angle ``phi`` [rad]."""
    from linkgen.families.spatial.kinematics import assembled_chain, solve
    from linkgen.model.names import GROUND

    check_vectors(what)
    chain = assembled_chain(mech)
    mo = solve(mech, np.array([float(phi)]), chain)
    fixed = set(mech.link(GROUND).points)
    xyz = {p: j.d[0][0] for p, j in mo.points.items()}
    if what == "forces":
        from linkgen.families.spatial.results import forces

        res = forces(mech, float(phi))

        def where(pair, r):  # a pair named by its point, else (a slide) the moving link's point
            if pair in xyz:
                return xyz[pair]
            return xyz[mech.link(r.by if r.on == GROUND else r.on).points[0]]

        return Arrows(what, float(phi), tuple(Arrow(f"R_{k} on {r.on}", r.on, where(k, r), np.asarray(r.force, dtype=float),
                                                    "reaction") for k, r in res.reactions.items()))
    w, e = float(mech.drive.omega), float(getattr(mech.drive, "epsilon", 0.0))
    out = []
    for p, j in mo.points.items():
        if p in fixed:
            continue
        v, a = j.d[1][0] * w, j.d[2][0] * w * w + j.d[1][0] * e
        if what == "velocity":
            out.append(Arrow(f"v_{p}", "", xyz[p], v, "velocity"))
        elif parts and float(np.linalg.norm(v)) > 0.0:
            t = v / np.linalg.norm(v)
            out += [Arrow(f"a_{p}^t", "", xyz[p], float(a @ t) * t, "tangential"),
                    Arrow(f"a_{p}^n", "", xyz[p], a - float(a @ t) * t, "normal")]
        else:
            out.append(Arrow(f"a_{p}", "", xyz[p], a, "acceleration"))
    return Arrows(what, float(phi), tuple(out))


def draw_spatial_arrows(views, arrows: Arrows, span: float) -> float:
    """Draw ``arrows`` (3-D) in every view of ``draw.spatial`` to one scale; returns it [unit per m]."""
    from linkgen.draw.teaching import COLORS, LONGEST

    longest = max((float(np.linalg.norm(a.vector)) for a in arrows.arrows), default=0.0)
    mu = _round(longest / (LONGEST * 0.6 * span)) if longest > 0.0 else 1.0
    for a in arrows.arrows:
        d = a.vector / mu
        if float(np.linalg.norm(d)) == 0.0:
            continue
        tip = a.at + d
        side = np.cross(d, [0.0, 0.0, 1.0])
        if float(np.linalg.norm(side)) < 1e-9 * float(np.linalg.norm(d)):
            side = np.cross(d, [1.0, 0.0, 0.0])
        side = 0.08 * float(np.linalg.norm(d)) * side / float(np.linalg.norm(side))
        head = np.array([tip - 0.2 * d + side, tip, tip - 0.2 * d - side])
        for v in views:
            v.line(np.array([a.at, tip]), color=COLORS[a.kind], lw=1.8, zorder=9)
            v.line(head, color=COLORS[a.kind], lw=1.8, zorder=9)
            if not v.is3d:
                q = v.proj(tip)
                v.ax.text(q[0], q[1], a.label, fontsize=7, color=COLORS[a.kind], zorder=9)
    return mu


def _round(raw: float) -> float:
    import math

    k = math.floor(math.log10(raw))
    return next(m * 10.0 ** k for m in (1.0, 2.0, 5.0, 10.0) if m * 10.0 ** k >= raw)


__all__ = ["cam_arrows", "draw_spatial_arrows", "spatial_arrows"]
