"""Strict TOML loader: every table and key is checked; unknown keys are errors."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from linkgen.families.planar.description import (
    CamPair,
    Drive,
    Friction,
    Gear,
    Link,
    LinkTorque,
    MassProperties,
    Mechanism,
    PointForce,
    Prismatic,
    Spring,
    TorsionSpring,
)
from linkgen.model.machine import machine_from_dict
from linkgen.model.toml_file import MAX_FILE_BYTES, parse_toml, read_bytes  # noqa: F401 (MAX_FILE_BYTES: its old home)
from linkgen.model.names import GROUND, check_name
from linkgen.model.schema import PLANAR, check as check_types
from linkgen.errors import DescriptionError
from linkgen.model.units import (angular_acceleration, angular_speed, finite, length, linear_acceleration, linear_speed,
                                 parse_angle, point2, shown, vector2)

_TOP = {"mechanism", "points", "links", "prismatic", "drive", "force", "torque", "machine", "gear", "cam", "spring",
        "torsion_spring", "friction"}
_FRICTION = {"pair", "coefficient", "pin_radius", "block_length"}
_SPRING = {"points", "stiffness", "rest_length", "damping"}
_TORSION = {"joint", "links", "stiffness", "rest_angle", "damping"}
_CAM = {"follower", "roller", "roller_radius", "spring_rate", "spring_preload", "segment", "law"}
_GEAR = {"planet", "kind", "module", "teeth", "pressure_angle"}
_MECH = {"name", "title", "gravity"}
_LINK = {"points", "length", "inertial", "density", "shape", "areal_density"}
_INERTIAL = {"mass", "com", "inertia"}
_PRISMATIC = {"slider", "guide", "point", "through", "angle", "offset"}
_DRIVE = {"joint", "omega", "epsilon", "range"}
_SLIDE_DRIVE = {"joint", "velocity", "acceleration", "start", "stop"}
_FORCE = {"link", "point", "force", "stroke"}
_TORQUE = {"link", "torque"}


def _table(value: Any, where: str) -> dict:
    if not isinstance(value, dict):
        raise DescriptionError(where, f"must be a table, got {shown(value)}")
    return value


def _keys(table: dict, allowed: set[str], required: set[str], where: str) -> None:
    for key in table:
        if key not in allowed:
            name = key if len(key) <= 60 else shown(key)  # a hostile file's key may be megabytes long
            raise DescriptionError(f"{where}.{name}", f"unknown key; allowed keys: {sorted(allowed)}")
    for key in sorted(required):
        if key not in table:
            raise DescriptionError(f"{where}.{key}", "is required")


def _str(value: Any, where: str) -> str:
    if not isinstance(value, str):
        raise DescriptionError(where, f"must be a string, got {shown(value)}")
    return value


def load(path: str | Path) -> Mechanism:
    """Read and validate a TOML description (UTF-8, with or without a byte-order mark).

    Raises:
        DescriptionError: with ``source`` = the file, for a missing or unreadable file, one that
            is not a regular file or is too large, bytes that are not UTF-8 text, invalid or too
            deeply nested TOML (linkgen.model.toml_file), and every problem found while
            building the Mechanism from it.
    """
    return loads(read_bytes(path), str(path))


def loads(raw: bytes | str, source: str = "<description>") -> Mechanism:
    """A planar Mechanism from the bytes (or text) of a TOML description; errors name ``source``.
    (``linkgen.load`` opens every family's descriptions: ``linkgen.pipeline.registry``.)"""
    data = parse_toml(raw, source)
    try:
        mech = from_dict(data)
        machine_from_dict(data)  # checked with the rest; linkgen.machine reads it
        if mech.slide_drive and "machine" in data:
            raise DescriptionError("machine", f"a machine's motor turns a crank; the drive {mech.drive.joint!r} is a "
                                              f"prismatic pair (a linear actuator): leave [machine] out")
        return mech
    except DescriptionError as exc:
        raise exc.in_file(source) from None


def from_dict(data: dict) -> Mechanism:
    """Build a Mechanism from the parsed TOML structure."""
    if isinstance(data, dict) and "cam" in data and "links" not in data:
        raise DescriptionError("cam", "a [cam] table without [links] describes a stand-alone cam (docs/cams.md), "
                                      "not a planar linkage; linkgen.load opens it")
    given = data.get("mechanism") if isinstance(data, dict) else None
    if isinstance(given, dict) and given.get("space", "planar") != "planar":
        raise DescriptionError("mechanism.space", f"must be \"spatial\" (a spatial four-bar, docs/spatial.md) or "
                                                  f"\"planar\" (the default), got {shown(given['space'])}")
    if isinstance(data, dict) and "joints" in data:
        raise DescriptionError("joints", "[joints] tables describe a spatial model: add space = \"spatial\" to "
                                         "[mechanism] (docs/spatial.md); a planar linkage's revolutes are the points "
                                         "its links share")
    check_types(data, PLANAR, "")
    _keys(data, _TOP, {"mechanism", "points", "links", "drive"}, "description")
    mech = _table(data["mechanism"], "mechanism")
    _keys(mech, _MECH | {"space"}, {"name"}, "mechanism")
    points = {
        check_name(name, f"points.{name}"): point2(xy, f"points.{name}")
        for name, xy in _table(data["points"], "points").items()
    }
    links = tuple(_link(name, spec) for name, spec in _table(data["links"], "links").items())
    prismatics = tuple(
        _prismatic(name, spec) for name, spec in _table(data.get("prismatic", {}), "prismatic").items()
    )
    return Mechanism(
        name=_str(mech["name"], "mechanism.name"),
        title=_str(mech.get("title", ""), "mechanism.title"),
        points=points,
        links=links,
        prismatics=prismatics,
        drive=_drive(_table(data["drive"], "drive"), {p.name for p in prismatics}),
        gravity=vector2(mech.get("gravity", [0.0, 0.0]), "mechanism.gravity"),
        forces=tuple(_force(i, f) for i, f in enumerate(_list(data.get("force", []), "force"))),
        torques=tuple(_torque(i, t) for i, t in enumerate(_list(data.get("torque", []), "torque"))),
        gears=tuple(_gear(name, spec) for name, spec in _table(data.get("gear", {}), "gear").items()),
        cams=tuple(_cam(name, spec, data) for name, spec in _table(data.get("cam", {}), "cam").items()),
        springs=tuple(_spring(i, s) for i, s in enumerate(_list(data.get("spring", []), "spring"))),
        torsion_springs=tuple(_torsion(i, s) for i, s in enumerate(_list(data.get("torsion_spring", []),
                                                                         "torsion_spring"))),
        frictions=tuple(_friction(i, f) for i, f in enumerate(_list(data.get("friction", []), "friction"))),
    )


def _names2(value: Any, where: str) -> tuple[str, str]:
    if not (isinstance(value, list) and len(value) == 2):
        raise DescriptionError(where, f"must be two names [first, second], got {shown(value)}")
    return _str(value[0], f"{where}[0]"), _str(value[1], f"{where}[1]")


def _spring(i: int, spec: Any) -> Spring:
    where = f"spring[{i}]"
    t = _table(spec, where)
    _keys(t, _SPRING, {"points", "stiffness", "rest_length"}, where)
    return Spring(_names2(t["points"], f"{where}.points"), finite(t["stiffness"], f"{where}.stiffness"),
                  length(t["rest_length"], f"{where}.rest_length"), finite(t.get("damping", 0.0), f"{where}.damping"))


def _torsion(i: int, spec: Any) -> TorsionSpring:
    where = f"torsion_spring[{i}]"
    t = _table(spec, where)
    _keys(t, _TORSION, {"joint", "links", "stiffness"}, where)
    rest = parse_angle(t["rest_angle"], f"{where}.rest_angle") if "rest_angle" in t else None
    return TorsionSpring(_str(t["joint"], f"{where}.joint"), _names2(t["links"], f"{where}.links"),
                         finite(t["stiffness"], f"{where}.stiffness"), rest,
                         finite(t.get("damping", 0.0), f"{where}.damping"))


def _friction(i: int, spec: Any) -> Friction:
    where = f"friction[{i}]"
    t = _table(spec, where)
    _keys(t, _FRICTION, {"pair", "coefficient"}, where)
    radius, block = (length(t[k], f"{where}.{k}") if k in t else None for k in ("pin_radius", "block_length"))
    return Friction(_str(t["pair"], f"{where}.pair"), finite(t["coefficient"], f"{where}.coefficient"), radius, block)


def _cam(name: str, spec: Any, data: dict) -> CamPair:
    """A ``[cam.NAME]`` pair: the follower's kind (oscillating or translating) is that of its pair
    with the ground, which sets the program's unit (angles or lengths)."""
    from linkgen.families.cam.description import program_from_table

    where = f"cam.{name}"
    t = _table(spec, where)
    _keys(t, _CAM, {"follower", "roller"}, where)
    follower = _str(t["follower"], f"{where}.follower")
    prismatic = _table(data.get("prismatic", {}), "prismatic")
    slides = any(isinstance(p, dict) and {p.get("slider"), p.get("guide")} == {follower, GROUND}
                 for p in prismatic.values())
    return CamPair(check_name(name, where), follower, _str(t["roller"], f"{where}.roller"),
                   program_from_table(t, not slides, where),
                   length(t.get("roller_radius", 0.0), f"{where}.roller_radius"),
                   finite(t.get("spring_rate", 0.0), f"{where}.spring_rate"),
                   finite(t.get("spring_preload", 0.0), f"{where}.spring_preload"))


def _gear(name: str, spec: Any) -> Gear:
    where = f"gear.{name}"
    t = _table(spec, where)
    _keys(t, _GEAR, {"planet", "kind", "module", "teeth"}, where)
    teeth = t["teeth"]
    if not (isinstance(teeth, list) and len(teeth) == 2 and all(isinstance(z, int) and not isinstance(z, bool)
                                                                for z in teeth)):
        raise DescriptionError(f"{where}.teeth", f"must be [z_fixed, z_planet], two whole numbers, got {shown(teeth)}")
    return Gear(check_name(name, where), _str(t["planet"], f"{where}.planet"), _str(t["kind"], f"{where}.kind"),
                length(t["module"], f"{where}.module"), (teeth[0], teeth[1]),
                parse_angle(t.get("pressure_angle", "20deg"), f"{where}.pressure_angle"))


def _list(value: Any, where: str) -> list:
    if not isinstance(value, list):
        raise DescriptionError(where, f"must be an array of tables ([[{where}]]), got {shown(value)}")
    return value


def _link(name: str, spec: Any) -> Link:
    where = f"links.{name}"
    spec = _table(spec, where)
    _keys(spec, _LINK, {"points"}, where)
    pts = spec["points"]
    if not isinstance(pts, list):
        raise DescriptionError(f"{where}.points", f"must be a list of point names, got {shown(pts)}")
    inertial = None
    if "inertial" in spec:
        t = _table(spec["inertial"], f"{where}.inertial")
        _keys(t, _INERTIAL, _INERTIAL, f"{where}.inertial")
        inertial = MassProperties(
            mass=finite(t["mass"], f"{where}.inertial.mass"),
            com=point2(t["com"], f"{where}.inertial.com"),
            inertia=finite(t["inertia"], f"{where}.inertial.inertia"),
        )
    shape = None
    if "shape" in spec:
        shape = {p: point2(xy, f"{where}.shape.{p}") for p, xy in _table(spec["shape"], f"{where}.shape").items()}
    return Link(
        name=name,
        shape=shape,
        points=tuple(_str(p, f"{where}.points[{i}]") for i, p in enumerate(pts)),
        length=length(spec["length"], f"{where}.length") if "length" in spec else None,
        inertial=inertial,
        density=finite(spec["density"], f"{where}.density") if "density" in spec else None,
        areal_density=finite(spec["areal_density"], f"{where}.areal_density") if "areal_density" in spec else None,
    )


def _prismatic(name: str, spec: Any) -> Prismatic:
    where = f"prismatic.{name}"
    spec = _table(spec, where)
    _keys(spec, _PRISMATIC, {"slider", "guide", "point", "through"}, where)
    return Prismatic(
        name=name,
        slider=_str(spec["slider"], f"{where}.slider"),
        guide=_str(spec["guide"], f"{where}.guide"),
        point=_str(spec["point"], f"{where}.point"),
        through=_str(spec["through"], f"{where}.through"),
        angle=parse_angle(spec.get("angle", 0.0), f"{where}.angle"),
        offset=length(spec.get("offset", 0.0), f"{where}.offset"),
    )


def _drive(spec: dict, slides: set[str] = frozenset()) -> Drive:
    """A revolute's drive (``omega``, ``epsilon``, ``range``), or a prismatic pair's (``joint`` naming a
    ``[prismatic.NAME]``: ``velocity`` [m/s], ``acceleration`` [m/s²], the stroke's ``start`` and
    ``stop`` [m])."""
    given = _SLIDE_DRIVE - {"joint"} & set(spec)
    if given and "omega" not in spec and spec.get("joint") not in slides:
        raise DescriptionError("drive.joint", f"unknown prismatic pair {shown(spec.get('joint'))}: a drive given by "
                                              f"{', '.join(sorted(given))} slides along a [prismatic.NAME] pair; "
                                              f"prismatic pairs: {sorted(slides)}")
    if spec.get("joint") in slides:
        _keys(spec, _SLIDE_DRIVE, {"joint", "velocity", "start", "stop"}, "drive")
        return Drive(joint=spec["joint"], omega=linear_speed(spec["velocity"], "drive.velocity"),
                     epsilon=linear_acceleration(spec.get("acceleration", 0.0), "drive.acceleration"),
                     start=length(spec["start"], "drive.start"), stop=length(spec["stop"], "drive.stop"))
    _keys(spec, _DRIVE, {"joint", "omega"}, "drive")
    start, stop = 0.0, None
    if "range" in spec:
        r = spec["range"]
        if not isinstance(r, list) or len(r) != 2:
            raise DescriptionError("drive.range", f"must be [from, to], got {shown(r)}")
        start, stop = parse_angle(r[0], "drive.range[0]"), parse_angle(r[1], "drive.range[1]")
    kwargs = {} if stop is None else {"start": start, "stop": stop}
    return Drive(
        joint=_str(spec["joint"], "drive.joint"),
        omega=angular_speed(spec["omega"], "drive.omega"),
        epsilon=angular_acceleration(spec.get("epsilon", 0.0), "drive.epsilon"),
        **kwargs,
    )


def _force(i: int, spec: Any) -> PointForce:
    where = f"force[{i}]"
    spec = _table(spec, where)
    _keys(spec, _FORCE, {"link", "point", "force"}, where)
    stroke = None
    if "stroke" in spec:
        s = spec["stroke"]
        if not isinstance(s, list) or len(s) != 2:
            raise DescriptionError(f"{where}.stroke", f"must be [from, to], got {shown(s)}")
        stroke = (parse_angle(s[0], f"{where}.stroke[0]"), parse_angle(s[1], f"{where}.stroke[1]"))
    return PointForce(
        link=_str(spec["link"], f"{where}.link"),
        point=_str(spec["point"], f"{where}.point"),
        force=vector2(spec["force"], f"{where}.force"),
        stroke=stroke,
    )


def _torque(i: int, spec: Any) -> LinkTorque:
    where = f"torque[{i}]"
    spec = _table(spec, where)
    _keys(spec, _TORQUE, _TORQUE, where)
    return LinkTorque(link=_str(spec["link"], f"{where}.link"), torque=finite(spec["torque"], f"{where}.torque"))
