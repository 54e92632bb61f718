"""Cross-reference and range checks of a Mechanism (called on construction)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from linkgen.model import limits
from linkgen.errors import DescriptionError
from linkgen.model.names import GROUND, check_name
from linkgen.model.defaults import DEFAULT_BLOCK_MASS, DEFAULT_DENSITY
from linkgen.model.units import bounded, shown
from linkgen.families.planar.higher_pairs import check_cams, check_gears
from linkgen.families.planar.friction import check_friction
from linkgen.families.planar.springs import check_springs

if TYPE_CHECKING:
    from linkgen.families.planar.description import Mechanism


def _finite(x: float, where: str) -> None:
    if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x):
        raise DescriptionError(where, f"must be a finite number, got {shown(x)}")


def _length(x: float, where: str) -> None:
    bounded(x, where, limits.MAX_LENGTH, "m")


def validate(m: Mechanism) -> None:
    """Raise DescriptionError for the first problem found in ``m``."""
    check_name(m.name, "mechanism.name")
    for name, xy in m.points.items():
        check_name(name, f"points.{name}")
        if len(xy) != 2:
            raise DescriptionError(f"points.{name}", f"must be [x, y], got {xy!r}")
        for i, c in enumerate(xy):
            _length(c, f"points.{name}[{i}]")
    _check_extent(m)
    _check_links(m)
    _check_prismatics(m)
    _check_drive(m)
    for i, g in enumerate(m.gravity):
        bounded(g, f"mechanism.gravity[{i}]", limits.MAX_GRAVITY, "m/s²")
    _check_loads(m)
    check_gears(m)
    check_cams(m)
    check_springs(m)
    _check_mobility(m)
    check_friction(m)


def _check_links(m: Mechanism) -> None:
    seen: set[str] = set()
    carried: set[str] = set()
    for link in m.links:
        where = f"links.{link.name}"
        check_name(link.name, where)
        if link.name in seen:
            raise DescriptionError(where, "duplicate link name")
        seen.add(link.name)
        if not link.points:
            raise DescriptionError(f"{where}.points", "must list at least one point")
        for i, p in enumerate(link.points):
            if p not in m.points:
                raise DescriptionError(
                    f"{where}.points[{i}]", f"unknown point {p!r}; known points: {sorted(m.points)}"
                )
            if p in link.points[:i]:
                raise DescriptionError(f"{where}.points[{i}]", f"point {p!r} listed twice")
        carried.update(link.points)
        if link.length is not None:
            if link.name == GROUND or len(link.points) != 2:
                raise DescriptionError(
                    f"{where}.length", "is allowed only on a moving link with exactly two points"
                )
            _positive(link.length, f"{where}.length", "m")
            _length(link.length, f"{where}.length")
            if link.length < limits.MIN_LENGTH:
                raise DescriptionError(f"{where}.length", f"must be at least {limits.MIN_LENGTH:g} m (linkgen's "
                                       f"limits, see the README), got {link.length!r}")
        if link.shape is not None:
            if link.length is not None or link.name == GROUND:
                raise DescriptionError(f"{where}.shape", "give either length or shape, and none on ground")
            if set(link.shape) != set(link.points):
                raise DescriptionError(
                    f"{where}.shape", f"must give exactly the link's points {list(link.points)}, got {sorted(link.shape)}"
                )
            for p, xy in link.shape.items():
                _length(xy[0], f"{where}.shape.{p}[0]")
                _length(xy[1], f"{where}.shape.{p}[1]")
        axis = _axis_length(m, link)
        if link.length is None and axis is not None:
            if axis == 0.0:
                raise DescriptionError(
                    f"{where}.points", f"the first two points {list(link.points[:2])} coincide, so they define no x axis"
                )
            if axis < limits.MIN_LENGTH:
                raise DescriptionError(
                    f"{where}.points", f"the first two points {list(link.points[:2])} are {axis!r} m apart; "
                    f"linkgen needs at least {limits.MIN_LENGTH:g} m (its limits, see the README)")
        if link.areal_density is not None:
            for other in ("density", "inertial"):
                if getattr(link, other) is not None:
                    raise DescriptionError(f"{where}.areal_density", f"give one of areal_density, {other}, not both")
            _positive(link.areal_density, f"{where}.areal_density", "kg/m²")
            if _plate_area(m, link) <= 0.0:
                raise DescriptionError(f"{where}.areal_density", "a plate needs at least three points not on one line; "
                                       "for a bar between two points give density [kg/m]")
        if link.density is not None:
            if link.inertial is not None:
                raise DescriptionError(f"{where}.density", "give either density or inertial, not both")
            if len(link.points) != 2:
                raise DescriptionError(f"{where}.density", "a uniform bar needs exactly two points")
            _positive(link.density, f"{where}.density", "kg/m")
        if link.inertial is not None:
            _positive(link.inertial.mass, f"{where}.inertial.mass", "kg")
            _length(link.inertial.com[0], f"{where}.inertial.com[0]")
            _length(link.inertial.com[1], f"{where}.inertial.com[1]")
            bounded(link.inertial.inertia, f"{where}.inertial.inertia", limits.MAX_INERTIA, "kg·m²")
            if link.inertial.inertia < 0:
                raise DescriptionError(
                    f"{where}.inertial.inertia", f"must be >= 0 kg·m², got {link.inertial.inertia!r}"
                )
        if link.name != GROUND:
            _check_mass(link, axis, _plate_area(m, link) if link.areal_density is not None else 0.0)
    if GROUND not in seen:
        raise DescriptionError("links", f"a link named {GROUND!r} (the frame) is required")
    for p in m.points:
        if p not in carried:
            raise DescriptionError(f"points.{p}", "is carried by no link")


def _axis_length(m: Mechanism, link) -> float | None:
    """Distance [m] between a moving link's first two points (its x axis), from ``length``,
    ``shape`` or the sketch; None for ground and one-point links."""
    if link.name == GROUND or len(link.points) < 2:
        return None
    if link.length is not None:
        return link.length
    pts = link.shape if link.shape is not None else m.points
    (x0, y0), (x1, y1) = pts[link.points[0]], pts[link.points[1]]
    return math.hypot(x1 - x0, y1 - y0)


def _plate_area(m: Mechanism, link) -> float:
    """Area [m²] of the convex hull of the link's points (shape or sketch coordinates)."""
    from linkgen.families.planar.plate import hull_area

    pts = link.shape if link.shape is not None else m.points
    return hull_area([pts[p] for p in link.points])


