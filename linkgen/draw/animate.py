"""The mechanism in motion: an animated GIF (or MP4 where an encoder is installed) of the skeleton
over the drive's range with every moving point's path, and optionally MuJoCo's own rendered
frames of a MuJoCo run beside it at the same crank angles."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Callable

import numpy as np

from linkgen.model.turn import full_turn
from linkgen.draw.plan import draw_paths, plt_module, title_of
from linkgen.draw.skeleton import draw_skeleton, frame_of, set_limits
from linkgen.draw.limits import MAX_FRAMES, MIN_FRAMES
from linkgen.errors import ArgumentError
from linkgen.families.planar.description import Mechanism
from linkgen.families.planar.positions import Positions, drive_angles, positions

FRAMES = 72  # default: one every 5° over a full revolution
FPS = 24
PANEL = (6.0, 4.5)  # inches per panel
DPI = 80
FORMATS = ("gif", "mp4")


def frame_angles(mech: Mechanism, frames: int) -> np.ndarray:
    """``frames`` crank angles [rad] over the drive's range: a full turn without repeating its
    start, a partial range from end to end."""
    if not (MIN_FRAMES <= frames <= MAX_FRAMES):
        raise ArgumentError(f"frames must be {MIN_FRAMES}..{MAX_FRAMES}, got {frames}")
    d = mech.drive
    if full_turn(mech):
        return d.start + (d.stop - d.start) * np.arange(frames) / frames
    return np.linspace(d.start, d.stop, frames)


def _canvas_rgb(fig) -> np.ndarray:
    fig.canvas.draw()
    return np.asarray(fig.canvas.buffer_rgba())[:, :, :3].copy()


def drawn_frames(mech: Mechanism, phi: np.ndarray, mujoco_frames: list[np.ndarray] | None = None,
                 progress: Callable[[int, int], None] | None = None) -> list[np.ndarray]:
    """RGB frames (h, w, 3) uint8: the closed-form skeleton at each crank angle ``phi`` [rad]
    with the point paths, and the matching MuJoCo frame to its right when given."""
    plt = plt_module()
    paths = positions(mech, drive_angles(mech))
    frame = frame_of(paths)
    pos = positions(mech, phi)
    panels = 2 if mujoco_frames is not None else 1
    fig, axes = plt.subplots(1, panels, figsize=(PANEL[0] * panels, PANEL[1]), dpi=DPI, layout="constrained",
                             squeeze=False)
    ax = axes[0, 0]
    out = []
    try:
        for i in range(len(pos)):
            ax.cla()
            draw_paths(ax, paths, lw=0.8)
            draw_skeleton(ax, pos, frame, i)
            set_limits(ax, paths, frame)
            ax.set_title(f"closed form, s = {float(phi[i]):.4g} m" if mech.slide_drive else
                         f"closed form, φ = {math.degrees(float(phi[i])):.1f}°", fontsize=10)
            if mujoco_frames is not None:
                m = axes[0, 1]
                m.cla()
                m.imshow(mujoco_frames[i])
                m.set_axis_off()
                m.set_title("MuJoCo run", fontsize=10)
            fig.suptitle(title_of(mech, 60 * panels), fontsize=9)
            out.append(_canvas_rgb(fig))
            if progress:
                progress(i + 1, len(pos))
    finally:
        plt.close(fig)
    return out


def mujoco_run_frames(mech: Mechanism, frames: int, width: int = 480, height: int = 360
                      ) -> tuple[np.ndarray, list[np.ndarray]]:
    """A MuJoCo run of the mechanism over its drive range (its validation settings), sampled at
    ``frames`` states: the crank angles MuJoCo reached [rad] (frames,) and its rendered frames."""
    from linkgen.draw.render import render_states
    from linkgen.mujoco.simulate import simulate_mechanism

    run = simulate_mechanism(mech, samples=frames, settle=False)
    phi = np.asarray(run.samples.crank[0], dtype=float)
    return phi, render_states(run.model, run.samples.qpos, width, height)


def save_animation(frames: list[np.ndarray], out: Path, fps: int = FPS) -> None:
    """Write the frames as an animated GIF (pillow) or MP4 (H.264 through imageio and
    imageio-ffmpeg, the ``video`` extra), by ``out``'s suffix; atomically, never through a
    symlink (``linkgen.outputs``).

    Raises:
        ArgumentError: the suffix is neither, or MP4 was asked for without an encoder installed.
    """
    from linkgen.outputs import atomic_output

    kind = Path(out).suffix.lstrip(".").lower()
    if kind not in FORMATS:
        raise ArgumentError(f"{out}: an animation is written as {' or '.join('.' + f for f in FORMATS)}, "
                            f"got {'.' + kind if kind else 'no suffix'}")
    with atomic_output(out) as tmp:
        _save_animation(frames, tmp, kind, fps, out)


def _save_animation(frames: list[np.ndarray], tmp: Path, kind: str, fps: int, out: Path) -> None:
    if kind == "gif":
        from PIL import Image

        images = [Image.fromarray(f) for f in frames]
        images[0].save(tmp, format="GIF", save_all=True, append_images=images[1:], duration=round(1000 / fps),
                       loop=0, optimize=False)
        return
    try:  # mp4
        import imageio.v2 as iio
        import imageio_ffmpeg  # noqa: F401  (the encoder imageio's FFMPEG format needs)
    except ImportError:
        raise ArgumentError(f"{out}: writing MP4 needs imageio and imageio-ffmpeg "
                            f"(pip install 'linkgen[video]'); write a .gif instead") from None
    iio.mimwrite(tmp, _even(frames), fps=fps, format="FFMPEG", macro_block_size=1)


def _even(frames: list[np.ndarray]) -> list[np.ndarray]:
    """Frames cropped to even width and height (what H.264 encoders accept)."""
    h, w = (frames[0].shape[0] // 2) * 2, (frames[0].shape[1] // 2) * 2
    return [f[:h, :w] for f in frames]


__all__ = ["FRAMES", "drawn_frames", "frame_angles", "mujoco_run_frames", "save_animation", "Positions"]
