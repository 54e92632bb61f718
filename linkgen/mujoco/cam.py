"""A cam mechanism in MuJoCo: the cam's profile as real geometry the roller touches, the follower
held on by its spring, the cam turned by a rotor inertia at ω; and the comparison of the
follower's motion, the contact force and the cam torque with the closed form.

The profile is a mesh: the profile polygon (PROFILE_POINTS vertices) extruded along z. MuJoCo
collides a mesh as its convex hull, so a profile that is concave anywhere is refused with the
angles where. The roller is a sphere of the roller's radius centred in the profile's plane (a
knife edge a sphere of KNIFE_RADIUS of the base circle; ROLLER_GEOM says why not a cylinder),
a flat face a thin box. Contacts are frictionless (condim 1), time constant CONTACT_TIME timesteps, impedance 0.9999; the
convex collision runs to CCD_TOLERANCE. The model as loaded (MuJoCo's qpos0) has the follower
where the closed form puts it at θ = 0, on the cam.

What this costs (measured, validation figures in docs/cams.md): the profile is a polygon, and
the roller rolling over its vertices is kicked off the cam at each — contact is lost in 6–8 % of
the steps (a sphere roller; a flat face 10 %) — so the follower's displacement follows the
closed form to ~1e-5 of the stroke (a flat face ~1e-4) and the contact force only as a mean over
a few degrees of cam turn (under a per cent; docs/cams-mujoco.md measures each contact choice);
the instantaneous force is a train of impacts. The follower's spring
is an actuator with an affine bias (no control input): F = −(preload + rate·q)."""

from __future__ import annotations

import math

import numpy as np
from lxml import etree

from linkgen.families.cam.description import CamMechanism
from linkgen.families.cam.kinetics import SAMPLES, state
from linkgen.families.cam.results import CAM as CAM_PAIR
from linkgen.families.cam.summary import FOLLOWER as FOLLOWER_NAME
from linkgen.errors import SimulationError
from linkgen.mujoco.guides import GUIDE_OVERHANG, GUIDE_SIZE, guide_span
from linkgen.mujoco.options import MESH_VOLUME_MARGIN, MUJOCO_MIN_BAR, MUJOCO_MIN_MESH_VOLUME
from linkgen.mujoco.scene import add_scene, add_scene_assets
from linkgen.mujoco.xml_text import comment

