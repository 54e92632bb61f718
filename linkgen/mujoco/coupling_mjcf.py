"""The loop-free MJCF (``linkgen build --loops coupling``): the tree of ``coupling.Coupling``, its
bodies placed at the drive range's middle, every joint but the crank's tied by a joint equality
(``polycoef``) to the joint it follows, and a header saying what the file is and how near it is.

Names are the validation model's (``mjcf``): bodies after their links, joints after their pairs,
sites, sensors ``pos:SITE``, the actuator ``drive:motor``; the couplings are equalities
``couple:JOINT``. No servo and no rotor inertia: the crank's hinge carries only what MuJoCo's
motor ``drive:motor`` applies.
"""

from __future__ import annotations

import math

from lxml import etree

from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.description import GROUND, Mechanism
from linkgen.families.planar.geometry import guide_shapes, link_shapes
from linkgen.families.planar.pose import mechanism_size
from linkgen.mujoco.coupling import TOLERANCE, Coupling
from linkgen.mujoco.coupling_torque import lag as lags
from linkgen.mujoco.mjcf import _link_visuals, _Source, fmt, vec, written_inertial
from linkgen.mujoco.options import Settings
from linkgen.mujoco.scene import add_scene, add_scene_assets, motion_extent
from linkgen.mujoco.tree import DRIVE_ACTUATOR, body_name, sensor_name, site_name

COUPLE = "couple:"  # an equality's name: COUPLE + the coupled joint's
# The least Newton tolerance written. linkgen's validation settings ask for 0 (iterate until no
# improvement), which the loop model meets in one iteration a step; the couplings' nonlinear rows
# never quite stop improving: 19 iterations a step on the seven-link at 4 rad/s (1 at 1e-10), 5x
# slower, for no change in its figures (the tests' lag and torque read the same to 2 digits).
MIN_TOLERANCE = 1e-10


def header(c: Coupling, mech: Mechanism, settings: Settings) -> str:
    """The file's comment: what it holds and what it leaves out, its settings and its error."""
    lo, hi = (math.degrees(a) for a in c.drive_range)
    lines = [
        f" {mech.name}: loop-free model for robot learning (linkgen build, loops coupling). The loops are not closed:",
        f" the pairs {', '.join(c.left_out)} are left out, and every joint but the crank's follows the joint named in",
        " its equality couple:JOINT by MuJoCo's joint equality, y - y0 = polycoef(x - x0) (y0, x0 the joints' ref),",
        " a quartic fitted by minimax (least largest error) over the drive range. Every link keeps its mass, inertia",
        " and weight on its own body (couplers and blocks too, on their coupled joints).",
        " Outputs (the links a pair joins to the ground, each on its own joint): "
        + ", ".join(f"{j.child} ({j.name})" for j in c.outputs) + ".",
        f" Valid over the crank angles {lo:.6g}..{hi:.6g} deg only: the crank joint {c.drive} is limited to them.",
        f" Joints read: {c.drive} the crank angle [rad]; a hinge to the ground its link's angle [rad]; a hinge",
        " between moving links the child's angle less the parent's [rad]; a slide the slider's displacement along",
        " its guide from the guide's base point [m] (as linkgen analyze gives them).",
        f" Largest position error over the range against linkgen's closed form (bound {TOLERANCE:g} of the travel):",
    ]
    lines += [f"   {j.describe()}, worst at {math.degrees(j.at):.4g} deg" for j in c.joints]
    omega = mech.drive.omega
    lag = lags(c, settings.timeconst, omega)
    worst = max(lag, key=lag.get)
    unit = next(j.unit for j in c.joints if j.name == worst)
    lines += [" Add MuJoCo's lag: its joint equality holds y = p(x) by a spring of stiffness 1/tau^2 and leaves out",
              " the curvature term p''(x)*xdot^2, so a moving coupling lags by about tau^2*|p''|*xdot^2 (it grows with",
              f" the square of the speed and of tau): at the drive's {omega:g} rad/s and tau = {settings.timeconst:g} s, up"
              f" to {lag[worst]:.2g} {unit} ({worst}); lags of chained couplings add up, and at a robot's settings (timestep"
              f" 2 ms, MuJoCo's default solref 0.02 s) tau is {0.02 / settings.timeconst:.3g} times this one, the lag"
              f" {(0.02 / settings.timeconst) ** 2:.3g} times."]
    if c.torque is not None:
        lines.append(f" Dynamics: {c.torque.text()}, worst at {math.degrees(c.torque.at):.4g} deg (MuJoCo's inverse")
        lines.append(" dynamics along the couplings, no acceleration, the loads applied): a quartic's slope and curvature")
        lines.append(" err most at the ends of its range.")
    else:
        lines.append(" Dynamics: not compared (no closed form for this mechanism's forces).")
    loads = [f"[[force]] {f.force[0]:g}, {f.force[1]:g} N at {f.point} on {f.link}" for f in mech.forces]
    loads += [f"[[torque]] {t.torque:g} N·m on {t.link}" for t in mech.torques]
    if loads:
        lines.append(" Not in the file (MJCF carries no such loads): " + "; ".join(loads)
                     + "; apply them each step: data.qfrc_applied[:] = 0, then for a force F at a point, "
                     "mujoco.mj_applyFT(model, data, F, [0, 0, 0], data.site(POINT).xpos, model.body(LINK).id, "
                     "data.qfrc_applied) (a torque M: mj_applyFT with [0, 0, 0], [0, 0, M] at the body's xipos); "
                     "data.xfrc_applied would act at the body's centre of mass.")
    lines.append(f" Settings: timestep {settings.timestep:g} s ({settings.integrator}), Newton tolerance "
                 f"{max(settings.tolerance, MIN_TOLERANCE):g}, couplings with solref "
                 f"{settings.solref}, solimp {settings.solimp_text} ({settings.label}). Drive: the motor {DRIVE_ACTUATOR}"
                 f" (torque [N·m] = ctrl), no servo, no rotor inertia. ")
    return "\n".join(lines)


