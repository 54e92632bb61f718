"""The mechanism description: frozen dataclasses, validated on construction.

The same objects come from a TOML file (``linkgen.load``) or are built in Python.
Every check names the field in TOML terms (``links.rod.points[1]``), the value and
what is allowed. Inside, SI units and radians.

Conventions:
    * The fixed link is the link named ``ground``; its points' coordinates are exact.
    * A point listed by two links is a revolute joint between them, named after the
      point. A point listed by k > 2 links is a compound hinge: k - 1 revolutes, those
      the Assur-group decomposition joins (see ``derive_revolutes``), each named
      ``POINT:FIRST-OTHER`` with its two links in description order.
    * A link's local frame has its origin at its first point and its x axis towards
      its second point; a one-point link's x axis is the world x axis in the sketch.
      ``length`` (two-point links) is the exact distance between the two points and
      ``shape`` gives exact coordinates of all of a link's points; otherwise the sketch
      coordinates define the link's shape.
    * A prismatic pair: the ``point`` of link ``slider`` moves along a line fixed to
      link ``guide``, through the guide's point ``through`` shifted by ``offset`` along
      the line's left normal, at ``angle`` to the guide's x axis. The two links keep
      their relative angle.
    * The drive is the revolute ``drive.joint`` between ground and the crank; the
      crank angle φ is the angle of the crank's x axis (its first point must be the
      pivot). Or the drive is a prismatic pair ``drive.joint`` (a linear actuator): the
      input is its stroke s [m] along the guide line from its base point, its speed
      [m/s] and acceleration [m/s²], and every ``phi``, ``omega``, ``epsilon`` of the
      results then holds s, ṡ, s̈. Between ground and a slider, the slider is the
      leading link ("crank" in the structure's terms); between a cylinder pivoted on
      the ground and its rod pinned to a rocker, the three form the first group
      (``structure``: the ACTUATOR), the cylinder standing for the crank.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from types import MappingProxyType
from typing import Mapping

from linkgen.families.planar.checks import validate
from linkgen.model.names import GROUND
from linkgen.families.planar.decompose import decompose
from linkgen.families.planar.friction import Friction
from linkgen.families.planar.springs import Spring, TorsionSpring



@dataclass(frozen=True)
class MassProperties:
    """Mass [kg], centre of mass in the link's local frame [m], inertia about it [kg·m²]."""

    mass: float
    com: tuple[float, float]
    inertia: float


@dataclass(frozen=True)
class Link:
    """A rigid link carrying named points.

    Attributes:
        length: exact distance between the two points of a two-point link [m], or None
            to take it from the sketch.
        inertial: explicit mass properties, or None.
        density: linear density of a uniform bar [kg/m] (two-point links), or None.
        shape: exact coordinates [m] of every point of the link in any rigid placement,
            or None to take the shape from the sketch (``length`` is the two-point shorthand).
        areal_density: a uniform plate over the convex hull of the link's points [kg/m²]
            (three points or more), or None.
    """

    name: str
    points: tuple[str, ...]
    length: float | None = None
    inertial: MassProperties | None = None
    density: float | None = None
    shape: Mapping[str, tuple[float, float]] | None = None
    areal_density: float | None = None


@dataclass(frozen=True)
class Prismatic:
    """A prismatic pair: ``slider``'s ``point`` moves on a line fixed to ``guide``."""

    name: str
    slider: str
    guide: str
    point: str
    through: str
    angle: float = 0.0
    offset: float = 0.0


@dataclass(frozen=True)
class Revolute:
    """A revolute pair at ``point`` between ``links[0]`` and ``links[1]`` (derived)."""

    name: str
    point: str
    links: tuple[str, str]


@dataclass(frozen=True)
class Drive:
    """The driven pair and its motion: a revolute's ω [rad/s], ε [rad/s²] and crank-angle range
    [rad], or a prismatic pair's speed [m/s], acceleration [m/s²] and stroke range [m]
    (``velocity``, ``acceleration``: the same numbers under the slide's names)."""

    joint: str
    omega: float
    epsilon: float = 0.0
    start: float = 0.0
    stop: float = 2.0 * math.pi

    @property
    def velocity(self) -> float:
        return self.omega

    @property
    def acceleration(self) -> float:
        return self.epsilon


@dataclass(frozen=True)
class PointForce:
    """External force [N] at a point of a link, world frame; optionally only while the
    crank angle is inside ``stroke`` = (from, to) [rad] (a process load)."""

    link: str
    point: str
    force: tuple[float, float]
    stroke: tuple[float, float] | None = None


@dataclass(frozen=True)
class LinkTorque:
    """External torque [N·m] about +z on a link."""

    link: str
    torque: float