# Profile vertices and steps per turn: measured on the bundled cams, 4000 and 20000 hold the
# displacement to ~1e-5 of the stroke with the sphere roller; 16 000 vertices halve that at ~20×
# the time and leave the contact force as it was, half the step changes nothing (the roller's
# impacts on the facets set the error; docs/cams-mujoco.md).
PROFILE_POINTS = 4000
STEPS_PER_TURN = 20000
# Steps per the follower's shortest time scale, max|q″|/(max|q‴|·ω) (how long its acceleration
# takes to change by its peak): a cam whose motion changes faster than the bundled ones' (a short
# rise, a steep law) gets a proportionally shorter step. 1000 gives the bundled cams (120°–150°
# rises and a sine: 1330–3180 steps per scale at STEPS_PER_TURN) no finer step than before.
STEPS_PER_SCALE = 1000
# The integrator: semi-implicit Euler, which finds the contacts once, at the start of each step.
# MuJoCo's RK4 runs collision detection again at each of its three trial states (mj_RungeKutta
# calls mj_forwardSkip(mjSTAGE_NONE)): when the roller bouncing over the profile's facets is off
# the cam at the step's start but touches it at a trial state, that stage's stiff contact
# acceleration (time constant CONTACT_TIME steps) enters the step's weighted sum although no
# contact acts at the state the step starts from, and the follower is kicked off the cam in one
# step. (MuJoCo's guidance: RK4 is for smooth, energy-conserving systems.) Euler, measured on the
# bundled cams: displacement, contact force and cam torque as close or closer, at a quarter of the
# cost (docs/cams.md).
INTEGRATOR = "Euler"
# The contact's time constant in timesteps: 2 (the stiffest MuJoCo allows) makes the roller bounce
# off the facets in over half the steps; 10 halves that and cuts the displacement error 2–10×.
CONTACT_TIME = 10
KNIFE_RADIUS = 1e-3
# The roller's geom: a sphere touches the extruded profile at one point of its mid-plane. A
# cylinder as thick as the extrusion has its flat ends in the planes of the mesh's caps, a
# degenerate pair for the convex collision (every point of a contact line equally deep), and
# measured over a quarter turn it leaves the cam in 17–27 % of the steps against the sphere's
# 6–8 %: displacement error 5.4e-5 → 8.1e-6 of the stroke (cam_translating), 1.4e-5 → 3.7e-6
# (cam_oscillating); the contact force's rms error 0.56 → 0.24 and 0.47 → 0.30 of its peak
# (validation/cam_contact.py, docs/cams-mujoco.md).
ROLLER_GEOM = "sphere"
CCD_TOLERANCE = 1e-12
CCD_ITERATIONS = 200
# The rotor's inertia holds the cam speed to SPEED_HOLD of ω against the cam torque's energy swing.
SPEED_HOLD = 1e-9
CAM, FOLLOWER, SPRING, CONTACT = "cam", "follower", "follower:spring", "follower:contact"
# Steps between progress reports (about a second of a run on this machine's cores).
PROGRESS_STEPS = 5000
# The profile is extruded HALF_THICKNESS of the size each side of the plane, or thicker where that
# would enclose less than MESH_VOLUME_MARGIN times MuJoCo's least mesh volume: its compiler
# rejects a mesh under mjMINVAL = 1e-15 m³ ("mesh volume is too small"; measured by bisection on
# mujoco 4.0 with boxes of 1e-4 and 1e-6 m sides: 1.0e-15 compiles, below does not). A cam of
# base radius 0.25 µm is then a disc some centimetres thick: the contact is in the plane, so the
# thickness changes nothing but the drawing.
HALF_THICKNESS = 0.02
# Thickest extrusion, as a multiple of the size: measured on mujoco 4.0 with the bundled cams
# scaled down, a 4000-vertex profile 3e13 times thicker than wide still compiles and one 4.6e14
# times does not (qhull cannot build its convex hull); a profile needing more than 1e12 is
# refused with the reason before MuJoCo is asked.
MAX_THICKNESS_RATIO = 1e12
# The contact force and cam torque are compared as means over this many equal parts of a turn.
WINDOWS = 72
# What MuJoCo's soft, faceted contact holds, set from measurement on the bundled cams (twice the
# worst seen, with the cylinder roller and RK4 used before): displacement 8.8e-5 and 2.5e-5 of the
# stroke; contact force 3.4e-2 and 2.6e-2 and cam torque 3.9e-2 and 2.6e-2 of their peaks as 5°
# means. Kept with the sphere roller (1.1e-5, 7.4e-3, 6.8e-3 at worst on the rollers): the flat
# face, a box the sphere does not concern, still reaches 9.3e-5, 1.2e-2, 1.8e-2. Not the linkages'
# 1e-6: see above.
CAM_TOLERANCES = {"displacement": 2e-4, "contact_force": 0.07, "cam_torque": 0.08}


def quantity_names(kind: str) -> dict[str, str]:
    """What each of CAM_TOLERANCES' quantities is called in a stand-alone cam's results
    (``analyze``'s vocabulary, ``families.cam.results``): the follower's displacement (a
    translating follower) or angle (an oscillating one), the contact force on it, the cam's
    balancing torque."""
    return {"displacement": f"followers.{FOLLOWER_NAME}.{'displacement' if kind == 'translating' else 'angle'}",
            "contact_force": f"contact.{CAM_PAIR}.normal_force", "cam_torque": "balancing_torque"}


def _f(x: float) -> str:
    return repr(float(x))


