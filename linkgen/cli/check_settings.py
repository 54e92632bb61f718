"""``linkgen check-settings``: MuJoCo's accuracy at the user's settings, predicted from the
closed form and MuJoCo's constraint model before any step, measured by a run, and the cheapest
settings that meet a tolerance (``crosscheck.check_settings``)."""

from __future__ import annotations

import argparse
import math
import re
from pathlib import Path

# What -o/--out writes, by extension (``common.output_kind``).
CHECK_SETTINGS = {".json": "the JSON object, as --json prints it"}
# A duration's units, in seconds.
_DURATION_UNITS = {"": 1.0, "s": 1.0, "ms": 1e-3, "us": 1e-6, "µs": 1e-6}


def duration_arg(text: str) -> float:
    """An argparse type: a duration > 0 [s], with its unit or none (seconds): 2ms, 500us, 0.002."""
    m = re.fullmatch(r"\s*([-+0-9.eE]+)\s*(s|ms|us|µs)?\s*", text)
    try:
        x = float(m.group(1)) * _DURATION_UNITS[m.group(2) or ""] if m else math.nan
    except ValueError:
        x = math.nan
    if not math.isfinite(x):
        raise argparse.ArgumentTypeError(f"expected a duration such as 2ms, 500us or 0.002 (seconds), got {text!r}")
    if not x > 0:
        raise argparse.ArgumentTypeError(f"must be > 0 s, got {text!r}")
    return x


def integrator_arg(text: str) -> str:
    from linkgen.mujoco.options import EVALUATIONS

    names = {k.lower(): k for k in EVALUATIONS}
    if text.lower() not in names:
        raise argparse.ArgumentTypeError(f"must be one of {', '.join(EVALUATIONS)}, got {text!r}")
    return names[text.lower()]


def numbers_arg(count: tuple[int, ...], what: str):
    """An argparse type: ``count`` finite numbers separated by spaces (``what`` says which)."""

    def parse(text: str) -> tuple[float, ...]:
        try:
            xs = tuple(float(x) for x in text.split())
        except ValueError:
            xs = ()
        if len(xs) not in count or not all(math.isfinite(x) for x in xs):
            raise argparse.ArgumentTypeError(f"expected {what}, got {text!r}")
        return xs

    return parse


def tolerance_arg(text: str) -> float:
    try:
        x = float(text)
    except ValueError:
        x = math.nan
    if not (math.isfinite(x) and x > 0):
        raise argparse.ArgumentTypeError(f"must be a relative error > 0, e.g. 1e-3, got {text!r}")
    return x


def cmd_check_settings(args) -> int:
    from linkgen.cli.closed_form import _output, write_json
    from linkgen.cli.common import OptionError
    from linkgen.cli.mujoco import _progress  # the progress line every MuJoCo command prints
    from linkgen.crosscheck.check_settings import user_settings
    from linkgen.errors import ArgumentError
    from linkgen.pipeline.registry import load, stage

    path, spelled, fmt = _output(args, CHECK_SETTINGS)
    if args.json and path is not None:
        raise OptionError(f"--json prints what {spelled} {path} writes: give one of them")
    if path is not None:  # a symlink or a folder refused before the runs, not after them
        from linkgen.outputs import check_output

        check_output(path)
    try:
        settings = user_settings(timestep=args.timestep, integrator=args.integrator, solref=args.solref,
                                 solimp=args.solimp)
    except ArgumentError as exc:
        raise OptionError(str(exc)) from None
    desc = load(args.model)
    result = stage(desc, "check_settings")(desc, settings, tolerance=args.tolerance, search=not args.no_search,
                                           progress=_progress(desc.name))
    if args.json or fmt == "json":
        write_json(result.to_dict(), path)
    else:
        print(result.text())
    return 0 if result.ok else 1  # 1: the run failed, or a prediction is off by more than the factor it claims


def add_command(sub) -> None:
    from linkgen.cli.common import add_out_argument, allowed_text
    from linkgen.mujoco.options import MUJOCO_SOLIMP

    c = sub.add_parser("check-settings", help="MuJoCo's accuracy at your settings: predicted before any step, "
                                              "measured, and the cheapest settings meeting a tolerance")
    c.add_argument("model", type=Path, help="description file (.toml) of a planar linkage")
    c.add_argument("--timestep", type=duration_arg, default=2e-3,
                   help="MuJoCo's timestep, with its unit: 2ms, 500us or 0.002 (seconds) (default: MuJoCo's, 2ms)")
    c.add_argument("--integrator", type=integrator_arg, default="Euler",
                   help="Euler, implicitfast or RK4 (default: MuJoCo's, Euler)")
    c.add_argument("--solref", type=numbers_arg((2,), "two numbers: a time constant [s] and a damping ratio"),
                   default=(0.02, 1.0), help="the loops' solref \"timeconst dampratio\" (default: MuJoCo's, \"0.02 1\")")
    c.add_argument("--solimp", type=numbers_arg((3, 5), "3 or 5 numbers: dmin dmax width [midpoint power]"),
                   default=MUJOCO_SOLIMP,
                   help="the loops' solimp \"dmin dmax width midpoint power\" (default: MuJoCo's, \"0.9 0.95 0.001 0.5 2\")")
    c.add_argument("--tolerance", type=tolerance_arg, default=1e-3,
                   help="the largest relative error the cheapest settings must meet on the loop gap and the point "
                        "positions (to the size), the reactions (to the peak reaction) and the crank torque (to its "
                        "peak) (no unit; default 1e-3)")
    c.add_argument("--no-search", action="store_true", help="predict and measure only: no search for cheaper settings")
    c.add_argument("--json", action="store_true", help="print the JSON object -o FILE.json writes")
    add_out_argument(c, f"write {allowed_text(CHECK_SETTINGS)}", metavar="FILE")
    c.set_defaults(func=cmd_check_settings)


__all__ = ["add_command", "duration_arg"]
