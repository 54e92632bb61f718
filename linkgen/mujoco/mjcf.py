"""MJCF writer: the validated description as a MuJoCo model with loop-closing constraints.

One body per moving link, its frame the link's local frame placed at the assembled sketch
pose (so every constraint holds at qpos0); hinge/slide joints along a spanning tree that
contains every prismatic pair; an equality ``connect`` for each loop-closing revolute.
The reference pose is the closed form's for an Assembly (or a Mechanism whose structure
decomposes into class-II groups), else the numeric one of ``linkgen.families.planar.pose`` (class III and
higher: MuJoCo needs a spanning tree and connects, not Assur groups).
Output is deterministic: fixed element order, one number format (``%.17g``).

Names. A user's name matches ``[A-Za-z_][A-Za-z0-9_]*``; linkgen uses it as-is only for the
object it names, and every name linkgen makes up contains ``:``, which user names cannot:
    * body = the link's name (ground is MuJoCo's world body); a link named ``world`` (MuJoCo's
      name for the world body) becomes body ``link:world`` (``body_name``/``link_name``);
    * joint = the pair's name (a revolute is named after its point, ``POINT:FIRST-OTHER`` at a
      compound hinge; a prismatic pair by its own name); connect = the closing revolute's name;
    * site = ``POINT`` on the first link that lists the point, ``POINT:LINK`` on the others;
    * sensor ``pos:SITE`` (the site's world position); actuator ``drive:motor`` on the drive joint;
    * tendons ``spring:I`` (the I-th ``[[spring]]``) and ``torsion:I`` (a torsion spring at a
      loop-closing revolute; at a tree joint it is the hinge's own stiffness), ``mujoco.springs``;
    * geoms ``LINK:bar:P-Q`` (a bar from the link's first point P to its point Q),
      ``ground:pivot:P``, ``LINK:block``, ``LINK:dot``, ``LINK:guide:PRISMATIC``; light
      ``light:sun``; materials ``mat:ground``, ``mat:crank``, ``mat:link``, ``mat:slider``.

Geoms are visual only (contype = conaffinity = 0; inertials are explicit) and sized as
fractions of the mechanism's size, so a 2 cm and a 30 m mechanism read the same. A guide runs
along its slider's stroke over the drive's range (``linkgen.mujoco.guides``), as ``linkgen draw``
draws it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from functools import cached_property

import mujoco
import numpy as np
from lxml import etree

from linkgen.families.planar.assembly import Assembly, assemble
from linkgen.families.planar.description import GROUND, MassProperties, Mechanism
from linkgen.errors import (AssemblyError, DescriptionError, LinkgenError, SimulationError, SingularityError,
                            StructureError)
from linkgen.families.planar.plate import convex_hull, hull_area
from linkgen.families.planar.geometry import GuideShape, LinkShape, effective_mass_properties, guide_shapes, link_shapes, sketch_input
from linkgen.families.planar.kinematics import solve
from linkgen.mujoco.options import MESH_VOLUME_MARGIN, MUJOCO_MIN_BAR, MUJOCO_MIN_MESH_VOLUME
from linkgen.mujoco.options import PLACEHOLDER, Settings
from linkgen.families.planar.pose import mechanism_size, reference_pose
from linkgen.mujoco.settings import crank_only, derive
from linkgen.mujoco.friction import HEADER_NOTE as FRICTION_NOTE
from linkgen.mujoco.scene import add_scene, add_scene_assets, add_servo, add_sketch_key, motion_extent, settings_comment
from linkgen.mujoco.tree import DRIVE_ACTUATOR, body_name, sensor_name, site_name, spanning_tree
from linkgen.mujoco.guides import GUIDE_SIZE, guide_span
from linkgen.mujoco.log import no_log_file
from linkgen.mujoco.springs import add_springs

# Integration and constraint settings come from the mechanism (linkgen.mujoco.settings): the loop
# time constant from the predicted loop gap and the crank speed, the timestep from it, the
# rotor inertia (armature of the driven joint, which holds the crank speed) from J(φ). The
# crank is driven by that rotor started at ω, plus a motor torque armature·ε for a constant ε:
# a velocity servo would fight the constraints.

# MuJoCo's compiler (mujoco 4.0, user_model.cc CheckBodyMassInertia) rejects a moving body whose
# mass or any diagonal inertia is below mjMINVAL = 1e-15; measured by bisection on a one-body
# model: mass 1e-15 kg compiles, 9.999999e-16 does not; diaginertia 1e-15 kg·m² compiles, below
# does not. A link's planar inertia I is written as diaginertia (I/2, I/2, I) (a lamina), so the
# written I must be ≥ 2e-15 kg·m².
MUJOCO_MIN_MASS = 1e-15  # kg
MUJOCO_MIN_INERTIA = 1e-15  # kg·m², each diagonal entry
# MuJoCo needs a positive rotational inertia even where the description gives 0 (a point mass,
# or a block that only translates). The floor is mass·(INERTIA_FLOOR·L)², L the link's span (the
# mechanism's size for a one-point link), and at least MuJoCo's own limit: on a rotating link it
# adds at most INERTIA_FLOOR² = 1e-12 of mass·L²·α to the forces (the inverse route's tolerance
# is 1e-10; a floor of 1e-4 showed there as 2e-8), or 2e-15 kg·m²·α where that is larger (tiny
# point masses); a block that only translates never feels it.
INERTIA_FLOOR = 1e-6

# Visual sizes as fractions of the mechanism's size (a 1.2 m four-bar: 12 mm bar radius).
BAR_RADIUS = 0.01
PIVOT_SIZE = (0.02, 0.005)  # radius, half-height
BLOCK_SIZE = (0.03, 0.018, 0.012)  # half-sizes
SITE_SIZE = 0.008
# A bar shorter than its radius would hide inside its end pivots; it is not drawn (a coincident
# tracer point gives none). MuJoCo rejects a capsule whose fromto points are closer than 1e-7 m
# ("fromto points too close", measured by bisection on mujoco 4.0): bars under 10× that are not
# drawn either, whatever the mechanism's size.
MIN_BAR = BAR_RADIUS
# A plate (link of three or more points) is this thin, half-thickness as a fraction of the size,
# and a paler, half-transparent shade of its link's colour so that its bars show through.
PLATE_HALF_THICKNESS = 0.003
PLATE_RGBA = {"mat:crank": "0.95 0.6 0.5 0.6", "mat:link": "0.55 0.7 0.95 0.6"}


def fmt(x: float) -> str:
    x = float(x)
    return "0" if x == 0.0 else repr(x)


def vec(*xs: float) -> str:
    return " ".join(fmt(x) for x in xs)


def written_inertial(mech: Mechanism, shapes: dict[str, LinkShape], link: str) -> MassProperties:
    """A moving link's mass properties as the MJCF gives them: the inertia raised to the floor
    (INERTIA_FLOOR). Raises DescriptionError, naming the field, for a mass MuJoCo cannot take."""
    mp = effective_mass_properties(mech, shapes, link)
    spec = mech.link(link)
    if not mp.mass >= MUJOCO_MIN_MASS:
        field = (f"links.{link}.inertial.mass" if spec.inertial is not None else
                 f"links.{link}.density" if spec.density is not None else f"links.{link}")
        raise DescriptionError(field, f"gives a mass of {mp.mass!r} kg; MuJoCo needs at least {MUJOCO_MIN_MASS:g} kg")
    span = shapes[link].span() or mechanism_size(mech)
    inertia = max(mp.inertia, mp.mass * (INERTIA_FLOOR * span) ** 2, 2 * MUJOCO_MIN_INERTIA)
    return MassProperties(mp.mass, mp.com, inertia)


@dataclass(frozen=True)
class _Source:
    """What the writer reads: the mechanism, shapes, guides and the reference pose
    {link: (origin (2,) [m], angle [rad])}."""

    mech: Mechanism
    shapes: dict[str, LinkShape]
    guides: dict[str, GuideShape]
    pose: dict[str, tuple[np.ndarray, float]]
    size: float

    @cached_property
    def travel(self) -> dict[str, tuple[float, float]]:
        """Each prismatic pair's stroke ends [m] on its guide line over the drive's range (at the
        sketch only where the range cannot be traced)."""
        from linkgen.families.planar.positions import guide_travel, positions

        try:
            return guide_travel(self.mech)
        except LinkgenError:
            sketch = positions(self.mech, [sketch_input(self.mech, self.shapes)])
            return {pair: sketch.travel(pair) for pair in self.guides}


def _source(source: Mechanism | Assembly) -> _Source:
    if isinstance(source, Mechanism):
        try:
            source = assemble(source)
        except StructureError:  # not class II: the numeric pose needs no groups
            mech = source
            ref = reference_pose(mech)
            shapes = link_shapes(mech)
            pose = {n: (ref.origin[n][0], float(ref.angle[n][0])) for n in mech.link_names}
            return _Source(mech, shapes, guide_shapes(mech, shapes), pose, mechanism_size(mech))
    mech = source.mechanism
    ref = solve(source, np.array([source.sketch_phi]))
    pose = {n: (ref.links[n].origin.p[0], float(ref.links[n].angle.v[0])) for n in mech.link_names}
    return _Source(mech, source.shapes, source.guides, pose, mechanism_size(mech))


def settings_for(source: Mechanism | Assembly) -> Settings:
    """Settings derived for the description's own drive (ω at the range's end if ε ≠ 0).
    Without a closed form (groups of class III and higher) they come from the crank speed and
    the masses alone (``crank_only``)."""
    return _derived(source)[0]


@no_log_file()  # MuJoCo's warnings stay out of the user's folder (linkgen.mujoco.log)
def _derived(source: Mechanism | Assembly) -> tuple[Settings, mujoco.MjModel | None]:
    """``settings_for``'s settings and the model compiled to derive them (None without one). Its
    joints and bodies are those of the file written with the settings: the sketch keyframe is set
    on it, and a cam's profile mesh is compiled once, not three times."""
    mech = source if isinstance(source, Mechanism) else source.mechanism
    d = mech.drive
    w_end = math.sqrt(max(d.omega**2 + 2 * d.epsilon * (d.stop - d.start), 0.0))
    omega = max(abs(d.omega), w_end)
    if isinstance(source, Mechanism):
        try:
            source = assemble(source)
        except StructureError:
            return crank_only(mech, omega), None
    model = mujoco.MjModel.from_xml_string(_write(source, PLACEHOLDER, keyframe=False))
    try:
        return derive(source, model, omega=omega, epsilon=d.epsilon)[0], model
    except (SimulationError, SingularityError, AssemblyError):  # a dead centre in the range: no loop forces there
        return replace(crank_only(mech, omega), label="from the crank speed (the range has a singular pose)"), model


