"""The sweep's benchmark: closed-form metrics of 10^5 four-bar variants × 360 crank angles.

Measures, in one run on this machine:

* the local sweep (``linkgen.studies.engine.run_study`` on every core: process start-up,
  chunking, the kernel, the chunk files and the table) — wall time;
* a per-variant loop over today's ``linkgen.forces`` + ``linkgen.summary`` (each variant loaded,
  its forces at the 360 angles and its design summary), timed on a random subsample and scaled
  to the whole study; the ratio of the two;
* the same sweep on a Dask ``LocalCluster`` of 2 worker processes (started before the clock),
  its time's ratio to the local run, and whether the two tables are the same bytes.

    .venv/bin/python validation/bench_sweep.py [VARIANTS] [--loop-sample N]
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

MODEL = str(ROOT / "models/fourbar.toml")
VARY = ["links.coupler.length=0.8:1.3", "points.C.x=0.8:1.3", "links.rocker.length=0.5:0.9", "drive.omega=5:15"]


def loop_seconds(study, rows: np.ndarray) -> float:
    """Wall time of the per-variant loop over ``linkgen.forces`` + ``linkgen.summary`` on ``rows``."""
    import linkgen
    from linkgen.errors import LinkgenError
    from linkgen.model.toml_file import parse_toml
    from linkgen.pipeline.registry import from_dict
    from linkgen.studies.design import variant_data
    from linkgen.studies.metrics import angles

    data = parse_toml(study.text, study.source)
    paths = [f.path for f in study.fields]
    t0 = time.perf_counter()
    for r in rows:
        given = dict(zip(paths, study.values[r].tolist()))
        try:
            mech = from_dict(variant_data(data, study.source, given), study.source)
            phi, _ = angles(mech.drive.start, mech.drive.stop)
            linkgen.forces(mech, phi)
            linkgen.summary(mech)
        except LinkgenError:
            pass  # a variant that does not assemble costs its attempt, as in a sweep
    return time.perf_counter() - t0


def _cpu() -> float:
    """CPU seconds of this process and its finished children (the local sweep's workers): what the
    sweep costs whatever else the machine runs."""
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def main() -> None:
    p = argparse.ArgumentParser()
    p.add_argument("variants", type=int, nargs="?", default=100_000)
    p.add_argument("--loop-sample", type=int, default=40)
    args = p.parse_args()
    from distributed import LocalCluster

    from linkgen.studies.engine import run_study
    from linkgen.studies.sweep import make_study, write_outputs

    study = make_study(MODEL, VARY, lhs=args.variants, seed=1)
    print(f"{args.variants} four-bar variants × {study.angles} crank angles, {os.cpu_count()} cores, "
          f"load average {os.getloadavg()[0]:.2f}", flush=True)
    with tempfile.TemporaryDirectory() as tmp:
        t0, cpu0 = time.perf_counter(), _cpu()
        local = run_study(study, Path(tmp) / "local", progress=False)
        t_local, cpu = time.perf_counter() - t0, _cpu() - cpu0
        local_bytes = write_outputs(local, study, Path(tmp) / "local")["parquet"].read_bytes()
        ok = local.column("status").to_pylist().count("ok")
        print(f"local sweep (every core): {t_local:.2f} s wall, {cpu:.2f} s CPU in this process and its workers "
              f"({ok} ok, {local.num_rows - ok} failed)", flush=True)

        rows = np.random.default_rng(0).choice(args.variants, args.loop_sample, replace=False)
        c0 = time.process_time()
        t_loop = loop_seconds(study, rows) / args.loop_sample * args.variants
        cpu_loop = (time.process_time() - c0) / args.loop_sample * args.variants
        print(f"per-variant loop over linkgen.forces + linkgen.summary: {t_loop / args.variants * 1e3:.1f} ms a "
              f"variant ({args.loop_sample} timed), {t_loop:.0f} s for {args.variants}; sweep is "
              f"{t_loop / t_local:.0f}× faster (CPU: {cpu_loop:.0f} s against {cpu:.1f} s, {cpu_loop / cpu:.0f}×)",
              flush=True)

        with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
            t0 = time.perf_counter()
            remote = run_study(study, Path(tmp) / "dask", scheduler=cluster.scheduler_address, progress=False)
            t_dask = time.perf_counter() - t0
        same = write_outputs(remote, study, Path(tmp) / "dask")["parquet"].read_bytes() == local_bytes
        print(f"Dask LocalCluster (2 worker processes): {t_dask:.2f} s, {t_dask / t_local:.2f}× the local run; "
              f"tables {'identical' if same else 'DIFFERENT'}", flush=True)
        print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
