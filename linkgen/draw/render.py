"""MuJoCo offscreen frames of the generated model, with no display.

MuJoCo picks its OpenGL backend from ``MUJOCO_GL`` when it is first imported (GLFW by default,
which needs a display). When ``MUJOCO_GL`` is not set, linkgen tries the headless backends
itself — EGL, then OSMesa, then GLFW where a display exists — and says plainly which were tried
and why each failed when none opens a context."""

from __future__ import annotations

import contextlib
import os
import sys

import mujoco
import numpy as np

from linkgen.draw.limits import MAX_HEIGHT, MAX_WIDTH, MIN_SIDE  # MuJoCo's offscreen buffer
from linkgen.errors import RenderError
from linkgen.mujoco.log import no_log_file

CAMERA = "overview"


def _backend_class(name: str):
    if name == "egl":
        from mujoco.egl import GLContext
    elif name == "osmesa":
        from mujoco.osmesa import GLContext
    else:
        from mujoco.glfw import GLContext
    return GLContext


def _candidates() -> list[str]:
    chosen = os.environ.get("MUJOCO_GL", "").strip().lower()
    if chosen:
        return [chosen]
    names = ["egl", "osmesa"] if sys.platform.startswith("linux") else []
    if not sys.platform.startswith("linux") or os.environ.get("DISPLAY") or os.environ.get("WAYLAND_DISPLAY"):
        names.append("glfw")
    return names


@contextlib.contextmanager
def _quiet_stderr():
    """MuJoCo's GL backends print warnings of their own while probing; keep them off the terminal."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        yield


def renderer(model: mujoco.MjModel, width: int, height: int) -> mujoco.Renderer:
    """A ``mujoco.Renderer`` on the first OpenGL backend that opens (see the module docstring).

    Raises:
        RenderError: the size exceeds the offscreen buffer, or no backend opened a context.
    """
    if not (MIN_SIDE <= width <= MAX_WIDTH and MIN_SIDE <= height <= MAX_HEIGHT):
        raise RenderError(f"frame size {width}×{height} px: allowed {MIN_SIDE}..{MAX_WIDTH} × {MIN_SIDE}..{MAX_HEIGHT} px "
                          f"(MuJoCo's offscreen buffer in the written model)")
    from mujoco.rendering.classic import gl_context

    tried = []
    for name in _candidates():
        try:
            with _quiet_stderr():
                cls = _backend_class(name)
                saved = getattr(gl_context, "GLContext", None)
                gl_context.GLContext = cls
                try:
                    return mujoco.Renderer(model, height, width)
                finally:
                    gl_context.GLContext = saved
        except Exception as exc:  # noqa: BLE001 — every backend failure is reported together below
            tried.append(f"{name}: {str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__}")
    raise RenderError("MuJoCo could not open an OpenGL context for offscreen rendering (tried "
                      + "; ".join(tried or ["no backend: MUJOCO_GL names none"]) + "). Install EGL (libegl1) "
                      "or OSMesa (libosmesa6), or set MUJOCO_GL to a backend this machine has.")


def render_states(model: mujoco.MjModel, qpos: np.ndarray, width: int = 640, height: int = 480,
                  camera: str = CAMERA) -> list[np.ndarray]:
    """RGB frames (height, width, 3) uint8 of ``model`` at each row of ``qpos`` (m, nq), seen
    by the named camera."""
    data = mujoco.MjData(model)
    r = renderer(model, width, height)
    frames = []
    try:
        for q in np.atleast_2d(qpos):
            data.qpos[:] = q
            data.qvel[:] = 0.0
            mujoco.mj_forward(model, data)
            r.update_scene(data, camera=camera)
            frames.append(r.render().copy())
    finally:
        r.close()
    return frames


@no_log_file()  # MuJoCo's warnings stay out of the user's folder (linkgen.mujoco.log)
def render_mechanism(mech, phi, width: int = 640, height: int = 480) -> tuple[mujoco.MjModel, list[np.ndarray]]:
    """Frames of the mechanism's generated model at crank angles ``phi`` [rad] (scalar or (m,)),
    posed from the closed-form (or numeric) pose."""
    from linkgen.mujoco.mjcf import write_mjcf
    from linkgen.mujoco.state import tree_state

    model = mujoco.MjModel.from_xml_string(write_mjcf(mech))
    qpos, _ = tree_state(mech, model, np.atleast_1d(np.asarray(phi, dtype=float)))
    return model, render_states(model, qpos, width, height)


__all__ = ["CAMERA", "RenderError", "render_mechanism", "render_states", "renderer"]
