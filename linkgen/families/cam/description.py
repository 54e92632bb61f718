"""A cam mechanism description: a disc cam driven at a constant speed and its roller (or knife-edge)
follower, translating or oscillating, held on the cam by a spring; read from TOML like a linkage
(the file has a ``[cam]`` table instead of points and links). Every check names the field, the
value and what is allowed; inside, SI units and radians.

    [mechanism]  name, title, gravity = [gx, gy] (optional)
    [cam]        base_radius [m] (an oscillating follower may give follower.lowest_angle instead),
                 omega [rad/s or "60rpm"], > 0: counter-clockwise
    [follower]   kind = "translating" | "oscillating"; roller_radius [m] (0: knife edge);
                 translating only: face = "roller" (default) | "flat" (a face square to its motion);
                 translating: offset [m], mass [kg]; oscillating: pivot_distance [m],
                 arm_length [m], inertia [kg·m² about the pivot], lowest_angle (optional);
                 spring_rate [N/m or N·m/rad], spring_preload [N or N·m at the lowest position]
    [[segment]]  kind = "rise" | "dwell" | "return", span (angle), law = "harmonic" | "cycloidal" |
                 "poly345", height [m, or an angle for an oscillating follower]; the spans make a turn
    or [law]     kind = "sine": amplitude, mean (optional), phase (optional) — y = mean + amplitude·sin(θ + phase)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from linkgen.families.cam.follower import Follower
from linkgen.families.cam.laws import LAWS, Program, Segment, SineProgram
from linkgen.errors import DescriptionError
from linkgen.model.names import check_name
from linkgen.model.schema import CAM_FILE, check as check_types
from linkgen.model import limits
from linkgen.model.units import angular_speed, bounded, finite, length, non_negative, parse_angle, shown, vector2

_TOP = {"mechanism", "cam", "follower", "segment", "law"}
_MECH = {"name", "title", "gravity"}
_CAM = {"base_radius", "omega"}
_FOLLOWER = {"kind", "face", "roller_radius", "offset", "mass", "pivot_distance", "arm_length", "inertia", "lowest_angle",
             "spring_rate", "spring_preload"}
_SEGMENT = {"kind", "span", "law", "height"}
_LAW = {"kind", "amplitude", "mean", "phase"}


# The commands that take a cam file (linkgen.cli); every other one refuses it, naming these.


@dataclass(frozen=True)
class CamMechanism:
    """A validated cam mechanism (see the module docstring); ``follower`` carries the geometry
    and the program, ``mass`` [kg] or ``inertia`` [kg·m²] the follower's, the spring its rate and
    preload (N/m and N, or N·m/rad and N·m)."""

    name: str
    title: str
    follower: Follower
    omega: float
    mass: float = 0.0
    inertia: float = 0.0
    spring_rate: float = 0.0
    spring_preload: float = 0.0
    gravity: tuple[float, float] = (0.0, 0.0)

    def __repr__(self) -> str:
        return f"CamMechanism({self.name!r}, {self.follower.kind} follower)"


def is_cam_data(data) -> bool:
    """A stand-alone cam mechanism: a ``[cam]`` table and no ``[links]`` (a linkage whose crank
    carries a cam has ``[cam.NAME]`` pair tables next to its links)."""
    return isinstance(data, dict) and "cam" in data and "links" not in data


def _length(value, field: str) -> float:
    """A length [m] within linkgen's limits (linkgen.model.limits)."""
    return bounded(length(value, field), field, limits.MAX_LENGTH, "m")


def _table(data: dict, key: str, allowed: set[str], required: set[str]) -> dict:
    t = data.get(key)
    if not isinstance(t, dict):
        raise DescriptionError(key, f"must be a table, got {shown(t)}" if key in data else "is required")
    for k in t:
        if k not in allowed:
            raise DescriptionError(f"{key}.{k}", f"unknown key; allowed keys: {sorted(allowed)}")
    for k in sorted(required):
        if k not in t:
            raise DescriptionError(f"{key}.{k}", "is required")
    return t


def program_from_table(data: dict, oscillating: bool, where: str = ""):
    """The motion program of ``data``'s ``[[segment]]`` tables or ``[law]`` table (angles for an
    oscillating follower, lengths for a translating one); errors name fields under ``where``."""
    try:
        return _program(data, oscillating)
    except DescriptionError as exc:
        if not where:
            raise
        raise DescriptionError(f"{where}.{exc.field}", exc.problem) from None