@dataclass(frozen=True)
class Gear:
    """A gear pair: the gear on link ``planet``, its pitch circle centred on the planet's first
    point (a point of the crank, which carries it), meshing with a gear fixed to the ground and
    centred on the crank's pivot — ``kind`` "internal" (a ring gear) or "external" (a sun gear);
    ``module`` m [m], ``teeth`` = (z_fixed, z_planet), ``pressure_angle`` [rad].

    The planet's angle turns ``ratio`` = 1 − z_fixed/z_planet (internal) or 1 + z_fixed/z_planet
    (external) times the crank's; the centre distance is m·(z_fixed ∓ z_planet)/2."""

    name: str
    planet: str
    kind: str
    module: float
    teeth: tuple[int, int]
    pressure_angle: float = math.radians(20.0)

    @property
    def ratio(self) -> float:
        zf, zp = self.teeth
        return 1.0 - zf / zp if self.kind == "internal" else 1.0 + zf / zp

    @property
    def planet_radius(self) -> float:
        return 0.5 * self.module * self.teeth[1]

    @property
    def fixed_radius(self) -> float:
        return 0.5 * self.module * self.teeth[0]

    @property
    def centre_distance(self) -> float:
        return self.fixed_radius - self.planet_radius if self.kind == "internal" else \
            self.fixed_radius + self.planet_radius


@dataclass(frozen=True)
class CamPair:
    """A disc cam on the crank driving link ``follower`` through a roller (or knife edge, radius 0)
    centred on the follower's point ``roller``: a higher pair. The follower turns about its
    revolute with the ground (oscillating) or slides on its prismatic pair with the ground
    (translating) by q(θ) − q(0) from the sketch, q the ``program`` (``linkgen.families.cam.laws``: rad or
    m) and θ the crank's angle from the sketch, so the sketch shows the follower at θ = 0; the
    cam's profile follows by inversion. Rising moves the roller away from the cam's axis. A spring
    of ``spring_rate`` [N·m/rad or N/m] and ``spring_preload`` [N·m or N at the program's lowest
    position] holds the follower on the cam."""

    name: str
    follower: str
    roller: str
    program: object
    roller_radius: float = 0.0
    spring_rate: float = 0.0
    spring_preload: float = 0.0


@dataclass(frozen=True)
class Mechanism:
    """A validated planar mechanism. Raises DescriptionError on construction if invalid."""

    def __repr__(self) -> str:
        return f"Mechanism({self.name!r}, {len(self.links)} links, {len(self.points)} points)"


    name: str
    points: Mapping[str, tuple[float, float]]
    links: tuple[Link, ...]
    drive: Drive
    prismatics: tuple[Prismatic, ...] = ()
    gravity: tuple[float, float] = (0.0, 0.0)
    forces: tuple[PointForce, ...] = ()
    torques: tuple[LinkTorque, ...] = ()
    title: str = ""
    gears: tuple[Gear, ...] = ()
    cams: tuple[CamPair, ...] = ()
    springs: tuple[Spring, ...] = ()
    torsion_springs: tuple[TorsionSpring, ...] = ()
    frictions: tuple[Friction, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "points", MappingProxyType(dict(self.points)))
        object.__setattr__(self, "links", tuple(self.links))
        object.__setattr__(self, "prismatics", tuple(self.prismatics))
        object.__setattr__(self, "forces", tuple(self.forces))
        object.__setattr__(self, "torques", tuple(self.torques))
        object.__setattr__(self, "gears", tuple(self.gears))
        object.__setattr__(self, "cams", tuple(self.cams))
        object.__setattr__(self, "springs", tuple(self.springs))
        object.__setattr__(self, "torsion_springs", tuple(self.torsion_springs))
        object.__setattr__(self, "frictions", tuple(self.frictions))
        validate(self)

    def link(self, name: str) -> Link:
        """The link named ``name`` (KeyError if none)."""
        return self._by_name[0][name]

    @cached_property
    def _by_name(self) -> tuple[dict[str, Link], dict[str, Revolute], dict[str, Prismatic]]:
        """Name → link, revolute, prismatic (the first of each name; validation rejects repeats)."""
        maps: tuple[dict, dict, dict] = ({}, {}, {})
        for m, items in zip(maps, (self.links, self.revolutes, self.prismatics)):
            for item in items:
                m.setdefault(item.name, item)
        return maps

    @cached_property
    def link_names(self) -> tuple[str, ...]:
        return tuple(link.name for link in self.links)

    @cached_property
    def moving_links(self) -> tuple[str, ...]:
        return tuple(n for n in self.link_names if n != GROUND)

    @cached_property
    def revolutes(self) -> tuple[Revolute, ...]:
        return derive_revolutes(self.links, self.prismatics, self.drive.joint, self.planets)

    @cached_property
    def planets(self) -> tuple[str, ...]:
        """Links a higher pair ties to the crank, known with it: gear planets, cam followers."""
        return tuple(g.planet for g in self.gears) + tuple(c.follower for c in self.cams)

    def revolute(self, name: str) -> Revolute:
        return self._by_name[1][name]

    def prismatic(self, name: str) -> Prismatic:
        return self._by_name[2][name]

    @cached_property
    def slide_drive(self) -> bool:
        """True when the drive is a prismatic pair (a linear actuator): the input is a stroke [m]."""
        return self.drive.joint in self._by_name[2] and self.drive.joint not in self._by_name[1]

    @cached_property
    def crank(self) -> str:
        """The leading link: the crank, or the slider of a prismatic drive with ground; of a prismatic
        drive between two moving links (an actuator), its guide (the cylinder)."""
        if self.slide_drive:
            pj = self.prismatic(self.drive.joint)
            return pj.slider if pj.guide == GROUND else pj.guide
        joint = self.revolute(self.drive.joint)
        return joint.links[1] if joint.links[0] == GROUND else joint.links[0]


