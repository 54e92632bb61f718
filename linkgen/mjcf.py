"""MJCF writer: the validated description as a MuJoCo model with loop-closing constraints.

One body per moving link, its frame the link's local frame placed at the assembled sketch
pose (so every constraint holds at qpos0); hinge/slide joints along a spanning tree that
contains every prismatic pair; an equality ``connect`` for each loop-closing revolute.
Output is deterministic: fixed element order, one number format (``%.17g``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from lxml import etree

from .assembly import Assembly
from .description import GROUND
from .errors import StructureError
from .geometry import effective_mass_properties
from .kinematics import solve
from .mjoptions import Settings
from .structure import Pair, pairs_of

# Integration and constraint settings come from the mechanism (linkgen.mjsettings): the loop
# time constant from the predicted loop gap and the crank speed, the timestep from it, the
# rotor inertia (armature of the driven joint, which holds the crank speed) from J(φ). The
# crank is driven by that rotor started at ω, plus a motor torque armature·ε for a constant ε:
# a velocity servo would fight the constraints.

_BAR_RADIUS = 0.01  # m, visual only


def fmt(x: float) -> str:
    x = float(x)
    return "0" if x == 0.0 else repr(x)


def vec(*xs: float) -> str:
    return " ".join(fmt(x) for x in xs)


@dataclass(frozen=True)
class TreeInfo:
    """How the description maps onto the MJCF: tree pairs (parent, child, pair) and closures."""

    tree: tuple[tuple[str, str, Pair], ...]
    closures: tuple[Pair, ...]

    def parent_of(self, link: str) -> tuple[str, Pair]:
        for parent, child, pair in self.tree:
            if child == link:
                return parent, pair
        raise KeyError(link)


def spanning_tree(asm: Assembly) -> TreeInfo:
    """The drive pair first, then every prismatic, then revolutes (Kruskal); the rest close loops."""
    mech = asm.mechanism
    pairs = pairs_of(mech)
    drive = next(p for p in pairs if p.kind == "R" and p.name == mech.drive.joint)
    ordered = [drive] + [p for p in pairs if p.kind == "P"] + [p for p in pairs if p.kind == "R" and p is not drive]
    root = {n: n for n in mech.link_names}

    def find(n):
        while root[n] != n:
            root[n] = root[root[n]]
            n = root[n]
        return n

    edges, closures = [], []
    for p in ordered:
        a, b = find(p.links[0]), find(p.links[1])
        if a == b:
            if p.kind == "P":
                raise StructureError(f"prismatic pair {p.name!r} closes a loop of prismatic pairs; not supported")
            closures.append(p)
        else:
            root[a] = b
            edges.append(p)
    tree, seen, frontier = [], {GROUND}, [GROUND]
    while frontier:
        parent = frontier.pop(0)
        for p in edges:
            if parent in p.links and p.other(parent) not in seen:
                child = p.other(parent)
                tree.append((parent, child, p))
                seen.add(child)
                frontier.append(child)
    return TreeInfo(tuple(tree), tuple(closures))


def site_name(asm: Assembly, link: str, point: str) -> str:
    """A point's site is named after the point on its first carrier, ``POINT__LINK`` elsewhere."""
    first = next(l.name for l in asm.mechanism.links if point in l.points)
    return point if first == link else f"{point}__{link}"


