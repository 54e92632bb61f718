"""``linkgen draw``, ``linkgen animate`` and ``linkgen render``: pictures of the mechanism."""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

from linkgen.cli.common import OptionError, _angle_arg, _positive_int, add_out_argument, allowed_text, output_kind
from linkgen.draw.limits import MAX_FRAMES, MAX_HEIGHT, MAX_WIDTH, MIN_FRAMES, MIN_SIDE


def _whole_in(lo: int, hi: int):
    """An argparse type: a whole number from ``lo`` to ``hi``, refused with the range it allows."""

    def parse(text: str) -> int:
        try:
            n = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
        if not lo <= n <= hi:
            raise argparse.ArgumentTypeError(f"expected a whole number from {lo} to {hi}, got {text!r}")
        return n

    return parse

FIGURE_FORMATS = ("png", "svg", "pdf")
# A position plan of more positions than this is a smear, not a drawing.
MAX_PLAN_POSITIONS = 73


def _angle_part(text: str, unit: str | None) -> float:
    t = text.strip()
    if unit == "m":  # a prismatic drive's strokes [m]
        return float(t.removesuffix("m"))
    for suffix, to_rad in (("deg", math.radians), ("°", math.radians), ("rad", float)):
        if t.endswith(suffix):
            return to_rad(float(t[: -len(suffix)]))
    x = float(t)
    return x if unit == "rad" else math.radians(x)


def angles_arg(text: str) -> np.ndarray:
    """``START:STOP:STEP``, in degrees unless a unit is given (``0:360:30``, ``0deg:180deg:15deg``,
    ``0:3:0.5rad`` — a unit on the last part applies to the parts without one; strokes of a prismatic
    drive in metres with ``m`` on the last part, ``0.3:0.6:0.05m``): the angles
    START, START + STEP, … up to STOP [rad], STOP included when it falls on the grid (but not
    when it repeats START a full turn later)."""
    parts = text.split(":")
    if len(parts) != 3:
        raise argparse.ArgumentTypeError(f"expected START:STOP:STEP such as 0:360:30 (degrees) or 0:3.14:0.5rad, "
                                         f"got {text!r}")
    last = parts[2].strip()
    unit = "rad" if last.endswith("rad") else "m" if last.endswith("m") and not last.endswith("mm") else None
    try:
        start, stop, step = (_angle_part(p, unit) for p in parts)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected three numbers with an optional unit (deg, °, rad; m for a "
                                         f"prismatic drive's strokes), got {text!r}") from None
    if not all(math.isfinite(x) for x in (start, stop, step)) or step <= 0.0 or stop < start:
        raise argparse.ArgumentTypeError(f"expected STEP > 0 and STOP >= START, got {text!r}")
    count = int(math.floor((stop - start) / step * (1 + 1e-12))) + 1
    if count > MAX_PLAN_POSITIONS:
        raise argparse.ArgumentTypeError(f"{text!r} gives {count} positions; a position plan shows at most "
                                         f"{MAX_PLAN_POSITIONS} (take a larger step)")
    phi = start + step * np.arange(count)
    if count > 1 and abs((phi[-1] - phi[0]) - 2 * math.pi) < 1e-9:
        phi = phi[:-1]
    return phi


# What -o/--out writes, by extension (``common.output_kind``).
DRAWING = {f".{f}": "the drawing" for f in FIGURE_FORMATS}
ANIMATION = {".gif": "the animation", ".mp4": "the animation, with the video extra: pip install 'linkgen[video]'"}
FRAME = {".png": "MuJoCo's frame"}


def _progress(label: str):
    def report(done: int, total: int) -> None:
        if sys.stderr.isatty() or done == total:
            print(f"\r{label}: {done}/{total} frames", end="\n" if done == total else "", file=sys.stderr, flush=True)

    return report


def cmd_draw(args) -> int:
    from linkgen.cli.files import atomic_output
    from linkgen.pipeline.registry import load, stage

    output_kind(args, args.out, DRAWING)
    if args.angle is not None and args.angles is not None:
        raise OptionError("--angle cannot be combined with --angles: --angle draws one position, --angles a plan")
    desc = load(args.model)
    draw = stage(desc, "draw")
    with atomic_output(args.out) as tmp:
        what = draw(desc, args.angles if args.angles is not None else args.angle, tmp)
    print(f"wrote {args.out}: {what}")
    return 0