def derive_revolutes(links: tuple[Link, ...], prismatics: tuple[Prismatic, ...] = (),
                     drive_joint: str | None = None, planets: tuple[str, ...] = ()) -> tuple[Revolute, ...]:
    """Revolute pairs implied by points shared between links, in the order their points
    first appear.

    A point on two links is one revolute named after the point, ``links`` in description
    order. At a point on k > 2 links (a compound hinge) the k - 1 revolutes are those the
    Assur-group decomposition joins (``planar.decompose``: each link to the carrier that
    is known first, or to its group partner), so the result does not depend on the order of
    the tables; each is named ``POINT:FIRST-OTHER`` with its two links in description order.
    If the mechanism does not decompose, a compound hinge joins its first carrier to each
    other one (the structure analysis then reports why it does not decompose).
    """
    order = {link.name: i for i, link in enumerate(links)}
    carriers: dict[str, list[str]] = {}
    for link in links:
        for p in dict.fromkeys(link.points):
            carriers.setdefault(p, []).append(link.name)
    compound = {p for p, names in carriers.items() if len(names) > 2}
    chosen = _decomposed_hinges(links, prismatics, drive_joint, carriers, planets) if compound else None
    joints = []
    for point, names in carriers.items():
        if len(names) < 2:
            continue
        if len(names) == 2:
            joints.append(Revolute(point, point, (names[0], names[1])))
            continue
        pairs = chosen[point] if chosen is not None else [(names[0], other) for other in names[1:]]
        for a, b in sorted((tuple(sorted(ab, key=order.__getitem__)) for ab in pairs),
                           key=lambda ab: (order[ab[0]], order[ab[1]])):
            joints.append(Revolute(f"{point}:{a}-{b}", point, (a, b)))
    return tuple(joints)


def _decomposed_hinges(links, prismatics, drive_joint, carriers, planets=()) -> dict[str, list[tuple[str, str]]] | None:
    """Point → the pairs of links the decomposition joins there, or None if it does not
    decompose (or the description is not yet valid enough to try)."""
    names = [link.name for link in links]
    if len(set(names)) != len(names) or GROUND not in names or not isinstance(drive_joint, str):
        return None
    point, _, rest = drive_joint.partition(":")
    ends = rest.split("-") if rest else carriers.get(point, [])
    slide = next((pj for pj in prismatics if pj.name == drive_joint), None)
    if slide is not None and point not in carriers:  # a prismatic drive: its slider leads
        point, ends = "", [slide.slider, slide.guide]
    movers = [e for e in ends if e != GROUND]
    if len(ends) != 2 or GROUND not in ends or len(movers) != 1 or movers[0] not in names:
        return None
    try:
        groups, left = decompose({link.name: tuple(link.points) for link in links},
                                 [(pj.name, pj.slider, pj.guide) for pj in prismatics], movers[0], planets)
    except TypeError:  # names of the wrong type: validation reports them
        return None
    if left:
        return None
    out: dict[str, list[tuple[str, str]]] = {p: [] for p, c in carriers.items() if len(c) > 2}
    if point in out:
        out[point].append((GROUND, movers[0]))
    for _, conns in groups:
        for kind, name, ab in conns:
            if kind == "R" and name in out:
                out[name].append(ab)
    if any(len(out[p]) != len(carriers[p]) - 1 for p in out):
        return None
    return out


__all__ = [
    "GROUND",
    "CamPair",
    "Gear",
    "MassProperties",
    "Link",
    "Prismatic",
    "Revolute",
    "Drive",
    "PointForce",
    "LinkTorque",
    "Mechanism",
    "Friction",
    "Spring",
    "TorsionSpring",
]
