"""The robot build's sensors and how to read them: the drive's actuator force and joint torque,
and the reaction at each revolute pair.

MuJoCo has no sensor for an equality constraint's force. Its maintainers' recipe
(google-deepmind/mujoco#1217): attach the constraint to a small static child body (no joints,
no mass) and put a ``force`` sensor on a site of that body; the force between the static body
and its parent is the force through the constraint. Each loop-closing ``connect`` J therefore
holds, on the body of the link that exerts the reaction (the pair's second link), a static body
``loop:J`` at the pair's point with the site ``loop:J``; the connect ties that body to the pair's
first link. A revolute of the tree gets its ``force`` sensor on a site of its child body at the
pair's point: the force between the child and its parent is the force through the joint.

``reactions(model, data, prefix)`` reads them all as the force on one link of the pair by the
other, in the mount's frame (the description's x, y, z), with the links named; where they are
the closed form's ``Forces.on[J]`` and ``Forces.by[J]`` it is ``reactions[J]``, else its negative."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from lxml import etree

from linkgen.mujoco.robot_xml import MOUNT

REACTION = "reaction:"
LOOP = "loop:"
ACTUATOR_FORCE = "drive:actuatorfrc"
JOINT_TORQUE = "drive:torque"


@dataclass(frozen=True)
class ReactionSite:
    """A revolute whose reaction gets a sensor: its name, its first and second link's bodies
    (the closed form's order; the ground's is the mount), and either the site at the pair's
    point on the child body of a tree joint, or for a loop-closing connect the pair's point in
    the second body's frame (3,) [m]."""

    joint: str
    first_body: str
    second_body: str
    site: str | None = None
    anchor: tuple[float, float, float] | None = None


def _v(*xs: float) -> str:
    return " ".join("0" if float(x) == 0.0 else repr(float(x)) for x in xs)


def add_sensors(root, actuator: str, drive, prefix: str = "") -> list[str]:
    """Add the sensors of the drive and of each revolute's reaction (``drive.reactions``:
    ``ReactionSite``) to the MJCF tree ``root``; returns what the header says of them (the names
    as they will be, behind ``prefix``)."""
    sensor = root.find("sensor")
    if sensor is None:
        sensor = etree.SubElement(root, "sensor")
    etree.SubElement(sensor, "actuatorfrc", name=ACTUATOR_FORCE, actuator=actuator)
    etree.SubElement(sensor, "jointactuatorfrc", name=JOINT_TORQUE, joint=drive.joint)
    said = [f"{prefix}{ACTUATOR_FORCE} (the actuator's force, in its units) and {prefix}{JOINT_TORQUE} (its torque "
            "on the crank [N·m])"]
    names = []
    for r in drive.reactions:
        if r.site is None:  # a loop-closing connect: from a static body of the second link to the first
            connect = root.find(f"equality/connect[@name='{r.joint}']")
            body = root.find(f"worldbody//body[@name='{r.second_body}']")
            static = etree.SubElement(body, "body", name=LOOP + r.joint, pos=_v(*r.anchor))
            _centre_on_parent(static, body, r.anchor)
            etree.SubElement(static, "site", name=LOOP + r.joint, size=_size(root))
            connect.set("body1", LOOP + r.joint)
            connect.set("body2", r.first_body)
            connect.set("anchor", "0 0 0")
            site = LOOP + r.joint
        else:
            site = r.site
        etree.SubElement(sensor, "force", name=REACTION + r.joint, site=site)
        names.append(r.joint)
    if names:
        said.append(f"{prefix}{REACTION}J, the force [N] through each revolute J ({', '.join(names)}) in its site's frame; "
                    "linkgen.mujoco.robot_sensors.reactions(model, data, prefix) gives each in the mount's frame as the "
                    "force on one link of the pair by the other, naming both (a sensor reads the force on its "
                    "site's body by that body's parent; a loop:J body passes it on to the pair's first link)")
    return said


