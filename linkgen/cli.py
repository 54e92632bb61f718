"""Command-line interface: ``linkgen structure|analyze|forces|build|simulate|validate``.

User mistakes (LinkgenError, missing files, bad arguments, conflicting options) print one
line to stderr naming the file concerned and exit with status 2; no traceback. A sampled run
(``analyze``/``forces`` with --samples/--csv) writes singular samples marked (column
``singular`` = 1) and exits with status 3 unless --keep-singular is given. Output closed early
by the reader (``linkgen analyze ... | head``) ends quietly with status 141, as a process
stopped by SIGPIPE would.
"""

from __future__ import annotations

import argparse
import csv
import json
import math
import os
import sys
from pathlib import Path

import numpy as np

from . import limits
from .assembly import assemble
from .cli_singular import SINGULAR_STATUS, report_singular
from .errors import DescriptionError, LinkgenError
from .files import atomic_open, message_for
from .kinematics import Kinematics, solve
from .load import load
from .units import parse_angle


def crank_grid(mech, samples: int) -> np.ndarray:
    """``samples`` crank angles [rad] over the drive range (a full turn excludes its end)."""
    d = mech.drive
    full = d.stop - d.start >= 2 * math.pi - 1e-12
    return np.linspace(d.start, d.stop, samples, endpoint=not full)


def _angle_arg(text: str) -> float:
    try:
        x = parse_angle(text if text.strip().endswith(("deg", "rad")) else float(text), "--angle")
    except (ValueError, DescriptionError) as exc:
        raise argparse.ArgumentTypeError(f"expected radians or e.g. '30deg', got {text!r}") from exc
    if abs(x) > limits.MAX_ANGLE:
        raise argparse.ArgumentTypeError(f"expected an angle within ±{limits.MAX_ANGLE:g} rad (linkgen's limits, "
                                         f"see the README), got {text!r}")
    return x


def _float_arg(text: str) -> float:
    try:
        x = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(x):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return x


def rate_arg(limit: float, unit: str):
    """An argparse type: a finite number with |x| <= ``limit`` (see linkgen.limits)."""

    def parse(text: str) -> float:
        x = _float_arg(text)
        if abs(x) > limit:
            raise argparse.ArgumentTypeError(f"expected a number within ±{limit:g} {unit} (linkgen's limits, "
                                             f"see the README), got {text!r}")
        return x

    return parse


# Most crank angles one command evaluates (--samples): the benchmark's size; the solution's
# arrays then take some 0.3 GB and the CSV about 1 GB.
MAX_SAMPLES = 10**6