def _check_mass(link, axis: float | None, area: float = 0.0) -> None:
    """The link's mass as MuJoCo will get it (explicit, density × length, or the defaults of
    linkgen.model.defaults) within [MIN_MASS, MAX_MASS]."""

    where = f"links.{link.name}"
    if link.inertial is not None:
        mass, how = link.inertial.mass, "as given"
    elif link.areal_density is not None:
        mass, how = link.areal_density * area, f"areal_density × area = {link.areal_density!r} kg/m² × {area!r} m²"
    elif link.density is not None:
        mass, how = link.density * axis, f"density × length = {link.density!r} kg/m × {axis!r} m"
    elif axis is None:
        mass, how = DEFAULT_BLOCK_MASS, "the default block"
    else:
        mass, how = DEFAULT_DENSITY * axis, (f"the default bar of {DEFAULT_DENSITY:g} kg/m × "
                                             f"{axis!r} m (give inertial or density)")
    if not limits.MIN_MASS <= mass <= limits.MAX_MASS:
        field = f"{where}.inertial.mass" if link.inertial is not None else (
            f"{where}.density" if link.density is not None else where)
        raise DescriptionError(field, f"mass {mass!r} kg ({how}) is outside {limits.MIN_MASS:g}..{limits.MAX_MASS:g} kg "
                               "(MuJoCo's smallest body mass and linkgen's limits, see the README)")


