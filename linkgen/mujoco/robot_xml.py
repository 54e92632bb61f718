"""The robot build's edits of an MJCF tree, the same for every family (``mujoco.robot`` says what
goes in): the mechanism under one fixed top body, its plane turned into a z-up world, the scene
taken out or turned, and every name the file defines behind one prefix.

The prefix covers every ``name`` and every attribute that refers to one (``REFERENCES``); the
compiled model's names are checked against it in tests/test_robot_build.py for every kind of
MuJoCo object."""

from __future__ import annotations

import math
import re

import numpy as np
from lxml import etree

from linkgen.errors import ArgumentError

MOUNT = "mount"
PLANES = ("xz", "yz", "xy")
# Letters, digits and _ - . : / only: MJCF attributes that list names (a flex's bodies, a skin's
# bones) split them on whitespace, and quotes, <, > and & are XML's own.
PREFIX_PATTERN = re.compile(r"[A-Za-z0-9_.:/-]+")
# Attributes whose value is the name of another element of the file.
REFERENCES = ("body1", "body2", "joint", "joint1", "joint2", "site", "objname", "refname", "mesh", "material",
              "texture", "tendon", "actuator", "geom1", "geom2", "body", "target", "cranksite", "slidersite",
              "jointinparent", "hfield", "class", "childclass", "camera", "light")
# Elements of the viewer's scene (linkgen.mujoco.scene) that a robot's own scene already has.
SCENE_NAMES = ("light:sun", "floor:plane", "overview", "tex:sky", "tex:floor", "mat:floor")


def check_prefix(prefix: str) -> str:
    """``prefix`` if MJCF can carry it at the head of every name; ArgumentError naming what it takes."""
    if not isinstance(prefix, str) or not PREFIX_PATTERN.fullmatch(prefix):
        raise ArgumentError(f"--prefix {prefix!r}: a prefix takes letters, digits and _ - . : / only, at least one "
                            "(MJCF attributes that list names split them on spaces; quotes, <, > and & are XML's)")
    return prefix


def plane_turn(plane: str, down: tuple[float, float]) -> np.ndarray:
    """The rotation (3, 3) from the description's frame to the world's: the description's plane
    (x, y) onto the world plane ``plane`` ("xz", "yz": the description's ``down`` (its gravity's
    direction, or −y without gravity) onto −z; "xy": the plane flat, its normal up)."""
    if plane not in PLANES:
        raise ArgumentError(f"--plane {plane!r}: the mechanism's plane is one of {', '.join(PLANES)} in a z-up world")
    if plane == "xy":
        return np.eye(3)
    g = np.asarray(down, dtype=float)
    angle = -0.5 * math.pi - (math.atan2(g[1], g[0]) if np.hypot(*g) > 0 else -0.5 * math.pi)
    c, s = math.cos(angle), math.sin(angle)
    in_plane = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])  # the description's down onto −y
    x, y = (np.eye(3)[0], np.eye(3)[2]) if plane == "xz" else (np.eye(3)[1], np.eye(3)[2])
    onto = np.column_stack([x, y, np.cross(x, y)])  # description x, y, z → world
    return onto @ in_plane


def quat(r: np.ndarray) -> tuple[float, float, float, float]:
    """The unit quaternion (w, x, y, z) of a rotation matrix (Shepperd's method)."""
    t = np.trace(r)
    if t > 0:
        s = 2.0 * math.sqrt(1.0 + t)
        q = (0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s)
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k])
        q = [0.0] * 4
        q[0] = (r[k, j] - r[j, k]) / s
        q[1 + i], q[1 + j], q[1 + k] = 0.25 * s, (r[j, i] + r[i, j]) / s, (r[k, i] + r[i, k]) / s
    q = np.array(q) / np.linalg.norm(q)
    return tuple(float(x) for x in (q if q[0] >= 0 else -q))


def _v(*xs: float) -> str:
    return " ".join("0" if float(x) == 0.0 else repr(float(x)) for x in xs)


def remove_scene(root) -> None:
    """Take out the viewer's scene: light, floor, camera, their textures and materials, and the
    ``visual`` settings (a robot's scene has its own)."""
    for el in list(root.iter()):
        if el.get("name") in SCENE_NAMES and el.getparent() is not None:
            el.getparent().remove(el)
    for el in root.findall("visual"):
        root.remove(el)