def _check_convex(cm: CamMechanism) -> None:
    th = np.linspace(0.0, 2 * math.pi, SAMPLES, endpoint=False)
    rho = cm.follower.profile_curvature_radius(th)
    bad = rho <= 0
    if np.any(bad):
        raise SimulationError(f"the cam's profile is concave from φ = {math.degrees(th[bad][0]):.4g}° (radius of "
                              f"curvature {rho[bad].max():.3g} m there); MuJoCo collides a mesh as its convex hull, "
                              "so linkgen does not model this cam in MuJoCo")


def cam_timestep(omega: float, q2: np.ndarray, q3: np.ndarray) -> float:
    """The step [s] a cam turning at ``omega`` needs: at most one STEPS_PER_TURN-th of a turn and
    one STEPS_PER_SCALE-th of the follower's shortest time scale, from its coordinate's second
    and third derivatives in the cam angle (``q2``, ``q3`` sampled over a turn). A cam standing
    still (ω = 0, a linkage's drive) bounds nothing: infinity."""
    if omega == 0:
        return math.inf
    dt = 2 * math.pi / omega / STEPS_PER_TURN
    j = float(np.abs(q3).max())
    if j > 0:
        dt = min(dt, float(np.abs(q2).max()) / (j * omega) / STEPS_PER_SCALE)
    return dt


def timestep(cm: CamMechanism) -> float:
    """The step [s] of a stand-alone cam's run (``cam_timestep``)."""
    q = cm.follower.output(np.linspace(0.0, 2 * math.pi, SAMPLES, endpoint=False))
    return cam_timestep(cm.omega, q[2], q[3])


def rotor_inertia(cm: CamMechanism) -> float:
    """The cam shaft's armature [kg·m²]: ½·J·ω²·2·SPEED_HOLD ≥ the cam torque's energy swing."""
    th = np.linspace(0.0, 2 * math.pi, SAMPLES, endpoint=False)
    t = state(cm, th).cam_torque
    swing = float(np.ptp(np.concatenate([[0.0], np.cumsum(t) * (2 * math.pi / SAMPLES)])))
    return max(swing / SPEED_HOLD / cm.omega / cm.omega, 1.0)  # not ω²: it underflows for a slow cam


def polygon_area(xy: np.ndarray) -> float:
    """Area [m²] enclosed by the polygon ``xy`` (n, 2) (shoelace formula)."""
    x, y = xy[:, 0], xy[:, 1]
    return 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))


def extrusion_half(profile_xy: np.ndarray, size: float) -> float:
    """Half-thickness [m] of a profile's extruded mesh and its follower's contact geom:
    HALF_THICKNESS of the size, or enough for MuJoCo's least mesh volume (see there)."""
    area = polygon_area(profile_xy)
    need = MESH_VOLUME_MARGIN * MUJOCO_MIN_MESH_VOLUME / (2 * area) if area > 0 else math.inf
    if not need <= MAX_THICKNESS_RATIO * size:
        raise SimulationError(
            f"the cam's profile (size {size:.3g} m, area {area:.3g} m²) is too small for MuJoCo: a mesh must enclose "
            f"at least {MUJOCO_MIN_MESH_VOLUME:g} m³, which would take a disc {need / size:.3g} times thicker than "
            "wide, beyond what MuJoCo's convex hull resolves; MuJoCo cannot model this cam")
    return max(HALF_THICKNESS * size, need)