def _check_extent(m: Mechanism) -> None:
    """The mechanism's size: the diagonal of its points' bounding box [m]."""
    xs = [xy[0] for xy in m.points.values()]
    ys = [xy[1] for xy in m.points.values()]
    if not xs:
        raise DescriptionError("points", "must give at least one point")
    size = math.hypot(max(xs) - min(xs), max(ys) - min(ys))
    if not limits.MIN_LENGTH <= size <= limits.MAX_LENGTH:
        raise DescriptionError("points", f"the sketch spans {size!r} m; linkgen needs "
                               f"{limits.MIN_LENGTH:g}..{limits.MAX_LENGTH:g} m (its limits, see the README)")


def _positive(x: float, where: str, unit: str) -> None:
    _finite(x, where)
    if x <= 0:
        raise DescriptionError(where, f"must be > 0 {unit}, got {x!r}")


def _check_prismatics(m: Mechanism) -> None:
    seen = {j.name for j in m.revolutes}
    for pj in m.prismatics:
        where = f"prismatic.{pj.name}"
        check_name(pj.name, where)
        if pj.name in seen:
            raise DescriptionError(where, "duplicate joint name (revolutes are named after their points)")
        seen.add(pj.name)
        for key in ("slider", "guide"):
            name = getattr(pj, key)
            if name not in m.link_names:
                raise DescriptionError(
                    f"{where}.{key}", f"unknown link {name!r}; known links: {list(m.link_names)}"
                )
        if pj.slider == pj.guide:
            raise DescriptionError(f"{where}.guide", f"must differ from slider {pj.slider!r}")
        if pj.point not in m.link(pj.slider).points:
            raise DescriptionError(
                f"{where}.point", f"{pj.point!r} is not a point of link {pj.slider!r}"
            )
        if pj.through not in m.link(pj.guide).points:
            raise DescriptionError(
                f"{where}.through", f"{pj.through!r} is not a point of link {pj.guide!r}"
            )
        bounded(pj.angle, f"{where}.angle", limits.MAX_ANGLE, "rad")
        _length(pj.offset, f"{where}.offset")


def _check_drive(m: Mechanism) -> None:
    d = m.drive
    if m.slide_drive:
        _check_slide_drive(m)
        return
    names = [j.name for j in m.revolutes]
    if d.joint not in names:
        slides = [p.name for p in m.prismatics]
        raise DescriptionError("drive.joint", f"unknown revolute {d.joint!r}; revolutes: {names}"
                               + (f"; or a prismatic pair (a linear actuator): {slides}" if slides else ""))
    joint = m.revolute(d.joint)
    if GROUND not in joint.links:
        raise DescriptionError("drive.joint", f"{d.joint!r} must join {GROUND!r} and the crank, joins {joint.links}")
    crank = m.link(m.crank)
    if len(crank.points) < 2 or crank.points[0] != joint.point:
        raise DescriptionError(
            f"links.{crank.name}.points",
            f"the crank's first point must be the drive pivot {joint.point!r} and it needs a second point, "
            f"got {list(crank.points)}",
        )
    bounded(d.omega, "drive.omega", limits.MAX_OMEGA, "rad/s")
    bounded(d.epsilon, "drive.epsilon", limits.MAX_EPSILON, "rad/s²")
    bounded(d.start, "drive.range[0]", limits.MAX_ANGLE, "rad")
    bounded(d.stop, "drive.range[1]", limits.MAX_ANGLE, "rad")
    if not d.start < d.stop or d.stop - d.start > 2 * math.pi + 1e-12:
        raise DescriptionError(
            "drive.range", f"must be [from, to] with from < to <= from + 360deg, got [{d.start!r}, {d.stop!r}] rad"
        )