def explicit_geom_defaults(root) -> None:
    """The file's ``<default>`` written onto each geom and removed: attached to a robot, the
    robot's own defaults then cannot change the mechanism's geoms, nor the mechanism's the robot's."""
    for default in root.findall("default"):
        for d in default.findall("geom"):
            for geom in root.iter("geom"):
                for k, v in d.attrib.items():
                    if k not in geom.attrib:
                        geom.set(k, v)
        root.remove(default)


def add_mount(root, turn: np.ndarray, keep: tuple[str, ...] = SCENE_NAMES):
    """Move everything of the world body (but the scene's ``keep``) into one fixed body ``mount``
    turned by ``turn``; a ``connect`` to the world body is to the mount. Returns the mount."""
    world = root.find("worldbody")
    mount = etree.Element("body", name=MOUNT, pos="0 0 0", quat=_v(*quat(turn)))
    for el in list(world):
        if not (isinstance(el.tag, str) and el.get("name") in keep):
            mount.append(el)
    world.append(mount)
    for connect in root.iter("connect"):
        if connect.get("body2") is None:
            connect.set("body2", MOUNT)
    return mount


def add_turned_scene(root, turn: np.ndarray, extent: tuple[float, float, float, float], size: float) -> None:
    """The viewer's scene in the z-up world: a sky, a floor below the mechanism's lowest point,
    a light above and a camera on the side of the plane's normal framing the motion ``extent``
    (xmin, xmax, ymin, ymax [m], in the description's plane)."""
    from linkgen.mujoco.scene import CAMERA_ASPECT, CAMERA_MARGIN, FLOOR_DEPTH

    asset = root.find("asset")
    etree.SubElement(asset, "texture", name="tex:sky", type="skybox", builtin="gradient", rgb1="0.95 0.97 1",
                     rgb2="0.7 0.78 0.88", width="64", height="64")
    etree.SubElement(asset, "texture", name="tex:floor", type="2d", builtin="checker", rgb1="0.82 0.82 0.8",
                     rgb2="0.74 0.74 0.72", width="256", height="256")
    etree.SubElement(asset, "material", name="mat:floor", texture="tex:floor", texrepeat="8 8", reflectance="0")
    x0, x1, y0, y1 = extent
    corners = np.array([turn @ (x, y, 0.0) for x in (x0, x1) for y in (y0, y1)])
    centre = turn @ (0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.0)
    span = max(x1 - x0, y1 - y0, size)
    world = root.find("worldbody")
    low = float(corners[:, 2].min()) - FLOOR_DEPTH * size - (0.1 * span if abs(turn[2, 2]) < 0.5 else 0.0)
    etree.SubElement(world, "geom", name="floor:plane", type="plane", pos=_v(centre[0], centre[1], low),
                     size=_v(2 * span, 2 * span, 0.1 * span), material="mat:floor", contype="0", conaffinity="0")
    etree.SubElement(world, "light", name="light:sun", pos=_v(centre[0], centre[1], centre[2] + 5.0 * size),
                     dir="0 0 -1", directional="true", diffuse="0.35 0.35 0.35", specular="0.05 0.05 0.05")
    half = 0.5 * max(y1 - y0, (x1 - x0) / CAMERA_ASPECT, 0.25 * size)
    distance = CAMERA_MARGIN * half / math.tan(math.radians(22.5))
    eye = centre + distance * turn[:, 2]
    etree.SubElement(world, "camera", name="overview", pos=_v(*eye), xyaxes=_v(*turn[:, 0], *turn[:, 1]))
    visual = etree.SubElement(root, "visual")
    etree.SubElement(visual, "global", offwidth="1280", offheight="960")


def add_prefix(root, prefix: str) -> None:
    """``prefix`` before every name the file defines and every reference to one (``REFERENCES``)."""
    defined = {el.get("name") for el in root.iter() if isinstance(el.tag, str) and el is not root and el.get("name")}
    for el in root.iter():
        if not isinstance(el.tag, str) or el is root:
            continue
        if el.get("name"):
            el.set("name", prefix + el.get("name"))
        for attr in REFERENCES:
            value = el.get(attr)
            if value is not None and value in defined:
                el.set(attr, prefix + value)


__all__ = ["MOUNT", "PLANES", "REFERENCES", "add_mount", "add_prefix", "add_turned_scene", "check_prefix",
           "explicit_geom_defaults", "plane_turn", "quat", "remove_scene"]
