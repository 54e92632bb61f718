"""The vectors a teacher draws on a planar skeleton at one crank angle, as data: every moving
point's velocity or acceleration (with its tangential and normal parts, along and across the
velocity), and the forces — the given loads (with their crank-angle range), the reactions in
every pair, and for a free-body view of one Assur group the loads on its links with the inertia
forces (−m·a_S at the centre of mass), which balance the reactions its pairs take from the links
it hangs on. Drawing them is ``draw.teaching``."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkgen.families.planar.description import GROUND
from linkgen.errors import ArgumentError

VECTORS = ("velocity", "acceleration", "forces")
UNITS = {"velocity": "m/s", "acceleration": "m/s²", "forces": "N"}


@dataclass(frozen=True)
class Arrow:
    """One vector: ``label`` (what the drawing writes), drawn from ``at`` (2,) [m], ``vector`` (2,)
    [m/s, m/s² or N]; ``kind`` one of "velocity", "acceleration", "tangential", "normal", "load",
    "weight", "inertia", "reaction"; ``link`` the link it belongs to or acts on; ``active`` False
    for a load outside its crank-angle range (drawn pale, not counted)."""

    label: str
    link: str
    at: np.ndarray
    vector: np.ndarray
    kind: str
    active: bool = True


@dataclass(frozen=True)
class Arrows:
    """The vectors of one drawing: ``what`` one of VECTORS, their ``unit``, and for a free-body view
    the group's label and links (``group`` empty otherwise)."""

    what: str
    phi: float
    arrows: tuple[Arrow, ...]
    group: str = ""
    group_links: tuple[str, ...] = ()

    @property
    def unit(self) -> str:
        return UNITS[self.what]

    def resultant(self) -> np.ndarray:
        """The sum of the active arrows (2,): zero for a free-body view in equilibrium."""
        return np.sum([a.vector for a in self.arrows if a.active], axis=0) if self.arrows else np.zeros(2)


def motion_arrows(asm, phi: float, what: str, parts: bool = False) -> Arrows:
    """Every moving point's velocity or acceleration at crank angle ``phi`` [rad] (the drive's ω, ε);
    with ``parts`` the acceleration as its tangential part (along the velocity) and normal part."""
    from linkgen.families.planar.kinematics import solve_motion

    mech = asm.mechanism
    mo = solve_motion(asm, [phi], mech.drive.omega, mech.drive.epsilon)
    fixed = set(mech.link(GROUND).points)
    owner = {p: ln.name for ln in mech.links for p in ln.points if ln.name != GROUND}
    out = []
    for name, (xy, v, a) in mo.points.items():
        if name in fixed:
            continue
        at, v, a = xy[0], v[0], a[0]
        if what == "velocity":
            out.append(Arrow(f"v_{name}", owner.get(name, ""), at, v, "velocity"))
            continue
        speed = float(np.linalg.norm(v))
        if parts and speed > 0.0:
            t = v / speed
            out.append(Arrow(f"a_{name}^t", owner.get(name, ""), at, float(a @ t) * t, "tangential"))
            out.append(Arrow(f"a_{name}^n", owner.get(name, ""), at, a - float(a @ t) * t, "normal"))
        else:
            out.append(Arrow(f"a_{name}", owner.get(name, ""), at, a, "acceleration"))
    return Arrows(what, float(phi), tuple(out))


def find_group(asm, text: str):
    """The Assur group named by ``text``: its numbers ("2,3", "II(2,3)") or one of its links' names.

    Raises:
        ArgumentError: no such group, naming the groups there are.
    """
    groups = asm.structure.groups
    key = text.replace("II", "").strip("() ").replace(" ", "")
    for g in groups:
        if key == f"{g.numbers[0]},{g.numbers[1]}" or text in g.links:
            return g
    have = "; ".join(f"{g.numbers[0]},{g.numbers[1]} ({g.links[0]}, {g.links[1]})" for g in groups) or "none"
    raise ArgumentError(f"--free-body {text!r}: no such Assur group in {asm.mechanism.name}; its groups are {have} "
                        f"(give the numbers, e.g. 2,3, or a link's name)")


def _stroke_text(f) -> str:
    if f.stroke is None:
        return ""
    return f", φ ∈ {math.degrees(f.stroke[0]):.4g}°..{math.degrees(f.stroke[1]):.4g}°"


def _reaction_label(mech, r, on: str) -> str:
    """``R_A on crank``; where another pair at the same point also acts on ``on`` (two links
    pinned to the ground at A), the link it comes from too: ``R_A on ground from rocker_5``."""
    label = f"R_{r.point} on {on}"
    twins = [q for q in mech.revolutes if q is not r and q.point == r.point and on in q.links]
    return label + f" from {next(k for k in r.links if k != on)}" if twins else label


