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
    p.add_argument("--repeat", type=int, default=2, help="local and Dask runs, alternated (the machine is shared: "
                                                          "their medians are compared)")
    args = p.parse_args()
    from distributed import LocalCluster

    from linkgen.studies.engine import run_study
    from linkgen.studies.sweep import make_study, write_outputs

    study = make_study(MODEL, VARY, lhs=args.variants, seed=1)
    print(f"{args.variants} four-bar variants × {study.angles} crank angles, {os.cpu_count()} cores, "
          f"load average {os.getloadavg()[0]:.2f}", flush=True)
    local_t, dask_t, same = [], [], True
    with tempfile.TemporaryDirectory() as tmp:
        reference = None
        for k in range(args.repeat):
            # The local run as the command runs it: no cluster in the process (its threads would make
            # the local workers spawned rather than forked, and its scheduler shares the process).
            t0, cpu0 = time.perf_counter(), _cpu()
            local = run_study(study, Path(tmp) / f"local{k}", progress=False)
            local_t.append(time.perf_counter() - t0)
            cpu = _cpu() - cpu0
            got = write_outputs(local, study, Path(tmp) / f"local{k}")["parquet"].read_bytes()
            reference = reference or got
            ok = local.column("status").to_pylist().count("ok")
            print(f"local sweep (every core): {local_t[-1]:.2f} s wall, {cpu:.2f} s CPU in this process and its "
                  f"workers ({ok} ok, {local.num_rows - ok} failed); load average {os.getloadavg()[0]:.2f}",
                  flush=True)
            with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
                t0 = time.perf_counter()
                remote = run_study(study, Path(tmp) / f"dask{k}", scheduler=cluster.scheduler_address,
                                   progress=False)
                dask_t.append(time.perf_counter() - t0)
            same &= write_outputs(remote, study, Path(tmp) / f"dask{k}")["parquet"].read_bytes() == reference
            print(f"Dask LocalCluster (2 worker processes, started before the clock): {dask_t[-1]:.2f} s; load "
                  f"average {os.getloadavg()[0]:.2f}", flush=True)
    t_local = float(np.median(local_t))
    print(f"median local {t_local:.2f} s, median Dask {np.median(dask_t):.2f} s: Dask/local "
          f"{np.median(dask_t) / t_local:.2f}×; tables {'identical' if same else 'DIFFERENT'}", flush=True)
    rows = np.random.default_rng(0).choice(args.variants, args.loop_sample, replace=False)
    c0 = time.process_time()
    t_loop = loop_seconds(study, rows) / args.loop_sample * args.variants
    cpu_loop = (time.process_time() - c0) / args.loop_sample * args.variants
    print(f"per-variant loop over linkgen.forces + linkgen.summary: {t_loop / args.variants * 1e3:.1f} ms a "
          f"variant ({args.loop_sample} timed), {t_loop:.0f} s for {args.variants}: {t_loop / t_local:.0f}× the "
          f"sweep's wall time (CPU: {cpu_loop:.0f} s against {cpu:.1f} s, {cpu_loop / cpu:.0f}×); load average "
          f"{os.getloadavg()[0]:.2f}", flush=True)


if __name__ == "__main__":
    main()