def write_mjcf(source: Mechanism | Assembly, settings: Settings | None = None) -> str:
    """The MJCF text of a mechanism (any structure class) or of an assembled one, with
    ``settings`` (default: derived from the mechanism and its drive,
    ``settings_for``)."""
    model = None
    if settings is None:
        settings, model = _derived(source)
    return _write(source, settings, keyframe=True if model is None else model)


def _write(source: Mechanism | Assembly, settings: Settings, keyframe: bool | mujoco.MjModel) -> str:
    """``write_mjcf`` with ``settings``; the sketch keyframe set on a compile of the file (True), on
    ``keyframe``, a model of the same joints and bodies, or left out (False)."""
    src = _source(source)
    mech, pose, size = src.mech, src.pose, src.size
    info = spanning_tree(mech)
    if mech.cams:  # a cam's contact needs the closed form (its profile) and a short enough timestep
        from linkgen.mujoco.cam_pair import cam_settings

        cam_asm = source if isinstance(source, Assembly) else assemble(source)
        settings = cam_settings(cam_asm, settings)

    root = etree.Element("mujoco", model=mech.name)
    etree.SubElement(root, "compiler", angle="radian", inertiafromgeom="false", autolimits="true")
    etree.SubElement(root, "option", timestep=fmt(settings.timestep), integrator=settings.integrator,
                     solver="Newton", iterations=str(settings.iterations), tolerance=fmt(settings.tolerance),
                     gravity=vec(mech.gravity[0], mech.gravity[1], 0.0))
    default = etree.SubElement(root, "default")
    etree.SubElement(default, "geom", contype="0", conaffinity="0", group="0")
    visual = etree.SubElement(root, "visual")
    etree.SubElement(visual, "global", offwidth="1280", offheight="960")
    etree.SubElement(visual, "headlight", ambient="0.25 0.25 0.25", diffuse="0.45 0.45 0.45", specular="0.05 0.05 0.05")
    asset = etree.SubElement(root, "asset")
    add_scene_assets(asset)

    world = etree.SubElement(root, "worldbody")
    etree.SubElement(world, "light", name="light:sun", pos=vec(0.0, 0.0, 5.0 * size), dir="0 0 -1",
                     directional="true", diffuse="0.35 0.35 0.35", specular="0.05 0.05 0.05")
    add_scene(world, motion_extent(src), size)
    _link_visuals(src, world, GROUND, "mat:ground")
    bodies = {GROUND: world}
    for parent, child, pair in info.tree:
        (po, pa), (co, ca) = pose[parent], pose[child]
        c, s = math.cos(pa), math.sin(pa)
        d = co - po
        rel = (c * d[0] + s * d[1], -s * d[0] + c * d[1])
        half = 0.5 * (ca - pa)
        body = etree.SubElement(bodies[parent], "body", name=body_name(child), pos=vec(rel[0], rel[1], 0.0),
                                quat=vec(math.cos(half), 0.0, 0.0, math.sin(half)))
        mp = written_inertial(mech, src.shapes, child)
        etree.SubElement(body, "inertial", pos=vec(mp.com[0], mp.com[1], 0.0), mass=fmt(mp.mass),
                         diaginertia=vec(mp.inertia / 2, mp.inertia / 2, mp.inertia))
        if pair.kind == "R":
            point = mech.revolute(pair.name).point
            local = src.shapes[child].local[point]
            attrs = dict(name=pair.name, type="hinge", pos=vec(local[0], local[1], 0.0), axis="0 0 1")
            if pair.name == mech.drive.joint:
                attrs["armature"] = fmt(settings.armature)
                d = mech.drive
                if d.stop - d.start < 2 * math.pi - 1e-12:  # a viewer's crank stops at the range's ends
                    ref = src.shapes[mech.crank].sketch_angle
                    attrs.update(limited="true", range=vec(d.start - ref, d.stop - ref))
            etree.SubElement(body, "joint", **attrs)
        else:
            g = src.guides[pair.name]
            direction = pose[g.guide][1] + g.alpha - ca
            attrs = dict(name=pair.name, type="slide", axis=vec(math.cos(direction), math.sin(direction), 0.0))
            if pair.name == mech.drive.joint:  # a prismatic drive: its rotor, a viewer's stops at the stroke's ends
                ref = sketch_input(mech, src.shapes)
                attrs.update(armature=fmt(settings.armature), limited="true",
                             range=vec(mech.drive.start - ref, mech.drive.stop - ref))
            etree.SubElement(body, "joint", **attrs)
        material = "mat:crank" if child == mech.crank else (
            "mat:slider" if len(mech.link(child).points) == 1 else "mat:link")
        _link_visuals(src, body, child, material)
        bodies[child] = body

    equality = etree.SubElement(root, "equality")
    for pair in info.closures:
        point = mech.revolute(pair.name).point
        a, b = pair.links
        if a == GROUND:  # body1 must be a body; swap so that world is body2
            a, b = b, a
        local = src.shapes[a].local[point]
        attrs = dict(name=pair.name, anchor=vec(local[0], local[1], 0.0), solref=settings.solref,
                     solimp=settings.solimp_text)
        etree.SubElement(equality, "connect", body1=body_name(a), **({"body2": body_name(b)} if b != GROUND else {}),
                         **attrs)
    for g in mech.gears:  # the planet's pin angle (relative to the crank) is (k − 1) times the crank's
        pin = next(r.name for r in mech.revolutes
                   if r.point == mech.link(g.planet).points[0] and set(r.links) == {mech.crank, g.planet})
        etree.SubElement(equality, "joint", name=f"gear:{g.name}", joint1=pin, joint2=mech.drive.joint,
                         polycoef=vec(0.0, g.ratio - 1.0, 0.0, 0.0, 0.0), solref=settings.solref,
                         solimp=settings.solimp_text)
    actuator = etree.SubElement(root, "actuator")
    etree.SubElement(actuator, "motor", name=DRIVE_ACTUATOR, joint=mech.drive.joint, gear="1")
    add_servo(actuator, mech.drive.joint, settings.armature, mech.drive.omega)
    if mech.cams:
        from linkgen.mujoco.cam_pair import add_cams

        add_cams(root, cam_asm, settings, size)
    add_springs(root, mech, pose, size)
    sensor = etree.SubElement(root, "sensor")
    for link in mech.links:
        for p in link.points:
            etree.SubElement(sensor, "framepos", name=sensor_name(mech, link.name, p), objtype="site",
                             objname=site_name(mech, link.name, p))
    root.insert(0, etree.Comment(settings_comment(settings, mech.slide_drive) + (FRICTION_NOTE if mech.frictions else "")))
    if keyframe is not False:
        add_sketch_key(root, source, mech, None if keyframe is True else keyframe)
    return etree.tostring(root, pretty_print=True, encoding="unicode")