def write_coupled(source: Mechanism | Assembly, c: Coupling, settings: Settings) -> str:
    """The loop-free MJCF text of ``source`` with the couplings ``c`` and ``settings`` (timestep,
    integrator, the equalities' solref and solimp; its armature is not written)."""
    mech = source if isinstance(source, Mechanism) else source.mechanism
    shapes = link_shapes(mech)
    size = mechanism_size(mech)
    src = _Source(mech, shapes, guide_shapes(mech, shapes), c.pose, size)
    root = etree.Element("mujoco", model=mech.name)
    etree.SubElement(root, "compiler", angle="radian", inertiafromgeom="false", autolimits="true")
    etree.SubElement(root, "option", timestep=fmt(settings.timestep), integrator=settings.integrator,
                     solver="Newton", iterations=str(settings.iterations),
                     tolerance=fmt(max(settings.tolerance, MIN_TOLERANCE)),
                     gravity=vec(mech.gravity[0], mech.gravity[1], 0.0))
    default = etree.SubElement(root, "default")
    etree.SubElement(default, "geom", contype="0", conaffinity="0", group="0")
    asset = etree.SubElement(root, "asset")
    add_scene_assets(asset)
    world = etree.SubElement(root, "worldbody")
    etree.SubElement(world, "light", name="light:sun", pos=vec(0.0, 0.0, 5.0 * size), dir="0 0 -1",
                     directional="true", diffuse="0.35 0.35 0.35", specular="0.05 0.05 0.05")
    add_scene(world, motion_extent(src), size)
    _link_visuals(src, world, GROUND, "mat:ground")
    refs = {j.name: j for j in c.joints}
    bodies = {GROUND: world}
    for parent, child, pair in c.tree:
        (po, pa), (co, ca) = c.pose[parent], c.pose[child]
        cs, sn = math.cos(pa), math.sin(pa)
        d = co - po
        half = 0.5 * (ca - pa)
        body = etree.SubElement(bodies[parent], "body", name=body_name(child),
                                pos=vec(cs * d[0] + sn * d[1], -sn * d[0] + cs * d[1], 0.0),
                                quat=vec(math.cos(half), 0.0, 0.0, math.sin(half)))
        mp = written_inertial(mech, shapes, child)
        etree.SubElement(body, "inertial", pos=vec(mp.com[0], mp.com[1], 0.0), mass=fmt(mp.mass),
                         diaginertia=vec(mp.inertia / 2, mp.inertia / 2, mp.inertia))
        if pair.kind == "R":
            local = shapes[child].local[mech.revolute(pair.name).point]
            attrs = dict(name=pair.name, type="hinge", pos=vec(local[0], local[1], 0.0), axis="0 0 1")
            if pair.name == mech.drive.joint:
                attrs.update(ref=fmt(c.phi_ref), range=vec(*c.drive_range))
            else:
                attrs["ref"] = fmt(refs[pair.name].ref)
        else:
            g = src.guides[pair.name]
            sign = 1.0 if child == g.slider else -1.0  # the joint reads the slider's displacement either way
            direction = c.pose[g.guide][1] + g.alpha - ca
            attrs = dict(name=pair.name, type="slide", axis=vec(sign * math.cos(direction), sign * math.sin(direction), 0.0),
                         ref=fmt(refs[pair.name].ref))
        etree.SubElement(body, "joint", **attrs)
        material = "mat:crank" if child == mech.crank else (
            "mat:slider" if len(mech.link(child).points) == 1 else "mat:link")
        _link_visuals(src, body, child, material)
        bodies[child] = body
    equality = etree.SubElement(root, "equality")
    for j in c.joints:
        etree.SubElement(equality, "joint", name=COUPLE + j.name, joint1=j.name, joint2=j.argument,
                         polycoef=vec(*j.fit.coef), solref=settings.solref, solimp=settings.solimp_text)
    actuator = etree.SubElement(root, "actuator")
    etree.SubElement(actuator, "motor", name=DRIVE_ACTUATOR, joint=mech.drive.joint, gear="1")
    sensor = etree.SubElement(root, "sensor")
    for link in mech.links:
        for p in link.points:
            etree.SubElement(sensor, "framepos", name=sensor_name(mech, link.name, p), objtype="site",
                             objname=site_name(mech, link.name, p))
    root.insert(0, etree.Comment(header(c, mech, settings)))
    return etree.tostring(root, pretty_print=True, encoding="unicode")


__all__ = ["COUPLE", "MIN_TOLERANCE", "header", "write_coupled"]
