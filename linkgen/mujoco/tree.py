"""The MuJoCo model's names and tree: which pairs become joints of a spanning tree and which
close loops (``connect``), and the names of bodies, sites and sensors (see ``mjcf``)."""

from __future__ import annotations

import math
from dataclasses import dataclass

from linkgen.errors import StructureError
from linkgen.families.planar.description import GROUND, Mechanism
from linkgen.families.planar.geometry import effective_mass_properties, link_shapes
from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.structure import Pair, drive_pair, pairs_of

DRIVE_ACTUATOR = "drive:motor"
WORLD = "world"  # MuJoCo's name for the world body


def _mechanism(source) -> Mechanism:
    """The description of a Mechanism, an Assembly or a ``mujoco.posed.Posed``."""
    return source if isinstance(source, Mechanism) else source.mechanism


def body_name(link: str) -> str:
    """The MuJoCo body of a link: its own name; ground is the world body; a link named
    ``world`` is ``link:world``."""
    if link == GROUND:
        return WORLD
    return "link:world" if link == WORLD else link


def link_name(body: str) -> str:
    """The link of a MuJoCo body name (inverse of ``body_name``)."""
    if body == WORLD:
        return GROUND
    return WORLD if body == "link:world" else body


def site_name(source: Mechanism | Assembly, link: str, point: str) -> str:
    """A point's site: ``POINT`` on its first carrier, ``POINT:LINK`` on the others."""
    first = next(l.name for l in _mechanism(source).links if point in l.points)
    return point if first == link else f"{point}:{link}"


def sensor_name(source: Mechanism | Assembly, link: str, point: str) -> str:
    """The ``framepos`` sensor of a point's site on a link."""
    return f"pos:{site_name(source, link, point)}"


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


def grow_tree(links, ordered) -> tuple[tuple[tuple[str, str, Pair], ...], tuple[Pair, ...]]:
    """The spanning tree the pairs ``ordered`` make over ``links``, taken in that order (a pair
    that would close a loop is left out): ((parent, child, pair) breadth first from the ground,
    the pairs left out)."""
    root = {n: n for n in links}

    def find(n):
        while root[n] != n:
            root[n] = root[root[n]]
            n = root[n]
        return n

    edges, left = [], []
    for p in ordered:
        a, b = find(p.links[0]), find(p.links[1])
        if a == b:
            left.append(p)
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
    return tuple(tree), tuple(left)


def spanning_tree(source: Mechanism | Assembly) -> TreeInfo:
    """The drive pair first, then every prismatic, then revolutes (Kruskal) from the lightest
    pair up; the rest close loops.

    A connect is soft: it opens by (1 − d)·d·τ²·A·λ, A the inverse inertia its two bodies
    present (MuJoCo's diagonal approximation, dominated by the lighter body). Taking the pairs
    at light links into the tree first leaves the loops to be closed between heavy links, where
    A is small: with a 0.1 g block between 10 kg links, closing at the block's pin instead of
    between the heavy links multiplies A, and so the gap, by 1e5. Pairs are ranked by the
    lighter of their two links' masses (ground counts as infinitely heavy); ties keep the
    description's order."""
    mech = _mechanism(source)
    cached = mech.__dict__.get("_linkgen_spanning_tree")
    if cached is not None:
        return cached
    pairs = pairs_of(mech)
    drive = drive_pair(mech, pairs)
    shapes = link_shapes(mech)
    mass = {n: effective_mass_properties(mech, shapes, n).mass for n in mech.moving_links} | {GROUND: math.inf}
    revolutes = sorted((p for p in pairs if p.kind == "R" and p is not drive),
                       key=lambda p: min(mass[p.links[0]], mass[p.links[1]]))
    planet_pins = [p for p in revolutes if any(set(p.links) == {mech.crank, planet} and
                                               mech.revolute(p.name).point == mech.link(planet).points[0]
                                               for planet in mech.planets)]
    # a cam's follower hangs on the ground by its own pair: the spring acts on that joint
    followers = {c.follower for c in mech.cams}
    follower_pins = [p for p in pairs if GROUND in p.links and set(p.links) & followers]
    revolutes = [p for p in revolutes if p not in planet_pins and p not in follower_pins]
    # a driven cylinder hangs on the ground by its pivot and its rod on it, so that the slide joint's
    # q counts the stroke (the rod the child): its pivot joins the tree right after the drive
    cylinder = ([p for p in revolutes if set(p.links) == {GROUND, drive.links[1]}]
                if drive.kind == "P" and GROUND not in drive.links else [])
    revolutes = cylinder + [p for p in revolutes if p not in cylinder]
    # a planet hangs on the crank by its pin, so its gear coupling ties two joints of the tree
    ordered = ([drive] + planet_pins + follower_pins + [p for p in pairs if p.kind == "P" and p not in follower_pins and p is not drive]
               + revolutes)
    tree, closures = grow_tree(mech.link_names, ordered)
    for p in closures:
        if p.kind == "P":
            raise StructureError(f"prismatic pair {p.name!r} closes a loop of prismatic pairs; not supported")
    info = TreeInfo(tree, closures)
    mech.__dict__["_linkgen_spanning_tree"] = info  # the Mechanism is frozen: derived once
    return info