def _plate(src: _Source, body, link: str, pts: list, material: str) -> None:
    """A link of three or more points (not on one line) drawn as a thin plate over their convex hull."""
    hull = convex_hull(pts)
    t = PLATE_HALF_THICKNESS * src.size
    area = hull_area(pts)
    if len(hull) < 3 or area < (MIN_BAR * src.size) ** 2 or 2 * t * area < MESH_VOLUME_MARGIN * MUJOCO_MIN_MESH_VOLUME:
        return  # a drawing only: left out where MuJoCo would reject the mesh as too small
    vertex = " ".join(vec(x, y, z) for z in (-t, t) for x, y in hull)
    asset = body.getroottree().getroot().find("asset")
    etree.SubElement(asset, "mesh", name=f"mesh:{link}", vertex=vertex)
    shade = {"rgba": PLATE_RGBA[material]} if material in PLATE_RGBA else {}
    etree.SubElement(body, "geom", name=f"{link}:plate", type="mesh", mesh=f"mesh:{link}", material=material,
                     **shade)


def _guide(src: _Source, body, link: str, g: GuideShape) -> None:
    """A prismatic pair's guide on its guide link: a bar along the slider's stroke (``guides``)."""
    mid, half = guide_span(*src.travel[g.name], BLOCK_SIZE[0] * src.size, src.size)
    centre = g.base + mid * np.array([math.cos(g.alpha), math.sin(g.alpha)])
    thick = GUIDE_SIZE[1] * src.size
    etree.SubElement(body, "geom", name=f"{link}:guide:{g.name}", type="box", size=vec(half, thick, thick),
                     pos=vec(centre[0], centre[1], -5 * thick), euler=vec(0.0, 0.0, g.alpha), material="mat:ground")


