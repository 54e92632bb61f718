"""The robot-ready MJCF (``linkgen build --robot``): the validation model (``mjcf``,
``spatial_mjcf``) made into one a robotics user drives, attaches to a robot and reads.

What changes against the validation build:
    * every name begins with the prefix (``robot_xml.add_prefix``), default ``NAME/``;
    * the mechanism hangs under one fixed body ``PREFIXmount`` (the ground link's geoms and sites
      and every moving link) that ``MjSpec.attach`` or ``<attach>`` places on any body of a robot;
      its quaternion turns the description's plane onto the world plane asked for, in a z-up world
      whose gravity is the description's turned the same way (the description's gravity onto −z);
    * no speed servo and no validation rotor inertia: one actuator on the driven joint (motor,
      position or velocity; ``drive_actuator``) and only the rotor inertia the description's
      [machine] gives (rotor through its gear ratio², and flywheel) as the joint's armature;
    * the driven hinge's angle is the description's crank angle φ (``ref`` = the sketch's φ);
    * MuJoCo's own settings: timestep 2 ms, ``implicitfast`` (``ROBOT_TIMESTEP``), the loop
      ``connect``s with MuJoCo's default solref/solimp (the scene's ``<default>`` sets them);
    * sensors: the drive's actuator force and joint torque, and each revolute's reaction
      (``robot_sensors``), read by ``robot_sensors.reactions``;
    * no floor, sky, light or camera unless asked (``scene``); a keyframe ``PREFIXsketch`` at rest.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import numpy as np
from lxml import etree

from linkgen.errors import ArgumentError
from linkgen.mujoco.options import Settings
from linkgen.mujoco.robot_accuracy import FAR_OFF, SERVO_FACTORS, accuracy_comment, predict_at
from linkgen.mujoco.robot_xml import PLANES, check_prefix

ACTUATORS = ("motor", "position", "velocity")
# MuJoCo's defaults and what robot users run: timestep 2 ms (MuJoCo's default), the
# ``implicitfast`` integrator (MuJoCo's recommendation for robots: it integrates the actuators'
# damping kv and the joints' damping implicitly, so a stiff position servo stays stable at 2 ms,
# at Euler's cost per step).
ROBOT_TIMESTEP = 0.002  # s
ROBOT_INTEGRATOR = "implicitfast"
# The settings the robot file states, as linkgen's Settings (for the accuracy line): MuJoCo's
# defaults for the loop constraints (solref "0.02 1", solimp "0.9 0.95 0.001 0.5 2"), solver
# (Newton, 100 iterations, tolerance 1e-8); no rotor inertia of linkgen's own.
ROBOT_SETTINGS = Settings(timestep=ROBOT_TIMESTEP, timeconst=0.02, impedance=0.9, integrator=ROBOT_INTEGRATOR,
                          iterations=100, tolerance=1e-8, armature=0.0, solimp=(0.9, 0.95, 0.001, 0.5, 2.0),
                          label="MuJoCo's defaults (robot build)")
# The actuator's torque limits are the closed form's peak balancing torque over the drive range
# (at the description's ω, ε, with its gravity and loads) times this margin: 50 % above what the
# description's own duty needs, for faster accelerations than the description's ε.
TORQUE_MARGIN = 1.5
# Default position servo: natural frequency ω_n = max(POSITION_BANDWIDTH, BANDWIDTH_PER_SPEED·|ω|)
# [rad/s] on the largest reduced inertia J over the range (kp = J·ω_n², critically damped
# kv = 2·J·ω_n). 5 Hz is a common joint position loop; a crank turning faster than that needs a
# loop a few times its own speed to follow it, hence 4·|ω|.
POSITION_BANDWIDTH = 2 * math.pi * 5.0  # rad/s
BANDWIDTH_PER_SPEED = 4.0
# Crank angles over the drive range at which the peak torque and the largest inertia are taken
# (every 1° of a full turn).
PEAK_SAMPLES = 361


@dataclass(frozen=True)
class RobotOptions:
    """What ``build --robot`` writes. ``prefix`` None: the mechanism's name and "/";
    ``actuator`` on the driven joint with ``gear`` (torque = gear·force) and the servo's
    ``kp`` [N·m/rad], ``kv`` [N·m·s/rad] at the joint, whatever the gear (None: derived,
    ``drive_actuator``);
    ``plane`` None: "xz" (planar linkages; a spatial chain takes none); ``scene``: a floor, sky,
    light and camera; ``rotor_inertia`` [kg·m²]: the drive's own (the CLI reads the [machine]);
    ``machine``: the description's [machine] (``linkgen.model.machine.Machine``), whose motor law,
    process load, shaft and start speed the header says how to apply (``robot_machine``)."""

    prefix: str | None = None
    actuator: str = "motor"
    gear: float = 1.0
    kp: float | None = None
    kv: float | None = None
    plane: str | None = None
    scene: bool = False
    rotor_inertia: float = 0.0
    machine: object | None = None

    def __post_init__(self) -> None:
        if self.prefix is not None:
            check_prefix(self.prefix)
        if self.actuator not in ACTUATORS:
            raise ArgumentError(f"--actuator {self.actuator!r}: one of {', '.join(ACTUATORS)}")
        if self.plane is not None and self.plane not in PLANES:
            raise ArgumentError(f"--plane {self.plane!r}: the mechanism's plane is one of {', '.join(PLANES)} in a "
                                "z-up world")
        for name, value in (("--gear", self.gear), ("--kp", self.kp), ("--kv", self.kv),
                            ("rotor_inertia", self.rotor_inertia)):
            if value is not None and not (math.isfinite(value) and (value > 0 or name == "rotor_inertia" and value == 0)):
                raise ArgumentError(f"{name} {value!r}: a finite number above 0")
        if self.kp is not None and self.actuator != "position":
            raise ArgumentError("--kp is the position servo's stiffness: give it with --actuator position")
        if self.kv is not None and self.actuator == "motor":
            raise ArgumentError("--kv is the position or velocity servo's gain: give it with --actuator position or "
                                "--actuator velocity")


@dataclass(frozen=True)
class RobotDrive:
    """What the robot build needs from a family's closed form: the driven joint, the sketch's
    crank angle [rad], the drive range (None: a full turn), the peak balancing torque over it
    [N·m] (None: no closed form) with the speed [rad/s] it was taken at, the largest reduced
    inertia [kg·m²], the revolutes whose reactions get sensors (``robot_sensors.Reaction``),
    the description's gravity (3,) [m/s²] in its own frame, what MJCF leaves out and what else
    the header says (text)."""

    family: str
    joint: str
    sketch: float
    range: tuple[float, float] | None
    peak_torque: float | None
    omega: float
    inertia: float
    reactions: tuple
    gravity: tuple[float, float, float]
    loads: tuple[str, ...] = ()
    notes: tuple[str, ...] = ()


def drive_actuator(drive: RobotDrive, opt: RobotOptions) -> tuple[str, dict, str]:
    """The actuator element's tag, attributes (but its name and joint) and the header's words.

    ``opt.kp``, ``opt.kv`` and the derived defaults are the servo's stiffness [N·m/rad] and
    damping [N·m·s/rad] at the joint; MuJoCo's actuator with gear g acts on the length g·φ and
    exerts g times its force on the joint, so the joint feels g²·kp: the file holds kp/g², kv/g²
    (and ctrlrange, forcerange) in the actuator's units."""
    g = opt.gear
    j = drive.inertia + opt.rotor_inertia
    wn = max(POSITION_BANDWIDTH, BANDWIDTH_PER_SPEED * abs(drive.omega))
    limit = None if not drive.peak_torque else TORQUE_MARGIN * drive.peak_torque / g
    peak = (f"the closed form's peak balancing torque {drive.peak_torque:.6g} N·m over the drive range at "
            f"ω = {drive.omega:.6g} rad/s × {TORQUE_MARGIN:g}, / gear" if limit else
            f"none: the closed form's balancing torque at ω = {drive.omega:.6g} rad/s is 0 N·m over the whole drive "
            "range (nothing to lift, accelerate or press), so the file sets no limit; give the actuator your motor's"
            if drive.peak_torque == 0 else
            "none: the closed form gives no balancing torque for this mechanism, so the file sets no limit; give the "
            "actuator your motor's")
    attrs = {"gear": _f(g)}
    if opt.actuator == "motor":
        if limit:
            attrs["ctrlrange"] = f"{_f(-limit)} {_f(limit)}"
        return "motor", attrs, f"motor (control = torque / gear {g:g}; ctrlrange: {peak})"
    if limit:
        attrs["forcerange"] = f"{_f(-limit)} {_f(limit)}"
    if opt.actuator == "position":
        kp = opt.kp if opt.kp is not None else j * wn**2
        kv = opt.kv if opt.kv is not None else 2.0 * math.sqrt(kp * j)  # critically damped on J_max, kp given or not
        attrs |= {"kp": _f(kp / g**2), "kv": _f(kv / g**2)}
        if drive.range is not None:
            attrs["ctrlrange"] = f"{_f(g * drive.range[0])} {_f(g * drive.range[1])}"
        damped = "given" if opt.kv is not None else "critically damped"
        how = ("given" if opt.kp is not None else
               f"J_max·ω_n², J_max = {j:.6g} kg·m² the largest reduced inertia, ω_n = {wn:.4g} rad/s")
        return "position", attrs, (f"position servo (control = gear·φ [rad]; at the joint: stiffness {kp:.6g} N·m/rad "
                                   f"({how}), damping {kv:.6g} N·m·s/rad ({damped}); "
                                   f"in the file, the actuator's units: kp = stiffness/gear² {kp / g**2:.6g}, "
                                   f"kv = damping/gear² {kv / g**2:.6g}; forcerange: {peak})")
    kv = opt.kv if opt.kv is not None else j * wn
    attrs["kv"] = _f(kv / g**2)
    how = "given" if opt.kv is not None else f"J_max·ω_n: time constant 1/ω_n = {1 / wn:.3g} s"
    return "velocity", attrs, (f"velocity servo (control = gear·ω [rad/s]; at the joint: damping {kv:.6g} N·m·s/rad "
                               f"({how}); in the file, the actuator's units: kv = damping/gear² {kv / g**2:.6g}; "
                               f"forcerange: {peak})")