def cmd_animate(args) -> int:
    from linkgen.cli.files import atomic_output
    from linkgen.draw.animate import save_animation
    from linkgen.pipeline.registry import load, stage

    output_kind(args, args.out, ANIMATION)
    desc = load(args.model)
    frames, how = stage(desc, "animate")(desc, args.frames, progress=_progress(f"drawing {args.out.name}"),
                                         mujoco=args.mujoco,
                                         notice=lambda text: print(text, file=sys.stderr, flush=True))
    with atomic_output(args.out) as tmp:
        save_animation(frames, tmp, args.fps)
    h, w = frames[0].shape[:2]
    print(f"wrote {args.out}: {len(frames)} frames of {w}×{h} px at {args.fps} frames/s{how}")
    return 0


def cmd_render(args) -> int:
    from PIL import Image

    from linkgen.cli.files import atomic_output
    from linkgen.pipeline.registry import load, stage

    output_kind(args, args.out, FRAME)
    desc = load(args.model)
    frame, what = stage(desc, "render")(desc, args.angle, args.width, args.height)
    with atomic_output(args.out) as tmp:
        Image.fromarray(frame).save(tmp, format="PNG")
    print(f"wrote {args.out}: {what}, {args.width}×{args.height} px, camera 'overview'")
    return 0


def add_commands(sub) -> None:
    d = sub.add_parser("draw", help="the mechanism's skeleton at one crank angle, or a position plan")
    d.add_argument("model", type=Path, help="description file (.toml)")
    add_out_argument(d, f"write {allowed_text(DRAWING)}", old=("--output",), required=True, metavar="FILE")
    d.add_argument("--angle", type=_angle_arg, help="crank angle with its unit, e.g. 30deg (default: the range's start)")
    d.add_argument("--angles", type=angles_arg,
                   help="a position plan at START:STOP:STEP, degrees unless a unit is given, e.g. 0:360:30 "
                        "or 0:3.14:0.5rad; every moving point's path is traced over the drive's range")
    d.set_defaults(func=cmd_draw)

    a = sub.add_parser("animate", help="the mechanism moving over its drive range, with its point paths")
    a.add_argument("model", type=Path, help="description file (.toml)")
    add_out_argument(a, f"write {allowed_text(ANIMATION)}", old=("--output",), required=True, metavar="FILE")
    a.add_argument("--frames", type=_whole_in(MIN_FRAMES, MAX_FRAMES), default=72,
                   help=f"frames over the range (no unit; default 72, {MIN_FRAMES} to {MAX_FRAMES})")
    a.add_argument("--fps", type=_positive_int, default=24, help="frames per second of the file (default 24)")
    a.add_argument("--mujoco", action="store_true",
                   help="also run the mechanism in MuJoCo and show its rendered frames beside the closed-form "
                        "drawing, at the crank angles MuJoCo reached (needs EGL or OSMesa without a display)")
    a.set_defaults(func=cmd_animate)

    r = sub.add_parser("render", help="a MuJoCo offscreen frame of the generated model at one crank angle")
    r.add_argument("model", type=Path, help="description file (.toml)")
    add_out_argument(r, f"write {allowed_text(FRAME)}", old=("--output",), required=True, metavar="FILE")
    r.add_argument("--angle", type=_angle_arg, help="crank angle with its unit, e.g. 30deg (default: the range's start)")
    r.add_argument("--width", type=_whole_in(MIN_SIDE, MAX_WIDTH), default=800,
                   help=f"image width [px] (default 800, {MIN_SIDE} to {MAX_WIDTH})")
    r.add_argument("--height", type=_whole_in(MIN_SIDE, MAX_HEIGHT), default=600,
                   help=f"image height [px] (default 600, {MIN_SIDE} to {MAX_HEIGHT})")
    r.set_defaults(func=cmd_render)


__all__ = ["add_commands", "angles_arg"]
