"""What makes the MJCF a scene a user can open in MuJoCo's viewer: a sky and a floor, a camera
framing the mechanism, a keyframe at the assembled sketch moving at the drive's ω, a speed servo
that keeps the crank turning with no control input, and a comment saying what the validation
settings are for.

The servo (``drive:servo``, a ``general`` actuator with an affine bias kv·(ω − q̇)) is only for
a plain viewer: every linkgen run switches it off (``settings.apply``) and drives the crank by its
rotor inertia, reading the drive torque from ``drive:motor``."""

from __future__ import annotations

import math

import mujoco
import numpy as np
from lxml import etree

from linkgen.mujoco.log import no_log_file

SERVO = "drive:servo"
KEY = "sketch"
# The servo brings the crank's rotor to ω with this time constant [s] (kv = armature / time).
SERVO_TIME = 0.05
# Floor below the mechanism's plane, as a fraction of its size (the pivots reach down 1 %).
FLOOR_DEPTH = 0.05
# The camera sees the mechanism's extent with this margin around it, at MuJoCo's 45° field of view.
CAMERA_MARGIN = 1.2
# The camera frames the extent for an image this much wider than tall (MuJoCo's viewer and
# ``linkgen render``'s default 800×600 are 4:3); MuJoCo's field of view (45°) is vertical.
CAMERA_ASPECT = 4.0 / 3.0


def _vec(*xs: float) -> str:
    return " ".join("0" if float(x) == 0.0 else repr(float(x)) for x in xs)


# The materials of the mechanism's parts: the ground, the crank, other links, sliders.
PART_RGBA = {"mat:ground": "0.35 0.35 0.35 1", "mat:crank": "0.85 0.3 0.2 1", "mat:link": "0.25 0.45 0.8 1",
             "mat:slider": "0.3 0.7 0.35 1"}


def add_scene_assets(asset) -> None:
    """The sky, the floor's checker and the parts' materials (``PART_RGBA``)."""
    etree.SubElement(asset, "texture", name="tex:sky", type="skybox", builtin="gradient", rgb1="0.95 0.97 1",
                     rgb2="0.7 0.78 0.88", width="64", height="64")
    etree.SubElement(asset, "texture", name="tex:floor", type="2d", builtin="checker", rgb1="0.82 0.82 0.8",
                     rgb2="0.74 0.74 0.72", width="256", height="256")
    etree.SubElement(asset, "material", name="mat:floor", texture="tex:floor", texrepeat="8 8", reflectance="0")
    for name, rgba in PART_RGBA.items():
        etree.SubElement(asset, "material", name=name, rgba=rgba)


def pose_extent(src) -> tuple[float, float, float, float]:
    """xmin, xmax, ymin, ymax [m] of every point at the reference pose."""
    xy = []
    for link, (origin, angle) in src.pose.items():
        c, s = math.cos(angle), math.sin(angle)
        for local in src.shapes[link].local.values():
            xy.append((origin[0] + c * local[0] - s * local[1], origin[1] + s * local[0] + c * local[1]))
    a = np.array(xy, dtype=float)
    return float(a[:, 0].min()), float(a[:, 0].max()), float(a[:, 1].min()), float(a[:, 1].max())


# Crank angles over the drive's range at which the camera's extent is taken.
EXTENT_SAMPLES = 73


def motion_extent(src) -> tuple[float, float, float, float]:
    """xmin, xmax, ymin, ymax [m] of every point over the drive's range (the reference pose's
    extent, ``pose_extent``, where the range cannot be traced)."""
    from linkgen.errors import LinkgenError
    from linkgen.families.planar.positions import drive_angles, positions

    try:
        x0, x1, y0, y1 = positions(src.mech, drive_angles(src.mech, EXTENT_SAMPLES)).bounds()
    except LinkgenError:
        return pose_extent(src)
    if getattr(src.mech, "cams", ()):  # a cam's profile turns within the circle of its largest radius
        from linkgen.families.planar.cam_profile import cam_reach

        px, py = src.mech.points[src.mech.revolute(src.mech.drive.joint).point]
        r = cam_reach(src.mech)
        x0, x1, y0, y1 = min(x0, px - r), max(x1, px + r), min(y0, py - r), max(y1, py + r)
    return x0, x1, y0, y1