def _f(x: float) -> str:
    return "0" if float(x) == 0.0 else repr(float(x))


def robot_model(xml: str, drive: RobotDrive, opt: RobotOptions, name: str, scene=None, source=None) -> str:
    """The robot MJCF from the validation MJCF text ``xml`` of the mechanism ``name``;
    ``scene`` (extent (xmin, xmax, ymin, ymax) [m] in the plane, size [m]) for ``opt.scene``
    on a planar linkage (a spatial chain's own scene is already z-up); ``source``: the
    description (or assembled mechanism) the accuracy line is predicted for."""
    from linkgen.mujoco.robot_sensors import add_sensors
    from linkgen.mujoco.robot_xml import (add_mount, add_prefix, add_turned_scene, explicit_geom_defaults,
                                          plane_turn, remove_scene)
    from linkgen.mujoco.scene import KEY, SERVO

    prefix = opt.prefix if opt.prefix is not None else f"{name}/"
    plane = opt.plane or "xz"
    root = etree.fromstring(xml.encode())
    for c in [c for c in root.iter(etree.Comment)]:
        c.getparent().remove(c)
    g = np.asarray(drive.gravity, dtype=float)
    turn = plane_turn(plane, (g[0], g[1])) if drive.family == "planar" else np.eye(3)
    world_g = turn @ g if plane != "xy" else np.array([0.0, 0.0, -float(np.linalg.norm(g))])
    option = root.find("option")
    keep = {k: option.get(k) for k in ("ccd_tolerance", "ccd_iterations", "cone") if option.get(k)}  # a cam's contact
    option.attrib.clear()
    option.attrib.update(dict(timestep=_f(ROBOT_TIMESTEP), integrator=ROBOT_INTEGRATOR, gravity=" ".join(map(_f, world_g)),
                              **keep))
    explicit_geom_defaults(root)
    if not (opt.scene and drive.family == "spatial"):
        remove_scene(root)
    add_mount(root, turn)
    if opt.scene and drive.family == "planar" and scene is not None:
        add_turned_scene(root, turn, *scene)
    for eq in root.iter("connect", "weld", "joint"):  # MuJoCo's defaults, or the robot scene's
        if eq.getparent() is not None and eq.getparent().tag == "equality":
            eq.attrib.pop("solref", None)
            eq.attrib.pop("solimp", None)
    joint = root.find(f".//joint[@name='{drive.joint}']")
    joint.attrib.pop("armature", None)
    if opt.rotor_inertia > 0:
        joint.set("armature", _f(opt.rotor_inertia))
    joint.set("ref", _f(drive.sketch))
    if joint.get("range"):
        lo, hi = (float(x) + drive.sketch for x in joint.get("range").split())
        joint.set("range", f"{_f(lo)} {_f(hi)}")
    actuator = root.find("actuator")
    for el in list(actuator):
        if not isinstance(el.tag, str) or el.get("name") in (SERVO, "drive:motor"):
            actuator.remove(el)
    tag, attrs, said = drive_actuator(drive, opt)
    act_name = f"drive:{tag}"
    actuator.insert(0, etree.Element(tag, name=act_name, joint=drive.joint, **attrs))
    sensors = add_sensors(root, act_name, drive, prefix)
    _at_rest(root, KEY, drive, opt)
    add_prefix(root, prefix)
    from dataclasses import replace

    from linkgen.mujoco.robot_machine import machine_loads

    drive = replace(drive, loads=drive.loads + machine_loads(opt.machine, drive.joint, opt.gear))
    header = _header(name, prefix, plane, drive, opt, said, sensors, world_g, accuracy_comment(source, ROBOT_SETTINGS))
    root.insert(0, etree.Comment(header))
    etree.indent(root, space="  ")
    return etree.tostring(root, pretty_print=True, encoding="unicode")


