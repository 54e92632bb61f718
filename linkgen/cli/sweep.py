"""``linkgen sweep``: a design study over numeric fields of a planar linkage's description
(``linkgen.studies``): a grid or a Latin hypercube of variants, each variant's design metrics
(or its failure and why), on every local core or a Dask cluster, resumable; the table as Parquet
and CSV with its provenance, maps of the metrics, a sample validated in MuJoCo."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from linkgen.cli.common import OptionError, whole_in

_count = whole_in(1)  # a count of variants, angles, workers or chunks
_seed = whole_in(0)


def _out_dir(path: Path) -> Path:
    from linkgen.outputs import output_folder

    if path.suffix and not path.is_dir():
        raise OptionError(f"-o/--out {path}: `linkgen sweep` writes a folder (sweep.parquet, sweep.csv, sweep.json, "
                          f"the plots and chunks/); give a name without an extension")
    return output_folder(path)


def cmd_sweep(args) -> int:
    from linkgen.studies.engine import run_study
    from linkgen.studies.sweep import make_study, write_outputs

    if args.seed is not None and args.lhs is None:
        raise OptionError("--seed: seeds the Latin hypercube; give --lhs N with it")
    if args.scheduler is not None and args.workers is not None:
        raise OptionError("--workers: the local processes; with --scheduler the cluster's workers run the sweep")
    study = make_study(args.model, args.vary, lhs=args.lhs, seed=args.seed or 0, angles=args.angles)
    out = _out_dir(args.out)
    table = run_study(study, out, workers=args.workers, scheduler=args.scheduler, chunk=args.chunk)
    paths = write_outputs(table, study, out)
    ok = table.column("status").to_pylist().count("ok")
    print(f"wrote {table.num_rows} variants ({ok} ok, {table.num_rows - ok} failed) × {table.num_columns} columns to "
          f"{paths['parquet']} and {paths['csv']}", file=sys.stderr)
    from linkgen.studies.plots import plot_study

    for path in plot_study(table, study, out):
        print(f"wrote {path}", file=sys.stderr)
    if args.validate:
        from linkgen.studies.validate import validate_sample

        report = validate_sample(study, table, args.validate, out)
        print(report.text())
        if not report.ok:
            return 1
    return 0


def add_vary(p: argparse.ArgumentParser) -> None:
    p.add_argument("--vary", action="append", required=True, metavar="FIELD=START:STOP[:N]",
                   help="a numeric field of the description by its path (links.coupler.length, points.C.x, "
                        "drive.omega, links.crank.density, mechanism.gravity.y) and its range in SI or with a unit "
                        "(80rpm:120rpm); N values on a grid, or START:STOP with --lhs; repeat for more fields")


def add_command(sub) -> None:
    p = sub.add_parser("sweep", help="design study: each variant's metrics over a grid or Latin hypercube of "
                                     "numeric fields (Parquet and CSV, plots, on every core or a Dask cluster)")
    p.add_argument("model", type=Path, help="description file (.toml) of a planar linkage")
    add_vary(p)
    p.add_argument("--lhs", type=_count, metavar="N", help="N variants of a Latin hypercube over the fields' ranges "
                                                           "instead of a grid")
    p.add_argument("--seed", type=_seed, help="the Latin hypercube's seed (default 0)")
    p.add_argument("--angles", type=_count, default=360, help="crank angles per variant over the drive's range "
                                                              "(default 360)")
    p.add_argument("-o", "--out", type=Path, required=True, help="folder for sweep.parquet, sweep.csv, sweep.json, "
                                                                 "the plots and the chunks (a rerun resumes)")
    p.add_argument("--workers", type=_count, help="local processes (default: one per core; 1 runs in this process)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="run on a Dask distributed cluster, e.g. tcp://host:8786")
    p.add_argument("--chunk", type=_count, help="variants per chunk (default: sized to last about 0.5 s)")
    p.add_argument("--validate", type=_count, metavar="K", help="run K variants (the extremes and a random sample) "
                                                                "through the MuJoCo cross-check")
    p.set_defaults(func=cmd_sweep)


__all__ = ["add_command", "add_vary", "cmd_sweep"]
