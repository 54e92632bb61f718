"""Checks of the higher pairs a description may add to its linkage: gear pairs ([gear.NAME]) and
cam pairs ([cam.NAME]); every message names the field, the value and what is allowed."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

from linkgen.errors import DescriptionError
from linkgen.model import limits
from linkgen.model.names import GROUND, check_name
from linkgen.model.units import bounded, shown

if TYPE_CHECKING:
    from linkgen.families.planar.description import Mechanism


# The planet's centre must sit the gear pair's centre distance from the crank's pivot, to this
# fraction of the mechanism's extent (the sketch's coordinates are exact where a gear is given).
GEAR_CENTRE_TOL = 1e-9


def check_gears(m: Mechanism) -> None:
    seen = set()
    for g in m.gears:
        where = f"gear.{g.name}"
        check_name(g.name, where)
        if g.planet not in m.link_names or g.planet in (GROUND, m.crank):
            raise DescriptionError(f"{where}.planet", f"must be a moving link other than the crank {m.crank!r}, "
                                                      f"got {g.planet!r}")
        if g.planet in seen:
            raise DescriptionError(f"{where}.planet", f"link {g.planet!r} already carries a gear")
        seen.add(g.planet)
        if g.kind not in ("internal", "external"):
            raise DescriptionError(f"{where}.kind", f"must be \"internal\" (a ring gear) or \"external\" (a sun "
                                                    f"gear), got {g.kind!r}")
        zf, zp = g.teeth
        if not (isinstance(zf, int) and isinstance(zp, int) and zf > 0 and zp > 0):
            raise DescriptionError(f"{where}.teeth", f"must be two whole numbers > 0 [fixed, planet], got {list(g.teeth)}")
        if max(zf, zp) > limits.MAX_TEETH:
            raise DescriptionError(f"{where}.teeth", f"must be at most {limits.MAX_TEETH} teeth each (the largest count "
                                                     f"float64 carries exactly; linkgen's limits, see the README), got "
                                                     f"{shown(list(g.teeth))}")
        if g.kind == "internal" and zf <= zp:
            raise DescriptionError(f"{where}.teeth", f"a ring gear needs more teeth than its planet, got {list(g.teeth)}")
        if not (math.isfinite(g.module) and g.module > 0):
            raise DescriptionError(f"{where}.module", f"must be > 0 m, got {g.module!r}")
        bounded(g.module, f"{where}.module", limits.MAX_LENGTH, "m")
        if 0.5 * g.module * max(zf, zp) > limits.MAX_LENGTH:
            raise DescriptionError(f"{where}", f"a pitch radius m·z/2 = {0.5 * g.module * max(zf, zp):g} m is beyond "
                                               f"±{limits.MAX_LENGTH:g} m (linkgen's limits, see the README)")
        if not 0.0 <= g.pressure_angle < math.radians(45.0):
            raise DescriptionError(f"{where}.pressure_angle", f"must be in [0°, 45°), got {math.degrees(g.pressure_angle):g}°")
        centre = m.link(g.planet).points[0]
        if centre not in m.link(m.crank).points:
            raise DescriptionError(f"links.{g.planet}.points[0]", f"the planet's first point, {centre!r}, is its gear's "
                                                                  f"centre and must be a point of the crank {m.crank!r}")
        pivot = m.points[m.revolute(m.drive.joint).point]
        d = math.dist(pivot, m.points[centre])
        size = max(math.dist(a, b) for a in m.points.values() for b in m.points.values())
        if abs(d - g.centre_distance) > GEAR_CENTRE_TOL * size:
            raise DescriptionError(f"points.{centre}", f"the planet's centre is {d:.9g} m from the crank's pivot; gear "
                                                       f"{g.name!r} needs the centre distance m·(z_fixed {'−' if g.kind == 'internal' else '+'} "
                                                       f"z_planet)/2 = {g.centre_distance:.9g} m")


def check_cams(m: Mechanism) -> None:
    seen = set(m.planets[:len(m.gears)])
    for cam in m.cams:
        where = f"cam.{cam.name}"
        check_name(cam.name, where)
        if cam.follower not in m.link_names or cam.follower in (GROUND, m.crank):
            raise DescriptionError(f"{where}.follower", f"must be a moving link other than the crank {m.crank!r} (the "
                                                        f"cam turns with the crank), got {cam.follower!r}")
        if cam.follower in seen:
            raise DescriptionError(f"{where}.follower", f"link {cam.follower!r} is already driven by a gear or a cam")
        seen.add(cam.follower)
        if cam.roller not in m.link(cam.follower).points:
            raise DescriptionError(f"{where}.roller", f"must be a point of the follower {cam.follower!r} (the roller's "
                                                      f"centre), one of {list(m.link(cam.follower).points)}; got "
                                                      f"{cam.roller!r}")
        bounded(cam.spring_rate, f"{where}.spring_rate", limits.MAX_FORCE, "N/m or N·m/rad")
        bounded(cam.spring_preload, f"{where}.spring_preload", limits.MAX_FORCE, "N or N·m")
        pivot = m.points[m.revolute(m.drive.joint).point]
        reach = math.dist(pivot, m.points[cam.roller])
        if not 0.0 <= cam.roller_radius < reach:
            raise DescriptionError(f"{where}.roller_radius", f"must be ≥ 0 m and below the roller centre's distance from "
                                                             f"the cam's axis in the sketch, {reach:.6g} m; got "
                                                             f"{cam.roller_radius!r} m")
        pairs = [r.name for r in m.revolutes if set(r.links) == {cam.follower, GROUND}]
        pairs += [p.name for p in m.prismatics if {p.slider, p.guide} == {cam.follower, GROUND}]
        if len(pairs) != 1:
            raise DescriptionError(f"{where}.follower", f"the follower {cam.follower!r} needs exactly one pair with the "
                                                        f"ground (a revolute at its pivot, or a prismatic pair); it has "
                                                        f"{len(pairs)}: {pairs}")
        for p in m.prismatics:
            if p.guide == cam.follower and p.slider == GROUND:
                raise DescriptionError(f"prismatic.{p.name}", f"a translating follower slides on the ground: give "
                                                              f"slider = {cam.follower!r} and guide = \"ground\"")


__all__ = ["GEAR_CENTRE_TOL", "check_cams", "check_gears"]