def _at_rest(root, key: str, drive: RobotDrive, opt: RobotOptions) -> None:
    """The keyframe ``key`` at rest, the drive joint at the sketch's φ (its ``ref``), and a
    position servo's control holding it there."""
    el = root.find(f"keyframe/key[@name='{key}']")
    if el is None:
        return
    qpos = [float(x) for x in el.get("qpos").split()]
    qpos[_qpos_index(root, drive.joint)] += drive.sketch
    el.set("qpos", " ".join(_f(x) for x in qpos))
    el.set("qvel", " ".join("0" for _ in el.get("qvel").split()))
    n_act = len([a for a in root.find("actuator") if isinstance(a.tag, str)])
    if opt.actuator == "position":
        el.set("ctrl", " ".join([_f(opt.gear * drive.sketch)] + ["0"] * (n_act - 1)))


def _qpos_index(root, joint: str) -> int:
    """Where ``joint``'s angle is in qpos (joints in tree order; a ball takes 4, a free 7)."""
    width = {"hinge": 1, "slide": 1, "ball": 4, "free": 7}
    at = 0
    for el in root.find("worldbody").iter("joint", "freejoint"):
        if el.get("name") == joint:
            return at
        at += 7 if el.tag == "freejoint" else width[el.get("type", "hinge")]
    raise KeyError(joint)


