"""A cam's profile in the crank's frame, from the closed-form motion of its follower."""

from __future__ import annotations

import math

import numpy as np

from linkgen.families.planar.description import CamPair
from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.cam_pair import contact_geometry
from linkgen.families.planar.groups import input_poses


def profile(asm: Assembly, cam: CamPair, points: int = 720, radius: float | None = None) -> np.ndarray:
    """The cam's profile (points, 2) [m] in the crank's frame (origin at the cam's axis, x along
    the crank's first two points) over a turn from the sketch: the roller centre seen from the
    cam, R(−φ)·(C − O), moved inwards by the roller's radius (or ``radius``: MuJoCo gives a
    knife edge a small roller) along the pitch curve's normal."""
    mech = asm.mechanism
    phi = asm.sketch_phi + np.linspace(0.0, 2 * math.pi, points, endpoint=False)
    poses = input_poses(mech, asm.structure, asm.shapes, phi)
    c = poses[cam.follower].point(asm.shapes[cam.follower].local[cam.roller])
    nrm, _ = contact_geometry(mech, asm.shapes, cam, c)
    o = np.asarray(mech.points[mech.revolute(mech.drive.joint).point], dtype=float)
    world = c.p - o - (cam.roller_radius if radius is None else radius) * nrm
    ang = poses[asm.structure.crank].angle.v
    cs, sn = np.cos(ang), np.sin(ang)
    return np.stack([cs * world[:, 0] + sn * world[:, 1], -sn * world[:, 0] + cs * world[:, 1]], axis=1)


def drawn_profiles(mech) -> dict[str, np.ndarray]:
    """Every cam's profile (720, 2) [m] in the crank's frame, by cam name: computed once per
    mechanism (drawings and cameras ask for it at every position)."""
    cached = mech.__dict__.get("_linkgen_cam_profiles")
    if cached is None:
        from linkgen.families.planar.assembly import assemble

        asm = assemble(mech)
        cached = {cam.name: profile(asm, cam) for cam in mech.cams}
        mech.__dict__["_linkgen_cam_profiles"] = cached  # the Mechanism is frozen: derived once
    return cached


def cam_reach(mech) -> float:
    """The largest radius [m] of any cam's profile about the crank's pivot (0 without cams)."""
    return max((float(np.hypot(*p.T).max()) for p in drawn_profiles(mech).values()), default=0.0)


__all__ = ["cam_reach", "drawn_profiles", "profile"]