def _link_visuals(src: _Source, body, link: str, material: str) -> None:
    mech, size = src.mech, src.size
    shape = src.shapes[link]
    names = mech.link(link).points
    pts = [shape.local[p] for p in names]
    if link == GROUND:
        for p, xy in zip(names, pts):
            etree.SubElement(body, "geom", name=f"{GROUND}:pivot:{p}", type="cylinder",
                             size=vec(PIVOT_SIZE[0] * size, PIVOT_SIZE[1] * size),
                             pos=vec(xy[0], xy[1], -2 * PIVOT_SIZE[1] * size), material=material)
    elif len(pts) == 1:
        etree.SubElement(body, "geom", name=f"{link}:block", type="box", size=vec(*(h * size for h in BLOCK_SIZE)),
                         pos=vec(pts[0][0], pts[0][1], 0.0), material=material)
    else:
        bars = [(q, xy) for q, xy in zip(names[1:], pts[1:])
                if math.hypot(xy[0] - pts[0][0], xy[1] - pts[0][1]) >= max(MIN_BAR * size, MUJOCO_MIN_BAR)]
        for q, xy in bars:
            etree.SubElement(body, "geom", name=f"{link}:bar:{names[0]}-{q}", type="capsule",
                             size=fmt(BAR_RADIUS * size),
                             fromto=vec(pts[0][0], pts[0][1], 0.0, xy[0], xy[1], 0.0), material=material)
        _plate(src, body, link, pts, material)
        if not bars:  # every point within a bar radius of the first
            etree.SubElement(body, "geom", name=f"{link}:dot", type="sphere", size=fmt(BAR_RADIUS * size),
                             pos=vec(pts[0][0], pts[0][1], 0.0), material=material)
    for pj in mech.prismatics:
        if pj.guide == link:
            _guide(src, body, link, src.guides[pj.name])
    for p, xy in zip(names, pts):
        etree.SubElement(body, "site", name=site_name(mech, link, p), pos=vec(xy[0], xy[1], 0.0),
                         size=fmt(SITE_SIZE * size))