def _positive_int(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if not 1 <= n <= MAX_SAMPLES:
        raise argparse.ArgumentTypeError(f"expected a whole number from 1 to {MAX_SAMPLES}, got {text!r}")
    return n


def cmd_structure(args) -> int:
    asm = assemble(load(args.model))
    s = asm.structure
    print(f"mechanism: {asm.mechanism.name}")
    print(f"mobility W = 3·n - 2·p5 = 3·{s.moving_links} - 2·{s.lower_pairs} = {s.mobility}")
    print(f"input link: I(0,1) crank {s.crank!r}, driven at {s.drive.name!r}")
    for g, m in zip(s.groups, asm.branches):
        pairs = ", ".join(f"{p.kind} {p.name}" for p in g.pairs)
        print(f"group {g.label}: pairs {pairs}; attached to {list(g.known)}; assembly mode m = {m:+d}")
    print(f"structure formula: {s.formula}")
    return 0


def _motion_json(kin: Kinematics, omega: float, epsilon: float, i: int = 0) -> dict:
    mo = kin.motion(omega, epsilon)
    return {
        "points": {n: {"position": p[i].tolist(), "velocity": v[i].tolist(), "acceleration": a[i].tolist()}
                   for n, (p, v, a) in mo.points.items()},
        "links": {n: {"angle": float(p[i]), "angular_velocity": float(v[i]), "angular_acceleration": float(a[i])}
                  for n, (p, v, a) in mo.links.items()},
        "sliders": {n: {"displacement": float(p[i]), "velocity": float(v[i]), "acceleration": float(a[i])}
                    for n, (p, v, a) in mo.sliders.items()},
    }


def drive_rates(mech, args) -> tuple[float, float]:
    """ω [rad/s] and ε [rad/s²] from --omega/--epsilon, else the description's drive."""
    return (mech.drive.omega if args.omega is None else args.omega,
            mech.drive.epsilon if args.epsilon is None else args.epsilon)


# Rows formatted at a time when writing CSV: bounds the text held in memory (~4096 rows ×
# 40 columns × 25 characters = 4 MB) whatever the number of samples.
CSV_CHUNK_ROWS = 4096


def _text(column: np.ndarray) -> list[str]:
    """A column's cells: whole numbers (booleans, integers) as such, floats at full precision."""
    if column.dtype.kind in "biu":
        return [str(int(x)) for x in column.tolist()]
    return [repr(float(x)) for x in column.tolist()]


def _write_csv(out, cols: list[str], data: list[np.ndarray]) -> int:
    writer = csv.writer(out)
    writer.writerow(cols)
    n = len(data[0]) if data else 0
    for start in range(0, n, CSV_CHUNK_ROWS):
        writer.writerows(zip(*(_text(np.asarray(d[start:start + CSV_CHUNK_ROWS])) for d in data)))
    return n


def write_rows(cols: list[str], data: list[np.ndarray], path: Path | None) -> None:
    """Columns (each (n,)) as CSV with a header, full precision, to ``path`` (written
    atomically) or stdout."""
    if path is None:
        _write_csv(sys.stdout, cols, data)
        return
    with atomic_open(path) as out:
        n = _write_csv(out, cols, data)
    print(f"wrote {n} crank angles × {len(cols)} columns to {path}", file=sys.stderr)


class OptionError(LinkgenError):
    """Command-line options that contradict each other (not about a file)."""


def _first_non_finite(obj, where: str = "") -> str | None:
    """The key path of the first NaN or infinity in a JSON-like structure, or None."""
    if isinstance(obj, float):
        return None if math.isfinite(obj) else where or "value"
    if isinstance(obj, dict):
        items = ((f"{where}.{k}" if where else str(k), v) for k, v in obj.items())
    elif isinstance(obj, (list, tuple)):
        items = ((f"{where}[{i}]", v) for i, v in enumerate(obj))
    else:
        return None
    for path, v in items:
        found = _first_non_finite(v, path)
        if found:
            return found
    return None


def check_finite(obj) -> None:
    """Raise LinkgenError naming the first NaN or infinity in a JSON-like result: such a value
    is never printed (and JSON has no such values)."""
    bad = _first_non_finite(obj)
    if bad is not None:
        raise LinkgenError(f"the result is not finite at {bad} (the computation overflowed or hit a singular "
                           "position); nothing was printed")


def print_json(obj) -> None:
    """``obj`` as strict JSON on stdout (checked by ``check_finite`` first)."""
    check_finite(obj)
    print(json.dumps(obj, indent=2, allow_nan=False))


def check_crank_options(args) -> None:
    """One crank state (--angle, --json) and samples (--samples, --csv) exclude each other."""
    sampled = [o for o, v in (("--samples", args.samples), ("--csv", args.csv)) if v is not None]
    single = [o for o, v in (("--angle", args.angle), ("--json", args.json or None)) if v is not None]
    if sampled and single:
        raise OptionError(f"{single[0]} cannot be combined with {sampled[0]}: {single[0]} is for one crank "
                          f"angle, {sampled[0]} for samples over the drive range")
    if args.keep_singular and not sampled:
        raise OptionError("--keep-singular is for samples (--samples, --csv); at one crank angle a singular "
                          "position is an error")


def cmd_analyze(args) -> int:
    check_crank_options(args)
    mech = load(args.model)
    omega, epsilon = drive_rates(mech, args)
    if args.samples is not None or args.csv is not None:
        phi = crank_grid(mech, args.samples or 360)
        kin = solve(mech, phi, on_singular="mark")
        mo = kin.motion(omega, epsilon)
        cols, data = ["phi", "singular"], [phi, kin.singular]
        for kind, table in (("point", mo.points), ("link", mo.links), ("slider", mo.sliders)):
            names = ("position", "velocity", "acceleration") if kind == "point" else (
                ("angle", "angular_velocity", "angular_acceleration") if kind == "link"
                else ("displacement", "velocity", "acceleration"))
            for n, arrays in table.items():
                for qname, arr in zip(names, arrays):
                    if arr.ndim == 2:
                        cols += [f"{n}.{qname}.x", f"{n}.{qname}.y"]
                        data += [arr[:, 0], arr[:, 1]]
                    else:
                        cols.append(f"{n}.{qname}")
                        data.append(arr)
        write_rows(cols, data, args.csv)
        return report_singular(args.model, kin, args.keep_singular)
    phi = mech.drive.start if args.angle is None else args.angle
    kin = solve(mech, np.array([phi]))
    result = _motion_json(kin, omega, epsilon)
    check_finite(result)
    if args.json:
        print_json(result)
        return 0
    print(f"{mech.name}: φ = {math.degrees(phi):.6g}° ({phi:.9g} rad), ω = {omega:g} rad/s, ε = {epsilon:g} rad/s²")
    print(f"{'point':<10}{'x [m]':>14}{'y [m]':>14}{'vx [m/s]':>14}{'vy [m/s]':>14}{'ax [m/s²]':>14}{'ay [m/s²]':>14}")
    for n, q in result["points"].items():
        print(f"{n:<10}" + "".join(f"{x:>14.6g}" for x in q["position"] + q["velocity"] + q["acceleration"]))
    print(f"{'link':<10}{'angle [rad]':>14}{'ω [rad/s]':>14}{'ε [rad/s²]':>14}")
    for n, q in result["links"].items():
        print(f"{n:<10}{q['angle']:>14.6g}{q['angular_velocity']:>14.6g}{q['angular_acceleration']:>14.6g}")
    if result["sliders"]:
        print(f"{'slider':<10}{'s [m]':>14}{'v [m/s]':>14}{'a [m/s²]':>14}")
        for n, q in result["sliders"].items():
            print(f"{n:<10}{q['displacement']:>14.6g}{q['velocity']:>14.6g}{q['acceleration']:>14.6g}")
    return 0


def add_crank_arguments(parser: argparse.ArgumentParser, example_angle: str) -> None:
    """MODEL, one crank state (--angle, --omega, --epsilon, --json) or samples (--samples, --csv)."""
    parser.add_argument("model", type=Path)
    parser.add_argument("--angle", type=_angle_arg, help=f"crank angle: radians, or e.g. {example_angle}")
    parser.add_argument("--omega", type=rate_arg(limits.MAX_OMEGA, "rad/s"),
                        help="crank speed [rad/s] (default: the description's)")
    parser.add_argument("--epsilon", type=rate_arg(limits.MAX_EPSILON, "rad/s²"),
                        help="crank acceleration [rad/s²] (default: the description's)")
    parser.add_argument("--json", action="store_true", help="print one JSON object (not with --samples/--csv)")
    parser.add_argument("--samples", type=_positive_int, help="evaluate this many angles over the drive range")
    parser.add_argument("--csv", type=Path, help="write the samples as CSV to this file (not with --angle/--json)")
    parser.add_argument("--keep-singular", action="store_true",
                        help="with samples: exit 0 even if some are singular (by default such samples are "
                             f"written marked, singular = 1, and the exit status is {SINGULAR_STATUS}); at one "
                             "crank angle a singular position is always an error (status 2)")


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors (the usage is one ``--help`` away); subcommands inherit it."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def build_parser() -> argparse.ArgumentParser:
    p = _Parser(prog="linkgen", description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="command", required=True)

    s = sub.add_parser("structure", help="mobility, Assur groups and the structure formula")
    s.add_argument("model", type=Path)
    s.set_defaults(func=cmd_structure)

    a = sub.add_parser("analyze", help="closed-form positions, velocities and accelerations")
    add_crank_arguments(a, "38.117deg")
    a.set_defaults(func=cmd_analyze)

    from . import cli_forces, cli_mujoco

    cli_forces.add_command(sub)
    cli_mujoco.add_commands(sub)
    return p


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        status = args.func(args)
        sys.stdout.flush()  # a closed pipe shows here, not in the interpreter's exit
        return status
    except BrokenPipeError:
        _silence_stdout()
        return 141
    except OptionError as exc:
        print(f"linkgen {args.command}: error: {exc}", file=sys.stderr)
        return 2
    except (LinkgenError, OSError) as exc:
        model = getattr(args, "model", None)
        text = message_for(model, exc) if model is not None else str(exc)
        print(f"linkgen: error: {text}", file=sys.stderr)
        return 2


def _silence_stdout() -> None:
    """Point stdout at /dev/null so that the interpreter's final flush of what is left in
    its buffer does not report the closed pipe again."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError, AttributeError):  # stdout without a file descriptor (captured)
        pass


if __name__ == "__main__":
    sys.exit(main())