def _check_slide_drive(m: Mechanism) -> None:
    """A prismatic drive: a pair between ground and the slider (a linear actuator on a fixed
    guide) or between two moving links (a cylinder and its rod: the structure analysis checks how
    they are held), a speed and acceleration within the limits, a stroke range start < stop."""
    d, pj = m.drive, m.prismatic(m.drive.joint)
    if pj.slider == GROUND:
        raise DescriptionError(f"prismatic.{pj.name}.slider", f"a driven prismatic pair's slider must be the moving "
                                                              f"link, not {GROUND!r}; swap slider and guide")
    for what, items in (("gear", m.gears), ("cam", m.cams)):
        if items:
            raise DescriptionError(f"{what}.{items[0].name}", f"a {what} pair turns with a crank; the drive "
                                   f"{d.joint!r} is a prismatic pair (a linear actuator), which has none")
    for i, f in enumerate(m.forces):
        if f.stroke is not None:
            raise DescriptionError(f"force[{i}].stroke", "is a range of crank angles; with a prismatic drive "
                                                         "(no crank) a force acts over the whole stroke: leave it out")
    bounded(d.omega, "drive.velocity", limits.MAX_OMEGA * limits.MAX_LENGTH, "m/s")
    bounded(d.epsilon, "drive.acceleration", limits.MAX_EPSILON * limits.MAX_LENGTH, "m/s²")
    _length(d.start, "drive.start")
    _length(d.stop, "drive.stop")
    if not d.start < d.stop:
        raise DescriptionError("drive", f"the stroke needs start < stop, got start = {d.start!r} m, "
                                        f"stop = {d.stop!r} m")


def _check_loads(m: Mechanism) -> None:
    for i, f in enumerate(m.forces):
        where = f"force[{i}]"
        if f.link not in m.link_names:
            raise DescriptionError(f"{where}.link", f"unknown link {f.link!r}; known links: {list(m.link_names)}")
        if f.point not in m.link(f.link).points:
            raise DescriptionError(f"{where}.point", f"{f.point!r} is not a point of link {f.link!r}")
        bounded(f.force[0], f"{where}.force[0]", limits.MAX_FORCE, "N")
        bounded(f.force[1], f"{where}.force[1]", limits.MAX_FORCE, "N")
        if f.stroke is not None:
            bounded(f.stroke[0], f"{where}.stroke[0]", limits.MAX_ANGLE, "rad")
            bounded(f.stroke[1], f"{where}.stroke[1]", limits.MAX_ANGLE, "rad")
            width = f.stroke[1] - f.stroke[0]
            if not 0.0 < width <= 2 * math.pi + 1e-12:
                raise DescriptionError(
                    f"{where}.stroke",
                    f"must be [from, to] crank angles with from < to <= from + 360deg, "
                    f"got [{f.stroke[0]!r}, {f.stroke[1]!r}] rad",
                )
    for i, t in enumerate(m.torques):
        if t.link not in m.link_names:
            raise DescriptionError(f"torque[{i}].link", f"unknown link {t.link!r}; known links: {list(m.link_names)}")
        bounded(t.torque, f"torque[{i}].torque", limits.MAX_TORQUE, "N·m")


def mobility_formula(n: int, p5: int, p4: int) -> str:
    """Chebychev's formula with the counts: ``W = 3·n - 2·p5 [- p4] = 3·3 - 2·4 [- 1] = W``
    (n moving links, p5 lower pairs, p4 higher pairs: gears and cams)."""
    w = 3 * n - 2 * p5 - p4
    if p4:
        return f"W = 3·n - 2·p5 - p4 = 3·{n} - 2·{p5} - {p4} = {w}"
    return f"W = 3·n - 2·p5 = 3·{n} - 2·{p5} = {w}"


def _check_mobility(m: Mechanism) -> None:
    n = len(m.moving_links)
    p5 = len(m.revolutes) + len(m.prismatics)
    p4 = len(m.gears) + len(m.cams)
    if 3 * n - 2 * p5 - p4 != 1:
        raise DescriptionError(
            "mechanism",
            f"mobility {mobility_formula(n, p5, p4)}; linkgen needs exactly 1 degree of freedom (one driven crank)",
        )
