"""``linkgen optimize``: the best design over numeric fields of a planar linkage's description
under constraints (``linkgen.studies.optimize``: differential evolution, seeded), written as a
description file keeping the user's comments and layout, and validated in MuJoCo."""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

from linkgen.cli.common import OptionError


def cmd_optimize(args) -> int:
    from linkgen.outputs import check_output
    from linkgen.studies.fourbar_params import fourbar_of
    from linkgen.studies.general import layout_of
    from linkgen.studies.optimize import metric_column, optimize, parse_constraint, write_design
    from linkgen.studies.sweep import make_study

    if args.out.suffix.lower() != ".toml":
        raise OptionError(f"-o/--out {args.out}: `linkgen optimize` writes the best design as a description "
                          f"(.toml); got {args.out.suffix or 'no extension'}")
    study = make_study(args.model, args.vary, lhs=1, seed=0, angles=args.angles)
    from linkgen.pipeline.registry import from_dict
    from linkgen.model.toml_file import parse_toml

    mech = from_dict(parse_toml(study.text, study.source), study.source)
    fb = fourbar_of(mech)
    columns = (fb.layout if fb is not None else layout_of(mech)).columns
    objective = metric_column(args.minimize, columns)
    constraints = tuple(parse_constraint(c, columns) for c in args.subject_to or ())
    check_output(args.out)  # a bad output refused before the search, not after
    start = time.perf_counter()
    last = [0.0]

    def progress(evaluations: int, best: float) -> None:
        now = time.perf_counter() - start
        if now - last[0] >= 1.0:
            last[0] = now
            print(f"optimize: {evaluations} variants, best {objective} {best:.6g}, {now:.1f} s", file=sys.stderr)

    best = optimize(study, objective, constraints, seed=args.seed, progress=progress)
    print(f"optimize: {best.evaluations} variants in {time.perf_counter() - start:.1f} s ({best.message})",
          file=sys.stderr)
    for f, v in zip(study.fields, best.values):
        print(f"{f.path} = {v:.9g} {f.unit}")
    unit = objective.rsplit(" [", 1)[1][:-1]
    print(f"{objective.split(' [')[0]} = {best.metrics[objective]:.6g} {unit}")
    for c in constraints:
        v = best.metrics[c.metric]
        shown = f"{math.degrees(v):.6g}°" if c.metric.endswith("[rad]") else f"{v:.6g}"
        print(f"subject to {c.text()}: {shown}")
    if not best.feasible:
        print(f"linkgen: error: no variant tried meets {' and '.join(c.text() for c in constraints)}; nothing written",
              file=sys.stderr)
        return 1
    write_design(study, best.values, args.out)
    print(f"wrote the best design to {args.out}", file=sys.stderr)
    if args.no_validate:
        return 0
    from linkgen.pipeline.registry import load, stage

    best_mech = load(args.out)
    result = stage(best_mech, "validate")(best_mech, practical=False)
    print(result.summary())
    return 0 if result.ok else 1


def add_command(sub) -> None:
    from linkgen.cli.sweep import _count, _seed, add_vary

    p = sub.add_parser("optimize", help="the best design over numeric fields under constraints (differential "
                                        "evolution), written as a description and validated in MuJoCo")
    p.add_argument("model", type=Path, help="description file (.toml) of a planar linkage")
    add_vary(p)
    p.add_argument("--minimize", required=True, metavar="METRIC", help="the metric to minimise, e.g. "
                                                                       "peak_balancing_torque")
    p.add_argument("--subject-to", action="append", metavar="CONSTRAINT",
                   help="METRIC >= VALUE or METRIC <= VALUE, with a unit where it has one: "
                        "\"min_transmission_angle >= 40deg\"; repeat for more")
    p.add_argument("--seed", type=_seed, default=0, help="the search's seed (default 0): the same seed, the same "
                                                         "design")
    p.add_argument("--angles", type=_count, default=360, help="crank angles per variant (default 360)")
    p.add_argument("-o", "--out", type=Path, required=True, help="the best design's description (.toml)")
    p.add_argument("--no-validate", action="store_true", help="skip the MuJoCo validation of the best design")
    p.set_defaults(func=cmd_optimize)


__all__ = ["add_command", "cmd_optimize"]