def _program(data: dict, oscillating: bool):
    if oscillating:
        def size(v, f):
            return bounded(parse_angle(v, f), f, limits.MAX_ANGLE, "rad")
    else:
        def size(v, f):
            return bounded(length(v, f), f, limits.MAX_LENGTH, "m")
    if ("segment" in data) == ("law" in data):
        raise DescriptionError("segment", "give the motion either as [[segment]] tables (rise, dwell, return) or as "
                                          "one [law] table (kind = \"sine\"), not both or neither")
    if "law" in data:
        t = _table(data, "law", _LAW, {"kind", "amplitude"})
        if t["kind"] != "sine":
            raise DescriptionError("law.kind", f"must be \"sine\", got {shown(t['kind'])}")
        return SineProgram(size(t["amplitude"], "law.amplitude"), size(t.get("mean", 0.0), "law.mean"),
                           parse_angle(t.get("phase", 0.0), "law.phase"))
    segs = data["segment"]
    if not isinstance(segs, list) or not segs:
        raise DescriptionError("segment", f"must be a list of [[segment]] tables, got {shown(segs)}")
    out = []
    for i, s in enumerate(segs):
        where = f"segment[{i}]"
        if not isinstance(s, dict):
            raise DescriptionError(where, f"must be a table, got {shown(s)}")
        for k in s:
            if k not in _SEGMENT:
                raise DescriptionError(f"{where}.{k}", f"unknown key; allowed keys: {sorted(_SEGMENT)}")
        kind = s.get("kind")
        if kind not in ("rise", "dwell", "return"):
            raise DescriptionError(f"{where}.kind", f"must be \"rise\", \"dwell\" or \"return\", got {shown(kind)}")
        if "span" not in s:
            raise DescriptionError(f"{where}.span", "is required")
        span = parse_angle(s["span"], f"{where}.span")
        if not span > 0:
            raise DescriptionError(f"{where}.span", f"must be > 0, got {shown(s['span'])}")
        if kind == "dwell":
            out.append(Segment("dwell", span))
            continue
        if s.get("law") not in LAWS:
            raise DescriptionError(f"{where}.law", f"must be one of {list(LAWS)}, got {shown(s.get('law'))}")
        if "height" not in s:
            raise DescriptionError(f"{where}.height", "is required")
        out.append(Segment(kind, span, s["law"], size(s["height"], f"{where}.height")))
    total = sum(s.span for s in out)
    if abs(total - 2 * math.pi) > 1e-9:
        raise DescriptionError("segment", f"the spans add up to {math.degrees(total):.6g}°; they must make one turn, 360°")
    level = 0.0
    for i, s in enumerate(out):
        level += s.height if s.kind == "rise" else -s.height if s.kind == "return" else 0.0
        if level < -1e-12:
            raise DescriptionError(f"segment[{i}]", "returns below the lowest position (the program starts there)")
    if abs(level) > 1e-9 * max(1.0, max(s.height for s in out)):
        raise DescriptionError("segment", f"the rises and returns do not cancel over the turn (net {level:g}): the "
                                          "follower must come back to where it started")
    return Program(tuple(out))


