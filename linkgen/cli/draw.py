"""``linkgen draw``, ``linkgen animate`` and ``linkgen render``: pictures of the mechanism."""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

from linkgen.cli.common import OptionError, _angle_arg, _positive_int, add_out_argument, allowed_text, output_kind, whole_in
from linkgen.draw.limits import MAX_FRAMES, MAX_HEIGHT, MAX_WIDTH, MIN_FRAMES, MIN_SIDE

FIGURE_FORMATS = ("png", "svg", "pdf")
VECTOR_CHOICES = ("velocity", "acceleration", "forces")
PLAN_CHOICES = ("velocity", "acceleration")
# A page's slider: two positions to move at all; 720 (every half degree) keeps the file under ~20 MB.
MIN_PAGE_FRAMES, MAX_PAGE_FRAMES = 2, 720
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
    one = [f"--{k.replace('_', '-')}" for k in ("vectors", "plan", "free_body") if getattr(args, k) is not None]
    if args.parts:
        one.append("--parts")
    if args.angles is not None and one:
        raise OptionError(f"{one[0]} draws at one crank angle (--angle); it cannot be combined with --angles")
    if args.plan is not None and len(one) > 1:
        raise OptionError(f"--plan draws the plan alone; it cannot be combined with {one[1] if one[0] == '--plan' else one[0]}")
    if args.parts and args.vectors != "acceleration":
        raise OptionError("--parts splits accelerations: it needs --vectors acceleration")
    desc = load(args.model)
    draw = stage(desc, "draw")
    with atomic_output(args.out) as tmp:
        what, _ = draw(desc, args.angles if args.angles is not None else args.angle, tmp, vectors=args.vectors,
                       parts=args.parts, free_body=args.free_body, plan=args.plan)
    print(f"wrote {args.out}: {what}")
    return 0


PAGE = {".html": "the interactive page"}


def cmd_page(args) -> int:
    from linkgen.cli.files import atomic_output
    from linkgen.pipeline.registry import load, stage

    output_kind(args, args.out, PAGE)
    desc = load(args.model)
    with atomic_output(args.out) as tmp:
        what = stage(desc, "page")(desc, tmp, args.frames, mujoco=args.mujoco,
                                   progress=_run_progress(f"running {args.model.name} in MuJoCo") if args.mujoco else None)
    print(f"wrote {args.out}: {what}")
    return 0


def _run_progress(label: str):
    def report(done: float, elapsed: float) -> None:
        print(f"\r{label}: {100.0 * done:.0f}% after {elapsed:.0f} s", end="\n" if done >= 1.0 else "", file=sys.stderr,
              flush=True)

    return report


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
    d.add_argument("--angle", type=_angle_arg,
                   help="crank angle with its unit, e.g. 30deg (default: the first pose from the range's start, "
                        "in 15° steps, off dead centres, dwells and limit positions; a spatial chain's sketch pose)")
    d.add_argument("--angles", type=angles_arg,
                   help="a position plan at START:STOP:STEP, degrees unless a unit is given, e.g. 0:360:30 "
                        "or 0:3.14:0.5rad; every moving point's path is traced over the drive's range")
    d.add_argument("--vectors", choices=VECTOR_CHOICES,
                   help="also draw arrows at one crank angle, to a stated scale: the moving points' velocities "
                        "[m/s] or accelerations [m/s²], or the forces [N] (loads with their crank-angle range, weights, "
                        "reactions)")
    d.add_argument("--parts", action="store_true",
                   help="with --vectors acceleration: also split each acceleration into its tangential and normal "
                        "parts")
    d.add_argument("--free-body", metavar="GROUP",
                   help="the forces on one Assur group alone (its numbers, e.g. 2,3, or a link's name): the "
                        "reactions of its outer pairs, its loads and inertia forces")
    d.add_argument("--plan", choices=PLAN_CHOICES,
                   help="instead of the skeleton, the velocity [m/s] or acceleration [m/s²] plan at one crank angle: "
                        "the polygons from a pole, to scale")
    d.set_defaults(func=cmd_draw)

    g = sub.add_parser("page", help="one self-contained interactive HTML page: the mechanism under a crank-angle "
                                    "slider with a play button, its vectors, curves and design summary")
    g.add_argument("model", type=Path, help="description file (.toml)")
    add_out_argument(g, f"write {allowed_text(PAGE)}", required=True, metavar="FILE")
    g.add_argument("--frames", type=whole_in(MIN_PAGE_FRAMES, MAX_PAGE_FRAMES), default=72,
                   help=f"crank angles on the slider (no unit; default 72, {MIN_PAGE_FRAMES} to {MAX_PAGE_FRAMES})")
    g.add_argument("--mujoco", action="store_true",
                   help="also run the linkage in MuJoCo over its drive range and draw MuJoCo's curves beside the "
                        "closed form's (planar linkages)")
    g.set_defaults(func=cmd_page)

    a = sub.add_parser("animate", help="the mechanism moving over its drive range, with its point paths")
    a.add_argument("model", type=Path, help="description file (.toml)")
    add_out_argument(a, f"write {allowed_text(ANIMATION)}", old=("--output",), required=True, metavar="FILE")
    a.add_argument("--frames", type=whole_in(MIN_FRAMES, MAX_FRAMES), default=72,
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
    r.add_argument("--width", type=whole_in(MIN_SIDE, MAX_WIDTH), default=800,
                   help=f"image width [px] (default 800, {MIN_SIDE} to {MAX_WIDTH})")
    r.add_argument("--height", type=whole_in(MIN_SIDE, MAX_HEIGHT), default=600,
                   help=f"image height [px] (default 600, {MIN_SIDE} to {MAX_HEIGHT})")
    r.set_defaults(func=cmd_render)


__all__ = ["add_commands", "angles_arg"]
