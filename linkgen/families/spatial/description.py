"""A spatial mechanism description: 3-D points, revolute pairs with their axes, spherical pairs,
prismatic pairs with a 3-D direction; read from TOML like a planar one, marked by
``[mechanism] space = "spatial"``. Every check names the field, the value and what is allowed;
inside, SI units and radians.

    [mechanism]        name, title, space = "spatial", gravity = [gx, gy, gz] (default 0)
    [points]           NAME = [x, y, z] at the sketch pose (moving points need only be close)
    [links.NAME]       points; length (two-point links: the exact distance); mass [kg] or
                       density [kg/m] (a uniform slender rod over the first two points; a
                       one-point link is a point mass)
    [joints.POINT]     kind = "revolute" or "cylindrical" (axis = [x, y, z]), or "spherical":
                       the pair at a point two links share (a cylindrical pair turns about and
                       slides along its axis)
    [prismatic.NAME]   slider, guide (default "ground"), point (default the slider's first),
                       direction = [x, y, z]: the slider's point moves on the line through its
                       sketch position along ``direction``
    [drive]            joint: the revolute between ground and the crank (omega, epsilon), or a
                       prismatic pair between ground and the input slider (velocity [m/s],
                       acceleration [m/s²], start, stop [m]: the input's range, displacements of
                       the slider's point from its sketch position along the line)
    [[force]]          link, point, force = [Fx, Fy, Fz], stroke (optional) — see ``spatial.loads``
    [[torque]]         link, torque = [Tx, Ty, Tz]

The crank angle φ is the angle of the crank's second point about the drive axis, measured
from the world axis least aligned with the drive axis (x, then y, then z) projected onto the
plane square to it — for an axis along z, from +x about +z. A prismatic input's coordinate s
[m] takes φ's place everywhere (the "input"): its rate and acceleration are m/s and m/s².
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, Mapping

import numpy as np

from linkgen.errors import DescriptionError
from linkgen.model import limits
from linkgen.model.defaults import DEFAULT_BLOCK_MASS, DEFAULT_DENSITY
from linkgen.model.names import GROUND, check_name
from linkgen.model.schema import SPATIAL, check as check_types
from linkgen.model.units import bounded, finite, length, shown
from linkgen.families.spatial.drive import Drive3, read_drive
from linkgen.families.spatial.loads import LinkTorque3, PointForce3, read_loads

_TOP = {"mechanism", "points", "links", "joints", "prismatic", "drive", "force", "torque"}
_MECH = {"name", "title", "space", "gravity"}
_LINK = {"points", "length", "mass", "density"}
_JOINT = {"kind", "axis"}
_PRISMATIC = {"slider", "guide", "point", "direction"}
JOINT_KINDS = ("revolute", "cylindrical", "spherical")
# A direction shorter than this (relative to its largest component's scale) has no direction.
MIN_DIRECTION = 1e-12


@dataclass(frozen=True)
class Link3:
    """A rigid link: its points, the exact distance between its two points (or None: from
    the sketch), its mass [kg] as a slender rod over its first two points (a point mass for a
    one-point link)."""

    name: str
    points: tuple[str, ...]
    length: float | None
    mass: float


@dataclass(frozen=True)
class Joint3:
    """A pair at the point ``name`` between ``links`` (description order): revolute with a unit
    ``axis`` (3,), or spherical (axis None)."""

    name: str
    kind: str
    links: tuple[str, str]
    axis: tuple[float, float, float] | None


@dataclass(frozen=True)
class Slide3:
    """A prismatic pair: ``point`` of ``slider`` moves along the unit ``direction`` (3,) on a
    line fixed to ``guide`` through the point's sketch position."""

    name: str
    slider: str
    guide: str
    point: str
    direction: tuple[float, float, float]


@dataclass(frozen=True)
class SpatialMechanism:
    """A validated spatial mechanism (see the module docstring)."""

    name: str
    title: str
    points: Mapping[str, tuple[float, float, float]]
    links: tuple[Link3, ...]
    joints: tuple[Joint3, ...]
    slides: tuple[Slide3, ...]
    drive: Drive3
    gravity: tuple[float, float, float] = (0.0, 0.0, 0.0)
    source: str | None = None
    forces: tuple[PointForce3, ...] = ()
    torques: tuple[LinkTorque3, ...] = ()

    def __repr__(self) -> str:
        return f"SpatialMechanism({self.name!r}, {len(self.links)} links, {len(self.joints) + len(self.slides)} pairs)"

    @property
    def slide_drive(self) -> bool:
        """Whether the input is a slider (its displacement s [m] takes the crank angle's place),
        under the planar description's name for it."""
        return self.drive.slides

    def link(self, name: str) -> Link3:
        return next(l for l in self.links if l.name == name)

    def joint(self, name: str) -> Joint3:
        return next(j for j in self.joints if j.name == name)

    def point(self, name: str) -> np.ndarray:
        return np.array(self.points[name], dtype=float)