def force_arrows(asm, phi: float, group: str | None = None) -> Arrows:
    """The forces at crank angle ``phi`` [rad]: every given point force (with its range; pale when
    off), each link's weight, and every pair's reaction (on the pair's first link, as
    ``linkgen forces`` gives it). With ``group`` (``find_group``) only what acts on that group's
    links from outside it: the reactions of its outer pairs, its given loads (weights, point
    forces, springs) and its inertia forces, which sum to zero."""
    from linkgen.families.planar.kinematics import solve
    from linkgen.families.planar.kinetostatics import forces
    from linkgen.families.planar.loads import applied_loads, mass_table
    from linkgen.model.strokes import stroke_active

    mech = asm.mechanism
    w, e = mech.drive.omega, mech.drive.epsilon
    kin = solve(asm, [phi])
    f = forces(asm, [phi], w, e)
    pts = {k: v.p[0] for k, v in kin.points.items()}
    out: list[Arrow] = []
    if group is None:
        for pf in mech.forces:
            on = bool(stroke_active(pf, np.array([phi]))[0])
            out.append(Arrow(f"F ({pf.link}{_stroke_text(pf)})", pf.link, pts[pf.point],
                             np.asarray(pf.force, dtype=float), "load", on))
        g = np.asarray(mech.gravity, dtype=float)
        if float(np.linalg.norm(g)) > 0.0:
            for name, mp in mass_table(asm).items():
                if mp.mass > 0.0:
                    out.append(Arrow(f"G_{name}", name, kin.point(name, mp.com).p[0], mp.mass * g, "weight"))
        for r in mech.revolutes:
            if r.name in f.reactions:
                out.append(Arrow(_reaction_label(mech, r, f.on[r.name]), f.on[r.name], pts[r.point],
                                 f.reactions[r.name][0], "reaction"))
        for p in mech.prismatics:
            out.append(Arrow(f"N_{p.name} on {p.slider}", p.slider, pts[p.point], _normal(kin, asm, p, f), "reaction"))
        return Arrows("forces", float(phi), tuple(out))
    grp = find_group(asm, group)
    inside = set(grp.links)
    loads = applied_loads(asm, kin, omega=w)
    for name in grp.links:
        mp = mass_table(asm)[name]
        com = kin.point(name, mp.com)
        acc = com.d2[0] * w * w + com.d1[0] * e
        out.append(Arrow(f"given on {name}", name, com.p[0], loads[name].force[0], "load"))
        if mp.mass > 0.0:
            out.append(Arrow(f"Φ_{name} = −m·a_S", name, com.p[0], -mp.mass * acc, "inertia"))
    for r in mech.revolutes:
        a, b = r.links
        if (a in inside) == (b in inside) or r.name not in f.reactions:
            continue
        sign = 1.0 if a in inside else -1.0  # reactions[J] acts on the first link
        on = a if a in inside else b
        out.append(Arrow(_reaction_label(mech, r, on), on, pts[r.point], sign * f.reactions[r.name][0], "reaction"))
    for p in mech.prismatics:
        if (p.slider in inside) == (p.guide in inside):
            continue
        sign, on = (1.0, p.slider) if p.slider in inside else (-1.0, p.guide)
        vec = _normal(kin, asm, p, f)
        if p.name in f.friction:
            vec = vec + float(f.friction[p.name][0]) * _direction(kin, asm, p)
        out.append(Arrow(f"N_{p.name} on {on}", on, pts[p.point], sign * vec, "reaction"))
        if mech.slide_drive and p.name == mech.drive.joint:  # the drive's force along its guide: the balancing force
            drive = float(np.asarray(f.balancing_torque)[0]) * _direction(kin, asm, p)
            out.append(Arrow(f"F_{p.name} (the drive) on {on}", on, pts[p.point], sign * drive, "load"))
    label = f"II({grp.numbers[0]},{grp.numbers[1]}) {grp.kind.value}"
    return Arrows("forces", float(phi), tuple(out), label, tuple(grp.links))


def _direction(kin, asm, p) -> np.ndarray:
    th = float(kin.links[p.guide].angle.v[0]) + asm.guides[p.name].alpha if p.guide in kin.links \
        else asm.guides[p.name].alpha
    return np.array([math.cos(th), math.sin(th)])


def _normal(kin, asm, p, f) -> np.ndarray:
    """The guide's normal force on the slider (2,) [N]: along the guide line's left normal."""
    u = _direction(kin, asm, p)
    return float(f.normal_force[p.name][0]) * np.array([-u[1], u[0]])


def check_vectors(what: str) -> str:
    if what not in VECTORS:
        raise ArgumentError(f"--vectors: expected one of {', '.join(VECTORS)}, got {what!r}")
    return what


__all__ = ["Arrow", "Arrows", "UNITS", "VECTORS", "check_vectors", "find_group", "force_arrows", "motion_arrows"]
