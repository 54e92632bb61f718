"""``linkgen referee`` (a solver's results against the closed form and, asked, MuJoCo: a verdict
and a diagnosis per column; a whole suite's answers with --suite) and ``linkgen suite export``
(the reference suite for solver authors). docs/referee.md."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from linkgen.cli.common import (FOLDER, OptionError, _positive_int, add_out_argument, allowed_text, check_finite,
                                output_kind, rate_arg)
from linkgen.model import limits

# What -o/--out writes, by kind.
REFEREE = {FOLDER: "the report: README.md, a PNG per column and verdict.json", ".json": "the verdict's JSON object"}


def _tolerance(text: str) -> float:
    import argparse
    import math

    try:
        x = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not (math.isfinite(x) and 0 < x < 1):
        raise argparse.ArgumentTypeError(f"expected a fraction of the column's scale between 0 and 1, e.g. 1e-6, "
                                         f"got {text!r}")
    return x


def cmd_referee(args) -> int:
    if args.suite is not None:
        return _suite(args)
    if len(args.inputs) != 2:
        raise OptionError(f"expected the description and your results (linkgen referee M.toml RESULTS.csv), got "
                          f"{len(args.inputs)} file(s); with --suite DIR: the answers folder only")
    from linkgen.pipeline.registry import load
    from linkgen.referee.compare import DEFAULT_TOLERANCE, referee
    from linkgen.referee.table import read_map

    kind = output_kind(args, args.out, REFEREE) if args.out is not None else None
    if args.json and kind == ".json":
        raise OptionError(f"--json prints what -o {args.out} writes: give one of them")
    if kind == FOLDER:
        from linkgen.outputs import output_folder

        output_folder(args.out)
    elif kind is not None:
        from linkgen.outputs import check_output

        check_output(args.out)
    desc = load(args.inputs[0])
    mapping = read_map(args.map) if args.map is not None else None
    v = referee(desc, args.inputs[1], mapping=mapping, omega=args.omega, epsilon=args.epsilon,
                tolerance=DEFAULT_TOLERANCE if args.tolerance is None else args.tolerance, mujoco=args.mujoco,
                progress=lambda line: print(f"referee: {line}", file=sys.stderr, flush=True))
    d = v.to_dict()
    check_finite(d)
    if args.json:
        print(json.dumps(d, indent=2, allow_nan=False))
    else:
        print(v.text())
    if kind == ".json":
        from linkgen.outputs import atomic_write_text

        atomic_write_text(args.out, json.dumps(d, indent=2, allow_nan=False) + "\n")
        print(f"wrote {args.out}", file=sys.stderr)
    elif kind == FOLDER:
        from linkgen.referee.report import write_report

        print(f"report: {write_report(v, args.out)}", file=sys.stderr)
    return 0 if v.ok else 1


def _suite(args) -> int:
    from linkgen.referee.suite import referee_suite, suite_text

    if len(args.inputs) != 1:
        raise OptionError(f"--suite {args.suite}: give the answers folder only (linkgen referee --suite DIR ANSWERS), "
                          f"got {len(args.inputs)} paths")
    if args.out is not None or args.map is not None or args.omega is not None or args.epsilon is not None:
        raise OptionError("--suite takes the suite's mechanisms, drives and headers as they are: -o, --map, --omega "
                          "and --epsilon are for one table")
    results = referee_suite(args.suite, args.inputs[0], tolerance=args.tolerance, mujoco=args.mujoco)
    if args.json:
        out = [{"folder": r["folder"], "family": r["family"], "missing": r["missing"],
                "verdicts": [v.to_dict() for v in r["verdicts"]]} for r in results]
        check_finite(out)
        print(json.dumps(out, indent=2, allow_nan=False))
    else:
        print(suite_text(results))
    return 0 if all(v.ok for r in results for v in r["verdicts"]) else 1


def cmd_suite_export(args) -> int:
    from linkgen.referee.suite import export

    def progress(text: str) -> None:
        print(f"suite: {text}", file=sys.stderr, flush=True)

    path = export(args.folder, count=args.count, seed=args.seed, mujoco=not args.no_mujoco, progress=progress)
    print(f"wrote {path}", file=sys.stderr)
    return 0


def add_commands(sub) -> None:
    r = sub.add_parser("referee", help="your solver's results against the closed form (and MuJoCo): a verdict and "
                       "a diagnosis per column (docs/referee.md)")
    r.add_argument("inputs", nargs="+", type=Path, metavar="FILE",
                   help="the description (.toml) and your results (.csv, headed as analyze and forces write: phi "
                        "[deg], B.position.x [mm], ...); with --suite: the answers folder")
    r.add_argument("--suite", type=Path, metavar="DIR",
                   help="a reference suite (linkgen suite export): referee every answer in the answers folder")
    r.add_argument("--map", type=Path, metavar="FILE",
                   help="a TOML file whose [columns] table names your headers as linkgen's, with units "
                        "(\"theta4 (deg)\" = \"rocker.angle [deg]\"; \"\" leaves a column out)")
    r.add_argument("--omega", type=rate_arg(limits.MAX_OMEGA, "rad/s"),
                   help="crank speed of your results [rad/s], or with a unit, e.g. 100rpm (default: the description's)")
    r.add_argument("--epsilon", type=rate_arg(limits.MAX_EPSILON, "rad/s²"),
                   help="crank acceleration of your results [rad/s²], or with a unit (default: the description's)")
    r.add_argument("--tolerance", type=_tolerance, default=None,
                   help="agreement, as a fraction of each column's scale (no unit; default 1e-6, or the suite's)")
    r.add_argument("--mujoco", action="store_true",
                   help="compare with MuJoCo's forward run and inverse dynamics too (planar linkages; seconds)")
    r.add_argument("--json", action="store_true", help="print the verdict as JSON")
    add_out_argument(r, f"write {allowed_text(REFEREE)}", metavar="DIR")
    r.set_defaults(func=cmd_referee)

    s = sub.add_parser("suite", help="a reference suite for solver authors: mechanisms of every family with their "
                       "descriptions, MJCF, closed-form tables and MuJoCo's agreement (docs/referee.md)")
    actions = s.add_subparsers(dest="action", required=True, help="export: write a suite into a folder")
    e = actions.add_parser("export", help="write a suite into a folder")
    e.add_argument("folder", type=Path, help="the folder to write (created)")
    e.add_argument("--count", type=_positive_int, default=6, help="mechanisms in the suite (no unit; default 6)")
    e.add_argument("--seed", type=int, default=0, help="the seed the planar linkages are drawn from (default 0)")
    e.add_argument("--no-mujoco", action="store_true", help="leave out MuJoCo's agreement figures (no MuJoCo runs)")
    e.set_defaults(func=cmd_suite_export)
