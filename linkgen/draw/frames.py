"""Animations and MuJoCo frames of cam mechanisms and spatial four-bars (the planar linkages'
are ``linkgen.draw.animate`` and ``linkgen.draw.render``): each frame is the same drawing
``linkgen draw`` makes, at one angle of a turn; MuJoCo frames show the generated model posed
from the closed form."""

from __future__ import annotations

import math
import tempfile
from pathlib import Path
from typing import Callable

import mujoco
import numpy as np

from linkgen.draw.render import render_states
from linkgen.mujoco.log import no_log_file


def turn_angles(frames: int) -> np.ndarray:
    """``frames`` angles [rad] evenly over one turn from 0."""
    return np.linspace(0.0, 2 * math.pi, frames, endpoint=False)


def _uniform(frames: list[np.ndarray]) -> list[np.ndarray]:
    """Frames padded with white to the largest one's size (a tight bounding box varies a little)."""
    h = max(f.shape[0] for f in frames)
    w = max(f.shape[1] for f in frames)
    out = []
    for f in frames:
        canvas = np.full((h, w, 3), 255, dtype=np.uint8)
        canvas[:f.shape[0], :f.shape[1]] = f
        out.append(canvas)
    return out


def spatial_frames(mech, phi: np.ndarray, progress: Callable[[int, int], None] | None = None) -> list[np.ndarray]:
    """RGB frames (h, w, 3) uint8: the spatial drawing (3-D view and projections) at each crank angle [rad]."""
    from PIL import Image

    from linkgen.draw.spatial import draw_spatial

    out = []
    with tempfile.TemporaryDirectory() as tmp:
        for i, p in enumerate(phi):
            path = Path(tmp) / f"{i}.png"
            draw_spatial(mech, [float(p)], path)
            out.append(np.asarray(Image.open(path).convert("RGB")))
            if progress:
                progress(i + 1, len(phi))
    return _uniform(out)


def cam_frames(cm, theta: np.ndarray, progress: Callable[[int, int], None] | None = None) -> list[np.ndarray]:
    """RGB frames (h, w, 3) uint8: the cam and its follower at each cam angle θ [rad]."""
    from linkgen.draw.cam import cam_figure
    from linkgen.draw.plan import plt_module

    plt = plt_module()
    out = []
    for i, t in enumerate(theta):
        fig = cam_figure(cm, float(t))
        fig.canvas.draw()
        out.append(np.asarray(fig.canvas.buffer_rgba())[:, :, :3].copy())
        plt.close(fig)
        if progress:
            progress(i + 1, len(theta))
    return _uniform(out)


@no_log_file()  # MuJoCo's warnings stay out of the user's folder (linkgen.mujoco.log)
def spatial_render(mech, phi, width: int = 640, height: int = 480) -> list[np.ndarray]:
    """MuJoCo frames of the spatial model at crank angles ``phi`` [rad], posed from the closed form."""
    from linkgen.families.spatial.kinematics import assembled_chain, solve
    from linkgen.mujoco.spatial_mjcf import write_spatial_mjcf
    from linkgen.mujoco.spatial_state import joint_state

    chain = assembled_chain(mech)
    model = mujoco.MjModel.from_xml_string(write_spatial_mjcf(mech, chain=chain))
    phi = np.atleast_1d(np.asarray(phi, dtype=float))
    motion = solve(mech, phi, chain)
    qpos = np.stack([joint_state(model, chain, motion, k, 0.0)[0] for k in range(phi.shape[0])])
    return render_states(model, qpos, width, height)


@no_log_file()  # MuJoCo's warnings stay out of the user's folder (linkgen.mujoco.log)
def cam_render(cm, theta, width: int = 640, height: int = 480) -> list[np.ndarray]:
    """MuJoCo frames of the cam model at cam angles θ [rad], the follower where the closed form puts it."""
    from linkgen.families.cam.kinetics import state
    from linkgen.mujoco.cam import CAM, FOLLOWER, cam_mjcf

    model = mujoco.MjModel.from_xml_string(cam_mjcf(cm))
    theta = np.atleast_1d(np.asarray(theta, dtype=float))
    sign = 1.0 if cm.follower.kind == "translating" else -1.0  # the arm's hinge turns against ψ (mujoco.cam)
    qpos = np.tile(model.qpos0, (theta.shape[0], 1))
    qpos[:, model.joint(CAM).qposadr[0]] = theta
    qpos[:, model.joint(FOLLOWER).qposadr[0]] = sign * state(cm, theta).displacement
    return render_states(model, qpos, width, height, camera="overview")


__all__ = ["cam_frames", "cam_render", "spatial_frames", "spatial_render", "turn_angles"]