def is_spatial(data: Mapping) -> bool:
    mech = data.get("mechanism")
    return isinstance(mech, dict) and mech.get("space") == "spatial"


def _table(value: Any, where: str) -> dict:
    if not isinstance(value, dict):
        raise DescriptionError(where, f"must be a table, got {shown(value)}")
    return value


def _keys(table: dict, allowed: set, where: str) -> None:
    for k in table:
        if k not in allowed:
            raise DescriptionError(f"{where}.{k}", f"unknown key; allowed: {', '.join(sorted(allowed))}")


def _vector3(value: Any, field: str, lengths: bool = False, limit: float = limits.MAX_LENGTH,
             unit: str = "m") -> tuple[float, float, float]:
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        raise DescriptionError(field, f"must be a list of 3 {'lengths' if lengths else 'numbers'} [x, y, z], "
                                      f"got {shown(value)}")
    read = length if lengths else finite
    return tuple(bounded(read(v, f"{field}[{i}]"), f"{field}[{i}]", limit, unit)  # type: ignore[return-value]
                 for i, v in enumerate(value))


def _direction(value: Any, field: str) -> tuple[float, float, float]:
    v = np.array(_vector3(value, field), dtype=float)
    n = float(np.linalg.norm(v))
    if not n > MIN_DIRECTION * max(1.0, float(np.abs(v).max())):
        raise DescriptionError(field, f"must be a non-zero direction, got {shown(value)}")
    return tuple(float(x) for x in v / n)  # type: ignore[return-value]


def spatial_from_dict(data: Mapping, source: str | None = None) -> SpatialMechanism:
    """A SpatialMechanism from a TOML-shaped dict; errors name the field (and ``source``)."""
    try:
        return _from_dict(data, source)
    except DescriptionError as exc:
        raise (exc.in_file(source) if source else exc) from None


def _from_dict(data: Mapping, source: str | None) -> SpatialMechanism:
    _keys(dict(data), _TOP, "")
    check_types(dict(data), SPATIAL, "")
    mech = _table(data.get("mechanism", {}), "mechanism")
    _keys(mech, _MECH, "mechanism")
    if mech.get("space") != "spatial":
        raise DescriptionError("mechanism.space", f"must be \"spatial\" for a spatial description, got {shown(mech.get('space'))}")
    name = check_name(mech.get("name", "mechanism"), "mechanism.name")
    title = mech.get("title", name)
    if not isinstance(title, str):
        raise DescriptionError("mechanism.title", f"must be a string, got {shown(title)}")
    gravity = _vector3(mech.get("gravity", [0.0, 0.0, 0.0]), "mechanism.gravity", limit=limits.MAX_GRAVITY, unit="m/s²")

    points_t = _table(data.get("points", {}), "points")
    if not points_t:
        raise DescriptionError("points", "must name at least the points of the pairs, as NAME = [x, y, z]")
    points = {check_name(k, f"points.{k}"): _vector3(v, f"points.{k}", lengths=True) for k, v in points_t.items()}

    links_t = _table(data.get("links", {}), "links")
    if GROUND not in links_t:
        raise DescriptionError("links", f"must have a link named {GROUND!r} (the fixed link)")
    links = tuple(_link(check_name(k, f"links.{k}"), _table(v, f"links.{k}"), points) for k, v in links_t.items())

    owners: dict[str, list[str]] = {p: [] for p in points}
    for l in links:
        for p in l.points:
            owners[p].append(l.name)
    joints_t = _table(data.get("joints", {}), "joints")
    joints = []
    for p, holders in owners.items():
        if len(holders) > 2:
            raise DescriptionError(f"points.{p}", f"is listed by {len(holders)} links ({', '.join(holders)}); a spatial "
                                                  "pair joins exactly two links")
        if len(holders) == 2 and p not in joints_t:
            raise DescriptionError(f"joints.{p}", f"missing: point {p} is shared by links {holders[0]} and {holders[1]}; "
                                                  "give its pair as kind = \"revolute\" with an axis, or \"spherical\"")
    for p, jt in joints_t.items():
        where = f"joints.{p}"
        jt = _table(jt, where)
        _keys(jt, _JOINT, where)
        if p not in points:
            raise DescriptionError(where, f"names no point; points are {', '.join(points)}")
        if len(owners[p]) != 2:
            raise DescriptionError(where, f"point {p} is on {len(owners[p])} link(s); a pair is a point two links share")
        kind = jt.get("kind")
        if kind not in JOINT_KINDS:
            raise DescriptionError(f"{where}.kind", f"must be one of {', '.join(JOINT_KINDS)}, got {shown(kind)}")
        axis = None
        if kind in ("revolute", "cylindrical"):
            if "axis" not in jt:
                raise DescriptionError(f"{where}.axis", f"missing: a {kind} pair needs its axis [x, y, z]")
            axis = _direction(jt["axis"], f"{where}.axis")
        elif "axis" in jt:
            raise DescriptionError(f"{where}.axis", "a spherical pair has no axis; remove the key")
        joints.append(Joint3(p, kind, (owners[p][0], owners[p][1]), axis))

    slides = []
    for sname, st in _table(data.get("prismatic", {}), "prismatic").items():
        where = f"prismatic.{check_name(sname, f'prismatic.{sname}')}"
        if sname in joints_t:  # MuJoCo's joints take the pairs' names: one name, one joint
            raise DescriptionError(where, f"duplicate pair name: the pair at point {sname} is named after its point; "
                                          f"give the prismatic pair another name")
        st = _table(st, where)
        _keys(st, _PRISMATIC, where)
        slider = st.get("slider")
        if slider not in links_t or slider == GROUND:
            raise DescriptionError(f"{where}.slider", f"must name a moving link, got {shown(slider)}")
        guide = st.get("guide", GROUND)
        if guide not in links_t or guide == slider:
            raise DescriptionError(f"{where}.guide", f"must name another link, got {shown(guide)}")
        slink = next(l for l in links if l.name == slider)
        point = st.get("point", slink.points[0])
        if point not in slink.points:
            raise DescriptionError(f"{where}.point", f"must be a point of link {slider} ({', '.join(slink.points)}), "
                                                     f"got {shown(point)}")
        if "direction" not in st:
            raise DescriptionError(f"{where}.direction", "missing: the line's direction [x, y, z]")
        slides.append(Slide3(sname, slider, guide, point, _direction(st["direction"], f"{where}.direction")))

    drive = read_drive(_table(data.get("drive", {}), "drive"), joints, slides)
    point_forces, torques = read_loads(dict(data), {l.name: l.points for l in links})
    if drive.slides:  # a stroke is a range of crank angles: a slider's input has none
        for i, f in enumerate(point_forces):
            if f.stroke is not None:
                raise DescriptionError(f"force[{i}].stroke", "is a range of crank angles; with a prismatic input "
                                                             f"({drive.joint}) there is none: remove it")
    return SpatialMechanism(name, title, MappingProxyType(points), links, tuple(joints), tuple(slides),
                            drive, gravity, source, point_forces, torques)