def _flat_plane(drive: RobotDrive, world_g) -> str:
    """The header's plane line for ``--plane xy``: gravity is the plane's normal there."""
    g = float(np.hypot(drive.gravity[0], drive.gravity[1]))
    if g == 0:
        return (" Plane: the description's x, y on the world's x, y (flat, z up); the description has no gravity, the "
                f"file's is {' '.join(f'{x:g}' for x in world_g)} m/s², normal to the plane.")
    return (f" Plane: the description's x, y on the world's x, y (flat, z up), so gravity "
            f"{' '.join(f'{x:g}' for x in world_g)} m/s² is normal to the mechanism's plane: the description's in-plane "
            f"gravity ({drive.gravity[0]:g}, {drive.gravity[1]:g}) m/s² is not felt, the joints carry the links' weight "
            "out of the plane (the reaction sensors read it along z), and the actuator's limits and the accuracy below "
            "are the closed form's without gravity.")


def _header(name, prefix, plane, drive, opt, said, sensors, world_g, accuracy: str) -> str:
    p = prefix
    lines = [
        f" linkgen robot model of {name} ({drive.family}): every name begins with {p!r}.",
        f" In it: the mechanism under the fixed body {p}{'mount'} (the ground link; place it on any body of a robot with "
        "mujoco.MjSpec.attach or <attach>); its links, joints and loop-closing connects; the actuator "
        f"{p}drive:{opt.actuator} on the driven joint {p}{drive.joint}, a {said}; the keyframe {p}sketch (the sketch "
        "pose at rest).",
        f" The driven joint's angle is the description's crank angle φ [rad] (its ref is the sketch's "
        f"φ = {drive.sketch:.6g}); armature {opt.rotor_inertia:g} kg·m² "
        + ("(the description's [machine] rotor and flywheel)." if opt.rotor_inertia else "(no rotor in the description)."),
        " Sensors: " + "; ".join(sensors) + ".",
        *(f" Note: {note}." for note in drive.notes),
        (_flat_plane(drive, world_g) if drive.family == "planar" and plane == "xy" else
         (f" Plane: the description's x, y on the world's {plane[0]}, {plane[1]} (z up), its gravity turned the same "
          "way: " if drive.family == "planar" else " Frame: the description's, z up; gravity ")
         + f"{' '.join(f'{x:g}' for x in world_g)} m/s².")
        + " Attached to a robot, the robot's own <option> (gravity, "
        "timestep, integrator) wins.",
        f" Settings: timestep {ROBOT_TIMESTEP:g} s, {ROBOT_INTEGRATOR}, MuJoCo's default solver; the connects carry no "
        "solref/solimp, so MuJoCo's defaults or the scene's <default><equality> apply.",
    ]
    if accuracy:
        lines.append(f" Accuracy at these settings: {accuracy}")
    lines.append(" Not in this file: the validation settings (a build without its robot option); "
                 + ("" if opt.scene else "a floor, sky, light and camera (the build's scene option adds them); ")
                 + ("what the description has that MJCF cannot carry (each step, set data.qfrc_applied to 0, then "
                    "apply each): " + "; ".join(drive.loads).replace("{P}", p)
                    if drive.loads
                    else "no loads besides gravity are described") + ".")
    return "\n".join(re.sub(r"--", "- -", line) for line in lines) + "\n"


__all__ = ["ACTUATORS", "BANDWIDTH_PER_SPEED", "FAR_OFF", "POSITION_BANDWIDTH", "ROBOT_INTEGRATOR", "ROBOT_SETTINGS",
           "ROBOT_TIMESTEP", "SERVO_FACTORS", "RobotDrive", "RobotOptions", "TORQUE_MARGIN", "accuracy_comment",
           "predict_at", "drive_actuator", "robot_model"]
