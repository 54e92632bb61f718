"""A linkage's cam pairs in MuJoCo: the cam's profile as a mesh on the crank's body, the roller a
sphere (``linkgen.mujoco.cam.ROLLER_GEOM``) on the follower's body at its centre, the follower's
spring an affine actuator on its joint with the ground — the same contact model as a
stand-alone cam (``linkgen.mujoco.cam``: PROFILE_POINTS vertices, CONTACT_TIME timesteps,
frictionless, the convex collision to CCD_TOLERANCE), so the same accuracy: the follower's motion
to ~1e-5 of its stroke and the forces as means over a few degrees of cam turn.

The profile is computed in the crank's frame from the closed form: the roller centre C over a
turn seen from the cam, R(−φ)·(C − O), moved inwards by the roller's radius along the pitch
curve's normal (``linkgen.families.planar.cam_pair``).
"""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
from lxml import etree

from linkgen.errors import SimulationError
from linkgen.families.planar.description import CamPair
from linkgen.mujoco.cam import (CCD_ITERATIONS, CCD_TOLERANCE, CONTACT_TIME, INTEGRATOR, KNIFE_RADIUS, PROFILE_POINTS,
                                ROLLER_GEOM, cam_timestep, extrusion_half)
from linkgen.mujoco.options import Settings
from linkgen.mujoco.tree import body_name
from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.cam_pair import above_lowest, ground_pair, sense
from linkgen.families.planar.cam_profile import profile

# A profile polygon turning the wrong way at a vertex by more than this angle [rad] is concave
# there (a convex polygon of PROFILE_POINTS vertices turns by 2π/PROFILE_POINTS per vertex on a
# circle; rounding of the closed form is ~1e-12).
CONCAVE_TOL = 1e-9
# Cam angles over a turn at which a cam's motion is sampled for its timestep.
CAM_SAMPLES = 3600


def spring_name(cam: CamPair) -> str:
    return f"cam:{cam.name}:spring"


def roller_name(cam: CamPair) -> str:
    return f"cam:{cam.name}:roller"


def profile_name(cam: CamPair) -> str:
    return f"cam:{cam.name}:profile"


def check_convex(cam: CamPair, prof: np.ndarray, phi_s: float) -> None:
    """MuJoCo collides a mesh as its convex hull: a profile concave anywhere is refused, naming
    the crank angles where."""
    e = np.roll(prof, -1, axis=0) - prof
    f = np.roll(e, -1, axis=0)
    turn = (e[:, 0] * f[:, 1] - e[:, 1] * f[:, 0]) / np.maximum(np.hypot(*e.T) * np.hypot(*f.T), np.finfo(float).tiny)
    area = float(np.sum(prof[:, 0] * np.roll(prof[:, 1], -1) - np.roll(prof[:, 0], -1) * prof[:, 1]))
    bad = np.sign(area) * turn < -CONCAVE_TOL  # the cam turns one way, the profile is traced the other
    if np.any(bad):
        k = int(np.flatnonzero(bad)[0])
        at = math.degrees(phi_s + 2 * math.pi * (k + 1) / prof.shape[0])
        raise SimulationError(f"cam {cam.name!r}: its profile is concave near crank angle {at:.4g}° ({int(bad.sum())} of "
                              f"{prof.shape[0]} vertices); MuJoCo collides a mesh as its convex hull, so linkgen does "
                              f"not model this cam in MuJoCo (a smaller roller or a larger cam makes it convex)")


def cam_settings(asm: Assembly, settings: Settings) -> Settings:
    """The settings with the step every cam pair needs (``mujoco.cam.cam_timestep``) and the
    cams' integrator (``mujoco.cam.INTEGRATOR``: contacts found once per step)."""
    th = np.linspace(0.0, 2 * math.pi, CAM_SAMPLES, endpoint=False)
    omega = abs(asm.mechanism.drive.omega)
    dt = min([settings.timestep] + [cam_timestep(omega, *cam.program.displacement(th)[2:]) for cam in asm.mechanism.cams])
    return replace(settings, timestep=dt, integrator=INTEGRATOR)


def add_cams(root, asm: Assembly, settings: Settings, size: float) -> None:
    """Add every cam pair's mesh, roller, contact settings and spring to the MJCF tree ``root``
    (``size`` [m]: the mechanism's, which scales the geoms)."""
    mech = asm.mechanism
    option = root.find("option")
    option.set("ccd_tolerance", repr(CCD_TOLERANCE))
    option.set("ccd_iterations", str(CCD_ITERATIONS))
    option.set("cone", "pyramidal")
    asset = root.find("asset")
    actuator = root.find("actuator")
    contact = {"solref": f"{CONTACT_TIME * settings.timestep!r} 1", "solimp": "0.9999 0.9999 0.001 0.5 2",
               "condim": "1", "margin": "0", "friction": "0 0 0"}
    o = np.asarray(mech.points[mech.revolute(mech.drive.joint).point], dtype=float)
    for cam in mech.cams:
        radius = cam.roller_radius or KNIFE_RADIUS * math.dist(o, mech.points[cam.roller])
        prof = profile(asm, cam, PROFILE_POINTS, radius)  # a knife edge's small roller touches, not cuts into, it
        check_convex(cam, prof, asm.sketch_phi)
        half = float(extrusion_half(prof, size))
        vert = " ".join(f"{x!r} {y!r} {z!r}" for z in (-half, half) for x, y in prof.tolist())
        etree.SubElement(asset, "mesh", name=profile_name(cam), vertex=vert)
        crank = root.find(f".//body[@name='{body_name(mech.crank)}']")
        etree.SubElement(crank, "geom", name=profile_name(cam), type="mesh", mesh=profile_name(cam),
                         material="mat:crank", contype="1", conaffinity="2", group="0", **contact)
        follower = root.find(f".//body[@name='{body_name(cam.follower)}']")
        local = asm.shapes[cam.follower].local[cam.roller]
        etree.SubElement(follower, "geom", name=roller_name(cam), type=ROLLER_GEOM, pos=f"{float(local[0])!r} {float(local[1])!r} 0",
                         size=f"{float(radius)!r}", material="mat:link", contype="2", conaffinity="1", group="0",
                         **contact)
        # the spring's torque (force) on the follower's joint: −σ·(preload + rate·(q − q_lowest)), with
        # q − q_lowest = q(0) − q_lowest + σ·qpos (the joint turns, or slides, by σ·δ from the sketch)
        sig = sense(mech, asm.shapes, cam)
        start = float(above_lowest(cam, np.zeros(1))[0])
        bias = (-sig * (cam.spring_preload + cam.spring_rate * start), -cam.spring_rate, 0.0)
        actuator.append(etree.Comment(f" {spring_name(cam)}: the spring holding the follower of cam {cam.name} on "
                                      f"the cam "))
        etree.SubElement(actuator, "general", name=spring_name(cam), joint=ground_pair(mech, cam)[1].name,
                         gainprm="0", biastype="affine", biasprm=" ".join(repr(float(b)) for b in bias))


__all__ = ["CONCAVE_TOL", "add_cams", "cam_settings", "check_convex", "profile_name", "roller_name", "spring_name"]
