"""Velocity and acceleration plans of a planar linkage at one crank angle, as a textbook builds them.

A plan puts every point's velocity (or acceleration) as a vector from one pole: the vertex named by
the point's lower-case letter (``a`` for A), every ground point at the pole. Each link is then
reached from a point already known: from the vertex of its reference point (a point it shares with
a link placed before it, or the pole) the relative vectors of the rigid body give its other points,

    v_Q = v_R + ω × RQ,       a_Q = a_R + (−ω² RQ) + ε × RQ   (normal, then tangential part),

and each prismatic pair reaches its slider's point P from the point of the guide under it (P₃ on
the guide link 3: the guide's own rigid motion at P), by the sliding velocity along the guide,

    v_P = v_P₃ + ṡ u,         a_P = a_P₃ + 2 ω_guide × ṡ u + s̈ u  (Coriolis, then sliding part).

Every chain is built from the relative formulas alone, from the closed form's link rates and slider
rates, and ends where the closed form puts the point's vector: ``VectorPlan.closure`` is how far
the ends miss, a fraction of the plan's size (≈ 1e-15 when the closed form is self-consistent)."""

from __future__ import annotations

import numpy as np

from linkgen.families.planar.description import GROUND, Mechanism
from linkgen.model.plans import KINDS, POLES, Chain, VectorPlan, check_kind, pole_name


def _cross(w: float, r: np.ndarray) -> np.ndarray:
    """ω ẑ × r for a planar vector r."""
    return w * np.array([-r[1], r[0]])


def link_order(asm) -> list[str]:
    """The moving links in the order their motion is known: the crank, each group's links in
    attachment order, then any link outside the groups (a gear's planet) in description order."""
    s = asm.structure
    order = [s.crank] + [name for g in s.groups for name in g.links]
    return order + [ln.name for ln in asm.mechanism.links if ln.name != GROUND and ln.name not in order]


def link_numbers(asm) -> dict[str, int]:
    """The structure formula's link numbers: ground 0, crank 1, each group's links."""
    s = asm.structure
    out = {GROUND: 0, s.crank: 1}
    for g in s.groups:
        out.update(dict(zip(g.links, g.numbers)))
    return out


def vector_plan(asm, phi: float, kind: str, omega: float | None = None, epsilon: float | None = None) -> VectorPlan:
    """The ``kind`` ("velocity" or "acceleration") plan of the assembled linkage ``asm`` at crank
    angle ``phi`` [rad] (ω, ε default to the drive's).

    Raises:
        ArgumentError: an unknown kind. AssemblyError, SingularityError: as ``kinematics.solve_motion``.
    """
    from linkgen.families.planar.kinematics import solve_motion
    from linkgen.families.planar.positions import positions

    check_kind(kind)
    mech: Mechanism = asm.mechanism
    w0 = mech.drive.omega if omega is None else float(omega)
    e0 = mech.drive.epsilon if epsilon is None else float(epsilon)
    mo = solve_motion(asm, [phi], w0, e0)
    pos = positions(mech, [phi])
    acc = kind == "acceleration"
    col = 2 if acc else 1
    pole = pole_name(kind, mech.points)  # not a point's vertex name
    fixed = set(mech.link(GROUND).points)
    xy = {p: np.asarray(v[0][0], dtype=float) for p, v in mo.points.items()}
    vec = {p: (np.zeros(2) if p in fixed else np.asarray(v[col][0], dtype=float)) for p, v in mo.points.items()}
    rate = {name: (float(v[1][0]), float(v[2][0])) for name, v in mo.links.items()}
    rate[GROUND] = (0.0, 0.0)
    numbers = link_numbers(asm)
    known: dict[str, tuple[str, ...]] = {p: (pole,) for p in fixed}  # point → vertex names of its chain
    chains: list[Chain] = []
    refs: dict[str, str] = {GROUND: mech.link(GROUND).points[0]} if mech.link(GROUND).points else {}

    def rigid(link: str, r_from: str, start: np.ndarray, r_to_xy: np.ndarray, to_name: str, names: tuple[str, ...],
              pts: list[np.ndarray], kinds: list[str]) -> None:
        w, e = rate[link]
        r = r_to_xy - xy[r_from]
        if acc:
            n = start + (-w * w) * r
            pts += [n, n + _cross(e, r)]
            names += (f"n_{to_name}{r_from.lower()}", to_name)
            kinds += ["normal", "tangential"]
        else:
            pts.append(start + _cross(w, r))
            names += (to_name,)
            kinds.append("relative")
        return names

    for link in link_order(asm):
        pts_of = mech.link(link).points
        ref = next((p for p in pts_of if p in known), None)
        if ref is None:  # no point shared with a placed link: its first point's vector from the pole
            ref = pts_of[0]
            chains.append(Chain(link, ref.lower(), (pole, ref.lower()), np.array([np.zeros(2), vec[ref]]), ("absolute",)))
        refs[link] = ref
        for q in pts_of:
            if q == ref:
                continue
            pts, kinds = [np.zeros(2), vec[ref]], ["absolute"]
            names = rigid(link, ref, vec[ref], xy[q], q.lower(), (pole, ref.lower()), pts, kinds)
            chains.append(Chain(link, q.lower(), names, np.array(pts), tuple(kinds)))
        for q in pts_of:
            known.setdefault(q, ())
    for i, pair in enumerate(mech.prismatics):
        g, p = pair.guide, pair.point
        if g not in refs:
            continue
        u = pos.guide_line(pair.name, 0)[1]
        s_v, s_a = (float(x[0]) for x in mo.sliders[pair.name][1:3])
        ref = refs[g]
        coincident = f"{p.lower()}{numbers.get(g, '')}" if g != GROUND else pole
        pts, kinds, names = [np.zeros(2)], [], (pole,)
        if g != GROUND:
            pts.append(vec[ref])
            kinds.append("absolute")
            names += (ref.lower(),)
            # the guide's point under P: its rigid motion, as for any point of the guide
            names = rigid(g, ref, vec[ref], xy[p], coincident, names, pts, kinds)
        w_g = rate[g][0]
        if acc:
            k = pts[-1] + 2.0 * _cross(w_g, s_v * u)
            pts += [k, k + s_a * u]
            names += (f"k_{p.lower()}", p.lower())
            kinds += ["coriolis", "sliding"]
        else:
            pts.append(pts[-1] + s_v * u)
            names += (p.lower(),)
            kinds.append("sliding")
        chains.append(Chain(pair.name, p.lower(), names, np.array(pts), tuple(kinds)))
    vertices = {pole: np.zeros(2)}
    vertices.update({p.lower(): v for p, v in vec.items()})  # ground points at the pole
    return VectorPlan(kind, float(phi), w0, e0, pole, vertices, tuple(chains),
                      tuple(sorted(fixed)))


__all__ = ["KINDS", "POLES", "link_numbers", "link_order", "vector_plan"]