def cam_mjcf(cm: CamMechanism) -> str:
    """The MJCF text (module docstring)."""
    _check_convex(cm)
    f = cm.follower
    size = 2 * float(np.hypot(*f.pitch_curve(np.linspace(0, 2 * math.pi, 73))[0].T).max())
    dt = timestep(cm)
    th = np.linspace(0.0, 2 * math.pi, PROFILE_POINTS, endpoint=False)
    rr = f.roller_radius if f.roller_radius > 0 else KNIFE_RADIUS * f.base_radius
    prof = f.profile(th, rr)  # a knife edge's small roller touches, not cuts into, the pitch curve
    half = extrusion_half(prof, size)
    root = etree.Element("mujoco", model=cm.name)
    root.append(comment(f" {cm.title or cm.name}: written by linkgen from the cam description. "
                              f"Contacts as stiff as the timestep allows; the follower's spring is {SPRING}. "))
    etree.SubElement(root, "compiler", angle="radian", inertiafromgeom="false")
    etree.SubElement(root, "option", timestep=_f(dt), integrator=INTEGRATOR, gravity=f"{_f(cm.gravity[0])} {_f(cm.gravity[1])} 0",
                     ccd_tolerance=_f(CCD_TOLERANCE), ccd_iterations=str(CCD_ITERATIONS), cone="pyramidal")
    default = etree.SubElement(root, "default")  # only the profile and the roller collide (set on them)
    etree.SubElement(default, "geom", contype="0", conaffinity="0")
    visual = etree.SubElement(root, "visual")
    etree.SubElement(visual, "global", offwidth="1280", offheight="960")
    etree.SubElement(visual, "headlight", ambient="0.25 0.25 0.25", diffuse="0.45 0.45 0.45", specular="0.05 0.05 0.05")
    asset = etree.SubElement(root, "asset")
    vert = " ".join(f"{_f(x)} {_f(y)} {_f(z)}" for z in (-half, half) for x, y in prof)
    etree.SubElement(asset, "mesh", name="cam:profile", vertex=vert)
    add_scene_assets(asset)
    world = etree.SubElement(root, "worldbody")
    etree.SubElement(world, "light", pos=f"0 0 {_f(5 * size)}", dir="0 0 -1", directional="true",
                     diffuse="0.35 0.35 0.35", specular="0.05 0.05 0.05")
    r = 0.5 * size  # the pitch curve's largest radius; the follower's pivot or stem beyond it
    reach = max(r, f.pivot_distance + 0.1 * r) if f.kind == "oscillating" else r
    top = r if f.kind == "oscillating" else f.lift_origin + float(np.ptp(f.output(th)[0])) + 0.3 * size
    add_scene(world, (-r, reach, -r, max(r, top)), size)
    # The follower's body stands where the closed form has it at θ = 0, its joint's ref there
    # (MuJoCo's qpos0): the model as loaded starts with the roller on the cam, the joint's
    # coordinate still the follower's from its lowest position. At qpos 0 (the lowest position) the
    # roller would sit inside a cam whose lift at θ = 0 is not 0 (cam_oscillating: 0.31 rad, the
    # roller 2× its radius deep), where the convex collision finds the shortest way out through
    # the extrusion's flat faces: a contact normal along z, a force of ~1e18 N with a stray
    # in-plane part, MuJoCo's BADQACC at the first step (a sphere roller scaled to 1e-2).
    q0 = float(state(cm, [0.0]).displacement[0])
    contact = {"solref": f"{_f(CONTACT_TIME * dt)} 1", "solimp": "0.9999 0.9999 0.001 0.5 2", "condim": "1", "margin": "0",
               "friction": "0 0 0"}
    cam = etree.SubElement(world, "body", name=CAM)
    etree.SubElement(cam, "joint", name=CAM, type="hinge", axis="0 0 1", armature=_f(rotor_inertia(cm)))
    etree.SubElement(cam, "inertial", pos="0 0 0", mass="1", diaginertia="1e-3 1e-3 1e-3")
    etree.SubElement(cam, "geom", name="cam:profile", type="mesh", mesh="cam:profile", rgba="0.85 0.3 0.2 1",
                     contype="1", conaffinity="2", **contact)
    if f.kind == "translating":
        fol = etree.SubElement(world, "body", name=FOLLOWER, pos=f"{_f(f.offset)} {_f(f.lift_origin + q0)} 0")
        etree.SubElement(fol, "joint", name=FOLLOWER, type="slide", axis="0 1 0", ref=_f(q0))
        etree.SubElement(fol, "inertial", pos="0 0 0", mass=_f(max(cm.mass, 1e-6)), diaginertia="1e-6 1e-6 1e-6")
        roller_pos = "0 0 0"
        if 0.3 * size >= MUJOCO_MIN_BAR:  # a drawing only: MuJoCo refuses shorter capsules
            etree.SubElement(fol, "geom", name="follower:stem", type="capsule", fromto=f"0 0 0 0 {_f(0.3 * size)} 0",
                             size=_f(0.01 * size), rgba="0.25 0.45 0.8 1", contype="0", conaffinity="0")
        # the fixed guide along the follower's stroke over the turn (linkgen.mujoco.guides), past the roller
        # (a flat face's thickness) at each end: a strip behind the cam, wider than the roller and the stem
        lift, block = f.output(th)[0], 0.01 * size if f.flat else rr
        mid, glen = guide_span(float(lift.min()), float(lift.max()), block, size)
        g, width = GUIDE_SIZE[1] * size, (1.0 + 2.0 * GUIDE_OVERHANG) * max(block, 0.02 * size)
        etree.SubElement(world, "geom", name=f"ground:guide:{FOLLOWER}", type="box", size=f"{_f(width)} {_f(glen)} {_f(g)}",
                         pos=f"{_f(f.offset)} {_f(f.lift_origin + mid)} {_f(-half - 2 * g)}", material="mat:ground")
        bias = f"{_f(-cm.spring_preload)} {_f(-cm.spring_rate)} 0"
    else:
        psi0 = f.psi0
        fol = etree.SubElement(world, "body", name=FOLLOWER, pos=f"{_f(f.pivot_distance)} 0 0",
                               axisangle=f"0 0 1 {_f(-q0)}")
        etree.SubElement(fol, "joint", name=FOLLOWER, type="hinge", axis="0 0 1", ref=_f(-q0))
        etree.SubElement(fol, "inertial", pos="0 0 0", mass="1",
                         diaginertia=" ".join([_f(max(cm.inertia, 1e-9))] * 3))
        x, y = -f.arm_length * math.cos(psi0), f.arm_length * math.sin(psi0)
        roller_pos = f"{_f(x)} {_f(y)} 0"
        if f.arm_length >= MUJOCO_MIN_BAR:  # a drawing only: MuJoCo refuses shorter capsules
            etree.SubElement(fol, "geom", name="follower:arm", type="capsule", fromto=f"0 0 0 {_f(x)} {_f(y)} 0",
                             size=_f(0.01 * size), rgba="0.25 0.45 0.8 1", contype="0", conaffinity="0")
        # q = −(ψ − ψ0): the spring torque (preload + rate·(ψ − ψ0)) turns the arm towards the cam, +q
        bias = f"{_f(cm.spring_preload)} {_f(-cm.spring_rate)} 0"
    if f.flat:  # the face, square to the motion, wide enough for every contact point x = ds/dθ
        reach = float(np.abs(f.output(th)[1]).max()) + 0.05 * size
        thick = 0.01 * size
        etree.SubElement(fol, "geom", name=CONTACT, type="box", pos=f"{_f(-f.offset)} {_f(thick)} 0",
                         size=f"{_f(reach)} {_f(thick)} {_f(half)}", rgba="0.25 0.45 0.8 1", contype="2",
                         conaffinity="1", **contact)
    else:
        etree.SubElement(fol, "geom", name=CONTACT, type=ROLLER_GEOM, pos=roller_pos, size=_f(rr),
                         rgba="0.25 0.45 0.8 1", contype="2", conaffinity="1", **contact)
    actuator = etree.SubElement(root, "actuator")
    etree.SubElement(actuator, "general", name=SPRING, joint=FOLLOWER, gainprm="0", biastype="affine", biasprm=bias)
    return etree.tostring(root, encoding="unicode", pretty_print=True)


__all__ = ["CAM_TOLERANCES", "INTEGRATOR", "ROLLER_GEOM", "cam_mjcf", "cam_timestep", "quantity_names",
           "rotor_inertia", "timestep"]