def write_mjcf(asm: Assembly, settings: Settings | None = None) -> str:
    """The MJCF text of the assembled mechanism, with ``settings`` (default: derived from the
    mechanism and its drive, ``linkgen.mjsettings.settings_for``)."""
    if settings is None:
        from .mjsettings import settings_for

        settings = settings_for(asm)
    mech = asm.mechanism
    ref = solve(asm, np.array([asm.sketch_phi]))
    pose = {n: (ref.links[n].origin.p[0], float(ref.links[n].angle.v[0])) for n in mech.link_names}
    info = spanning_tree(asm)

    root = etree.Element("mujoco", model=mech.name)
    etree.SubElement(root, "compiler", angle="radian", inertiafromgeom="false", autolimits="true")
    etree.SubElement(root, "option", timestep=fmt(settings.timestep), integrator=settings.integrator,
                     solver="Newton", iterations=str(settings.iterations), tolerance=fmt(settings.tolerance),
                     gravity=vec(mech.gravity[0], mech.gravity[1], 0.0))
    default = etree.SubElement(root, "default")
    etree.SubElement(default, "geom", contype="0", conaffinity="0", group="0")
    visual = etree.SubElement(root, "visual")
    etree.SubElement(visual, "global", offwidth="1280", offheight="960")
    asset = etree.SubElement(root, "asset")
    for name, rgba in (("ground", "0.5 0.5 0.5 1"), ("crank", "0.85 0.3 0.2 1"), ("link", "0.25 0.45 0.8 1"),
                       ("slider", "0.3 0.7 0.35 1")):
        etree.SubElement(asset, "material", name=f"mat_{name}", rgba=rgba)

    world = etree.SubElement(root, "worldbody")
    etree.SubElement(world, "light", name="sun", pos="0 0 5", dir="0 0 -1", directional="true")
    _link_visuals(asm, world, GROUND, "mat_ground")
    bodies = {GROUND: world}
    for parent, child, pair in info.tree:
        (po, pa), (co, ca) = pose[parent], pose[child]
        c, s = math.cos(pa), math.sin(pa)
        d = co - po
        rel = (c * d[0] + s * d[1], -s * d[0] + c * d[1])
        half = 0.5 * (ca - pa)
        body = etree.SubElement(bodies[parent], "body", name=child, pos=vec(rel[0], rel[1], 0.0),
                                quat=vec(math.cos(half), 0.0, 0.0, math.sin(half)))
        mp = effective_mass_properties(mech, asm.shapes, child)
        inertia = max(mp.inertia, 1e-9)  # MuJoCo needs positive inertia; a translating body never uses it
        etree.SubElement(body, "inertial", pos=vec(mp.com[0], mp.com[1], 0.0), mass=fmt(mp.mass),
                         diaginertia=vec(inertia / 2, inertia / 2, inertia))
        if pair.kind == "R":
            point = mech.revolute(pair.name).point
            local = asm.shapes[child].local[point]
            attrs = dict(name=pair.name, type="hinge", pos=vec(local[0], local[1], 0.0), axis="0 0 1")
            if pair.name == mech.drive.joint:
                attrs["armature"] = fmt(settings.armature)
            etree.SubElement(body, "joint", **attrs)
        else:
            g = asm.guides[pair.name]
            direction = pose[g.guide][1] + g.alpha - ca
            etree.SubElement(body, "joint", name=pair.name, type="slide",
                             axis=vec(math.cos(direction), math.sin(direction), 0.0))
        material = "mat_crank" if child == mech.crank else (
            "mat_slider" if len(mech.link(child).points) == 1 else "mat_link")
        _link_visuals(asm, body, child, material)
        bodies[child] = body

    equality = etree.SubElement(root, "equality")
    for pair in info.closures:
        point = mech.revolute(pair.name).point
        a, b = pair.links
        local = asm.shapes[a].local[point]
        attrs = dict(name=pair.name, anchor=vec(local[0], local[1], 0.0), solref=settings.solref,
                     solimp=settings.solimp_text)
        if a == GROUND:  # body1 must be a body; swap so that world is body2
            a, b = b, a
            local = asm.shapes[a].local[point]
            attrs["anchor"] = vec(local[0], local[1], 0.0)
        etree.SubElement(equality, "connect", body1=a, **({"body2": b} if b != GROUND else {}), **attrs)
    actuator = etree.SubElement(root, "actuator")
    etree.SubElement(actuator, "motor", name="drive", joint=mech.drive.joint, gear="1")
    sensor = etree.SubElement(root, "sensor")
    for link in mech.links:
        for p in link.points:
            name = site_name(asm, link.name, p)
            etree.SubElement(sensor, "framepos", name=f"pos_{name}", objtype="site", objname=name)
    return etree.tostring(root, pretty_print=True, encoding="unicode")


def _link_visuals(asm: Assembly, body, link: str, material: str) -> None:
    mech = asm.mechanism
    shape = asm.shapes[link]
    pts = [shape.local[p] for p in mech.link(link).points]
    if link == GROUND:
        for p, xy in zip(mech.link(link).points, pts):
            etree.SubElement(body, "geom", name=f"pivot_{p}", type="cylinder", size="0.015 0.005",
                             pos=vec(xy[0], xy[1], -0.01), material=material)
    elif len(pts) == 1:
        etree.SubElement(body, "geom", name=f"{link}_block", type="box", size="0.03 0.018 0.012",
                         pos=vec(pts[0][0], pts[0][1], 0.0), material=material)
    else:
        for i, q in enumerate(pts[1:], start=1):
            etree.SubElement(body, "geom", name=f"{link}_bar{i}", type="capsule", size=fmt(_BAR_RADIUS),
                             fromto=vec(pts[0][0], pts[0][1], 0.0, q[0], q[1], 0.0), material=material)
    for pj in mech.prismatics:
        if pj.guide == link:
            g = asm.guides[pj.name]
            size = max(shape.span(), 0.1)
            etree.SubElement(body, "geom", name=f"{pj.name}_guide", type="box",
                             size=vec(size, 0.004, 0.004), pos=vec(g.base[0], g.base[1], -0.02),
                             euler=vec(0.0, 0.0, g.alpha), material="mat_ground")
    for p, xy in zip(mech.link(link).points, pts):
        etree.SubElement(body, "site", name=site_name(asm, link, p), pos=vec(xy[0], xy[1], 0.0), size="0.008")