def _link(name: str, t: dict, points: dict) -> Link3:
    where = f"links.{name}"
    _keys(t, _LINK, where)
    pts = t.get("points")
    if not isinstance(pts, list) or not pts or len(set(pts)) != len(pts):
        raise DescriptionError(f"{where}.points", f"must be a list of distinct point names, got {shown(pts)}")
    for i, p in enumerate(pts):
        if p not in points:
            raise DescriptionError(f"{where}.points[{i}]", f"names no point in [points], got {shown(p)}")
    size = None
    if "length" in t:
        if len(pts) != 2:
            raise DescriptionError(f"{where}.length", f"is for a link of two points; this one has {len(pts)}")
        size = bounded(length(t["length"], f"{where}.length"), f"{where}.length", limits.MAX_LENGTH, "m")
        if not size > 0:
            raise DescriptionError(f"{where}.length", f"must be > 0 m, got {shown(t['length'])}")
    if "mass" in t and "density" in t:
        raise DescriptionError(where, "give mass or density, not both")
    if name == GROUND:
        mass = 0.0
    elif "mass" in t:
        mass = finite(t["mass"], f"{where}.mass")
        if not mass > 0:
            raise DescriptionError(f"{where}.mass", f"must be > 0 kg, got {shown(t['mass'])}")
    else:
        density = finite(t.get("density", DEFAULT_DENSITY), f"{where}.density")
        if not density > 0:
            raise DescriptionError(f"{where}.density", f"must be > 0 kg/m, got {shown(t.get('density'))}")
        if len(pts) == 1:
            mass = DEFAULT_BLOCK_MASS if "density" not in t else density
            if "density" in t:
                raise DescriptionError(f"{where}.density", "a one-point link has no length; give its mass [kg]")
        else:
            span = size if size is not None else math.dist(points[pts[0]], points[pts[1]])
            mass = density * span
    if name != GROUND and not limits.MIN_MASS <= mass <= limits.MAX_MASS:
        raise DescriptionError(f"{where}.{'mass' if 'mass' in t else 'density'}",
                               f"gives a mass of {mass:g} kg; linkgen's limits are {limits.MIN_MASS:g}..{limits.MAX_MASS:g} kg")
    return Link3(name, tuple(pts), size, mass)


__all__ = ["Drive3", "Joint3", "Link3", "Slide3", "SpatialMechanism", "is_spatial", "spatial_from_dict"]