def _centre_on_parent(static, parent, anchor) -> None:
    """Give the static body ``static`` (at ``anchor`` in ``parent``'s frame, not turned) a massless
    inertial at its parent's centre of mass. MuJoCo scales an equality's regularisation by its
    bodies' ``invweight0``, taken at each body's centre of mass: a bare static body's is its own
    origin, the pair's point, where the link is far lighter to push than at its centre (the
    four-bar's rocker: 0.571 against 0.0357 1/kg), which softened each loop 16-fold and opened
    the four-bar's gap 2.2-fold (3.1e-3 of its size against 1.4e-3 with the connect on the link).
    Centred on its parent's, it weighs what its link weighs and the loop is as stiff as the
    validation model's; being massless it changes no dynamics and no sensor reading."""
    inertial = parent.find("inertial")
    if inertial is None:  # the mount (the world's, weightless to MuJoCo) or a link without mass
        return
    centre = np.array([float(x) for x in inertial.get("pos", "0 0 0").split()]) - np.asarray(anchor, dtype=float)
    etree.SubElement(static, "inertial", pos=_v(*centre), mass="0", diaginertia="0 0 0")


def _size(root) -> str:
    site = next(iter(root.iter("site")), None)
    return site.get("size") if site is not None and site.get("size") else "0.005"


@dataclass(frozen=True)
class Reaction:
    """A revolute's reaction: the force [N] (3,) on link ``on`` by link ``by`` (body names
    without the prefix; the mount is the ground), in the mount's frame."""

    joint: str
    on: str
    by: str
    force: np.ndarray


def reactions(model, data, prefix: str) -> dict[str, Reaction]:
    """Every ``reaction:J`` sensor of the robot model attached under ``prefix`` (the full
    prefix of its names: the robot's attach prefix and the file's; ArgumentError naming the
    prefixes the model has where no ``prefix``mount is), read after ``mj_forward`` (or a step: then at the step's start state),
    as the force on the pair's first link by its second, in the mount's frame."""
    import mujoco

    out = {}
    mount = _mount(model, prefix)
    to_mount = data.xmat[mount].reshape(3, 3).T
    for i in range(model.nsensor):
        s = model.sensor(i)
        if s.type[0] != mujoco.mjtSensor.mjSENS_FORCE or not s.name.startswith(prefix + REACTION):
            continue
        joint = s.name[len(prefix + REACTION):]
        site = int(model.sensor_objid[i])
        body = int(model.site_bodyid[site])
        reading = data.sensordata[model.sensor_adr[i]:model.sensor_adr[i] + 3]
        # the sensor gives the force between the site's body and its parent in the site's frame,
        # as the force on the body by its parent (measured against the closed form's reactions:
        # tests/test_robot_build.py)
        force = to_mount @ (data.site_xmat[site].reshape(3, 3) @ reading)
        parent = int(model.body_parentid[body])
        if model.body(body).name == prefix + LOOP + joint:  # a connect's static body: massless, it passes
            # the force its parent (the second link) exerts on it to the first link
            on, by = int(model.equality(prefix + joint).obj2id[0]), parent
        else:
            on, by = body, parent
        out[joint] = Reaction(joint, _link(model, on, prefix), _link(model, by, prefix), force)
    return out


def _mount(model, prefix: str) -> int:
    """The id of the body ``prefix``mount; ArgumentError naming the prefixes the model has (each
    mount whose mechanism carries reaction sensors) where it has none such."""
    from linkgen.errors import ArgumentError

    try:
        return model.body(prefix + MOUNT).id
    except KeyError:
        pass
    sensed = {model.sensor(i).name.split(REACTION)[0] for i in range(model.nsensor) if REACTION in model.sensor(i).name}
    have = sorted(p for p in sensed if _has_body(model, p + MOUNT))
    raise ArgumentError(f"robot_sensors.reactions: prefix {prefix!r}: the model has no body {prefix + MOUNT!r}; "
                        + (f"pass the full prefix of the mechanism's names, one of {', '.join(map(repr, have))} (its "
                           f"mount body is PREFIX{MOUNT})" if have else
                           "it holds no linkgen robot mechanism with reaction sensors"))


def _has_body(model, name: str) -> bool:
    try:
        model.body(name)
    except KeyError:
        return False
    return True


def _link(model, body: int, prefix: str) -> str:
    name = model.body(body).name
    return "ground" if name == prefix + MOUNT else name[len(prefix):]


__all__ = ["ACTUATOR_FORCE", "JOINT_TORQUE", "LOOP", "REACTION", "Reaction", "ReactionSite", "add_sensors", "reactions"]