def add_scene(world, extent: tuple[float, float, float, float], size: float) -> None:
    """Floor plane under the mechanism's plane and an ``overview`` camera looking down on it."""
    x0, x1, y0, y1 = extent
    cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    span = max(x1 - x0, y1 - y0, size)
    etree.SubElement(world, "geom", name="floor:plane", type="plane", pos=_vec(cx, cy, -FLOOR_DEPTH * size),
                     size=_vec(2 * span, 2 * span, 0.1 * span), material="mat:floor")
    half = 0.5 * max(y1 - y0, (x1 - x0) / CAMERA_ASPECT, 0.25 * size)
    distance = CAMERA_MARGIN * half / math.tan(math.radians(22.5))
    etree.SubElement(world, "camera", name="overview", pos=_vec(cx, cy, distance), xyaxes="1 0 0 0 1 0")


def add_servo(actuator, joint: str, armature: float, omega: float) -> None:
    kv = armature / SERVO_TIME
    actuator.append(etree.Comment(" drive:servo holds the crank at the drive's ω in a plain viewer; linkgen's own "
                                  "runs switch it off and drive the crank by its rotor inertia "))
    etree.SubElement(actuator, "general", name=SERVO, joint=joint, gainprm="0", biastype="affine",
                     biasprm=_vec(kv * omega, 0.0, -kv))


def settings_comment(settings, slides: bool = False) -> str:
    """The MJCF's first comment: its settings; ``slides``: the drive is a prismatic pair (its rotor
    a mass [kg] on the slide joint, keeping the slide's speed)."""
    text = _settings_comment(settings)
    if slides:
        text = (text.replace("kg·m² on the drive joint", "kg on the drive's slide joint")
                .replace("keeps the crank speed constant", "keeps the slide's speed constant"))
    return text


def _settings_comment(settings) -> str:
    if not settings.label.startswith("derived"):
        return (f" settings: {settings.label}: timestep {settings.timestep:g} s ({settings.integrator}), connects with "
                f"solref {settings.solref}, solimp {settings.solimp_text}; rotor inertia (armature) "
                f"{settings.armature:g} kg·m² on the drive joint. linkgen validate reports what they cost in "
                f"accuracy (the practical-settings table). ")
    return (f" linkgen validation settings, derived from this mechanism: timestep {settings.timestep:g} s ({settings.integrator}), "
            f"loop-closing connects with time constant {settings.timeconst:g} s and impedance "
            f"{settings.impedance:g} (they hold the loop gap to ~1e-8 of the size), and a rotor inertia "
            f"(armature) of {settings.armature:g} kg·m² on the drive joint that keeps the crank speed constant. "
            f"For a robot scene, linkgen build with its robot option writes a model to drive and attach "
            f"(docs/robotics.md). ")


@no_log_file()  # MuJoCo's warnings stay out of the user's folder (linkgen.mujoco.log)
def add_sketch_key(root, source, mech, model: mujoco.MjModel | None = None) -> None:
    """The keyframe ``sketch``: the assembled sketch pose, moving at the drive's ω; its joint state
    read on ``model`` (a compile of ``root`` when None; else one of the same joints and bodies)."""
    from linkgen.families.planar.geometry import link_shapes, sketch_input
    from linkgen.mujoco.state import tree_state

    if model is None:
        try:
            model = mujoco.MjModel.from_xml_string(etree.tostring(root, encoding="unicode"))
        except ValueError:  # MuJoCo rejects the model: the caller's own compile says why
            return
    phi = sketch_input(mech, link_shapes(mech))
    qpos, qvel = tree_state(mech, model, [phi], mech.drive.omega)
    keyframe = etree.SubElement(root, "keyframe")
    etree.SubElement(keyframe, "key", name=KEY, qpos=_vec(*qpos[0]), qvel=_vec(*qvel[0]))


def switch_off_servo(model: mujoco.MjModel) -> None:
    """Zero the viewer's speed servo in a compiled model (no-op for models without one)."""
    try:
        act = model.actuator(SERVO).id
    except KeyError:
        return
    model.actuator_biasprm[act, :] = 0.0
    model.actuator_gainprm[act, :] = 0.0


__all__ = ["KEY", "SERVO", "add_scene", "add_scene_assets", "add_servo", "motion_extent", "add_sketch_key", "pose_extent",
           "settings_comment", "switch_off_servo"]
