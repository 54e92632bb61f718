"""Cross-reference and range checks of a Mechanism (called on construction)."""

from __future__ import annotations

import math

from .description import GROUND, Mechanism, check_name
from .errors import DescriptionError


def _finite(x: float, where: str) -> None:
    if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(x):
        raise DescriptionError(where, f"must be a finite number, got {x!r}")


def validate(m: Mechanism) -> None:
    """Raise DescriptionError for the first problem found in ``m``."""
    check_name(m.name, "mechanism.name")
    for name, xy in m.points.items():
        check_name(name, f"points.{name}")
        if len(xy) != 2:
            raise DescriptionError(f"points.{name}", f"must be [x, y], got {xy!r}")
        for i, c in enumerate(xy):
            _finite(c, f"points.{name}[{i}]")
    _check_links(m)
    _check_prismatics(m)
    _check_drive(m)
    for i, g in enumerate(m.gravity):
        _finite(g, f"mechanism.gravity[{i}]")
    _check_loads(m)
    _check_mobility(m)


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
        if link.shape is not None:
            if link.length is not None or link.name == GROUND:
                raise DescriptionError(f"{where}.shape", "give either length or shape, and none on ground")
            if set(link.shape) != set(link.points):
                raise DescriptionError(
                    f"{where}.shape", f"must give exactly the link's points {list(link.points)}, got {sorted(link.shape)}"
                )
            for p, xy in link.shape.items():
                _finite(xy[0], f"{where}.shape.{p}[0]")
                _finite(xy[1], f"{where}.shape.{p}[1]")
        if link.length is None and link.name != GROUND and len(link.points) >= 2:
            pts = link.shape if link.shape is not None else m.points
            (x0, y0), (x1, y1) = pts[link.points[0]], pts[link.points[1]]
            if math.hypot(x1 - x0, y1 - y0) == 0.0:
                raise DescriptionError(
                    f"{where}.points", f"the first two points {list(link.points[:2])} coincide, so they define no x axis"
                )
        if link.density is not None:
            if link.inertial is not None:
                raise DescriptionError(f"{where}.density", "give either density or inertial, not both")
            if len(link.points) != 2:
                raise DescriptionError(f"{where}.density", "a uniform bar needs exactly two points")
            _positive(link.density, f"{where}.density", "kg/m")
        if link.inertial is not None:
            _positive(link.inertial.mass, f"{where}.inertial.mass", "kg")
            _finite(link.inertial.com[0], f"{where}.inertial.com[0]")
            _finite(link.inertial.com[1], f"{where}.inertial.com[1]")
            _finite(link.inertial.inertia, f"{where}.inertial.inertia")
            if link.inertial.inertia < 0:
                raise DescriptionError(
                    f"{where}.inertial.inertia", f"must be >= 0 kg·m², got {link.inertial.inertia!r}"
                )
    if GROUND not in seen:
        raise DescriptionError("links", f"a link named {GROUND!r} (the frame) is required")
    for p in m.points:
        if p not in carried:
            raise DescriptionError(f"points.{p}", "is carried by no link")


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
        _finite(pj.angle, f"{where}.angle")
        _finite(pj.offset, f"{where}.offset")


def _check_drive(m: Mechanism) -> None:
    d = m.drive
    names = [j.name for j in m.revolutes]
    if d.joint not in names:
        raise DescriptionError("drive.joint", f"unknown revolute {d.joint!r}; revolutes: {names}")
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
    _finite(d.omega, "drive.omega")
    _finite(d.epsilon, "drive.epsilon")
    _finite(d.start, "drive.range[0]")
    _finite(d.stop, "drive.range[1]")
    if not d.start < d.stop or d.stop - d.start > 2 * math.pi + 1e-12:
        raise DescriptionError(
            "drive.range", f"must be [from, to] with from < to <= from + 360deg, got [{d.start!r}, {d.stop!r}] rad"
        )


def _check_loads(m: Mechanism) -> None:
    for i, f in enumerate(m.forces):
        where = f"force[{i}]"
        if f.link not in m.link_names:
            raise DescriptionError(f"{where}.link", f"unknown link {f.link!r}; known links: {list(m.link_names)}")
        if f.point not in m.link(f.link).points:
            raise DescriptionError(f"{where}.point", f"{f.point!r} is not a point of link {f.link!r}")
        _finite(f.force[0], f"{where}.force[0]")
        _finite(f.force[1], f"{where}.force[1]")
        if f.stroke is not None:
            _finite(f.stroke[0], f"{where}.stroke[0]")
            _finite(f.stroke[1], f"{where}.stroke[1]")
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
        _finite(t.torque, f"torque[{i}].torque")


def _check_mobility(m: Mechanism) -> None:
    n = len(m.moving_links)
    p5 = len(m.revolutes) + len(m.prismatics)
    w = 3 * n - 2 * p5
    if w != 1:
        raise DescriptionError(
            "mechanism",
            f"mobility W = 3·n - 2·p5 = 3·{n} - 2·{p5} = {w}; linkgen needs exactly 1 degree of freedom "
            f"(one driven crank)",
        )