def cam_from_dict(data: dict) -> CamMechanism:
    for k in data:
        if k not in _TOP:
            raise DescriptionError(k, f"unknown table; a cam description has {sorted(_TOP)}")
    check_types(data, CAM_FILE, "")
    mech = _table(data, "mechanism", _MECH, {"name"})
    name = check_name(mech["name"], "mechanism.name") if isinstance(mech["name"], str) else None
    if name is None:
        raise DescriptionError("mechanism.name", f"must be a string, got {shown(mech['name'])}")
    cam = _table(data, "cam", _CAM, {"omega"})
    f = _table(data, "follower", _FOLLOWER, {"kind"})
    kind = f["kind"]
    if kind not in ("translating", "oscillating"):
        raise DescriptionError("follower.kind", f"must be \"translating\" or \"oscillating\", got {shown(kind)}")
    osc = kind == "oscillating"
    program = _program(data, osc)
    omega = bounded(angular_speed(cam["omega"], "cam.omega"), "cam.omega", limits.MAX_OMEGA, "rad/s")
    if not omega >= limits.MIN_CAM_OMEGA:
        raise DescriptionError("cam.omega", f"must be at least {limits.MIN_CAM_OMEGA:g} rad/s (the cam turns "
                                            f"counter-clockwise; linkgen's limits, see the README), got {shown(cam['omega'])}")
    rr = non_negative(_length(f.get("roller_radius", 0.0), "follower.roller_radius"), "follower.roller_radius", "m")
    wrong = [k for k in (("pivot_distance", "arm_length", "inertia", "lowest_angle") if not osc
                         else ("offset", "mass")) if k in f]
    if wrong:
        raise DescriptionError(f"follower.{wrong[0]}", f"is not a key of a {kind} follower")
    if osc:
        for k in ("pivot_distance", "arm_length"):
            if k not in f:
                raise DescriptionError(f"follower.{k}", "is required for an oscillating follower")
        a, l = _length(f["pivot_distance"], "follower.pivot_distance"), _length(f["arm_length"], "follower.arm_length")
        if not (a > 0 and l > 0):
            raise DescriptionError("follower", f"pivot_distance and arm_length must be > 0, got {a:g} and {l:g} m")
        if ("base_radius" in cam) == ("lowest_angle" in f):
            raise DescriptionError("cam.base_radius", "give the cam's base_radius or the follower's lowest_angle "
                                                      "(one of them)")
        if "lowest_angle" in f:
            psi = parse_angle(f["lowest_angle"], "follower.lowest_angle")
            r0 = math.sqrt(a * a + l * l - 2 * a * l * math.cos(psi))
            rb = r0 - rr
            if not rb > 0:  # the user gave no base radius: say what is wrong with what they gave
                c = (a * a + l * l - rr * rr) / (2 * a * l)
                least = f"; with this roller it must exceed {math.degrees(math.acos(c)):.6g}°" if abs(c) <= 1 else ""
                raise DescriptionError("follower.lowest_angle", f"puts the roller's centre {r0:.6g} m from the cam's axis, "
                                       f"within the roller's radius {rr:g} m: the cam would have no base circle; give a "
                                       f"larger lowest_angle (the arm's angle at the pivot from the line to the cam's "
                                       f"axis) or a smaller roller_radius{least}")
        else:
            rb = _length(cam["base_radius"], "cam.base_radius")
        fol = Follower(kind, program, rb, rr, pivot_distance=a, arm_length=l)
    else:
        if "base_radius" not in cam:
            raise DescriptionError("cam.base_radius", "is required")
        rb = _length(cam["base_radius"], "cam.base_radius")
        face = f.get("face", "roller")
        if face not in ("roller", "flat"):
            raise DescriptionError("follower.face", f"must be \"roller\" or \"flat\", got {shown(face)}")
        if face == "flat" and rr > 0:
            raise DescriptionError("follower.roller_radius", "a flat-faced follower has no roller: leave it out or 0")
        fol = Follower(kind, program, rb, rr, offset=_length(f.get("offset", 0.0), "follower.offset"), face=face)
    if not rb > 0:
        raise DescriptionError("cam.base_radius", f"must be > 0 m (the base circle inside the roller), got {rb:g}")
    if rb < limits.MIN_LENGTH:
        raise DescriptionError("cam.base_radius", f"must be at least {limits.MIN_LENGTH:g} m (linkgen's limits, see the "
                                                  f"README), got {rb!r}")
    try:
        fol.psi0 if osc else fol.lift_origin
    except ValueError as exc:
        raise DescriptionError("follower", str(exc)) from None
    mass = bounded(non_negative(f.get("mass", 0.0), "follower.mass", "kg"), "follower.mass", limits.MAX_MASS, "kg")
    inertia = bounded(non_negative(f.get("inertia", 0.0), "follower.inertia", "kg·m²"), "follower.inertia",
                      limits.MAX_INERTIA, "kg·m²")
    rate = bounded(non_negative(f.get("spring_rate", 0.0), "follower.spring_rate", "N/m or N·m/rad"),
                   "follower.spring_rate", limits.MAX_FORCE, "N/m or N·m/rad")
    preload = bounded(finite(f.get("spring_preload", 0.0), "follower.spring_preload"), "follower.spring_preload",
                      limits.MAX_FORCE, "N or N·m")
    title = mech.get("title", "")
    if not isinstance(title, str):
        raise DescriptionError("mechanism.title", f"must be a string, got {shown(title)}")
    return CamMechanism(name, title, fol, omega, mass, inertia, rate, preload,
                        tuple(bounded(g, f"mechanism.gravity[{i}]", limits.MAX_GRAVITY, "m/s²") for i, g in
                              enumerate(vector2(mech.get("gravity", [0.0, 0.0]), "mechanism.gravity"))))


__all__ = ["CamMechanism", "cam_from_dict", "is_cam_data", "program_from_table"]
