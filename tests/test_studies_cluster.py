"""Design studies at scale: a real Dask ``LocalCluster`` (scheduler and two worker processes on
this machine) gives the local run's table bit for bit; a sweep killed with SIGKILL resumes from
the chunks it wrote and ends with the same table."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

from linkgen.studies.engine import run_study
from linkgen.studies.sweep import make_study, write_outputs

ROOT = Path(__file__).resolve().parent.parent
FOURBAR = str(ROOT / "models/fourbar.toml")


def test_dask_cluster_gives_the_local_table(tmp_path):
    from distributed import LocalCluster

    study = make_study(FOURBAR, ["links.coupler.length=0.5:1.5:12", "points.C.x=0.6:1.4:6",
                                 "links.rocker.density=-2:10:3"])
    local = run_study(study, tmp_path / "local", workers=1, progress=False)
    local_bytes = write_outputs(local, study, tmp_path / "local")["parquet"].read_bytes()
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0") as cluster:
        remote = run_study(study, tmp_path / "dask", scheduler=cluster.scheduler_address, chunk=25, progress=False)
    assert write_outputs(remote, study, tmp_path / "dask")["parquet"].read_bytes() == local_bytes


def test_killed_sweep_resumes(tmp_path):
    """SIGKILL once two chunks are written; the rerun says it resumes, computes the rest and
    writes the table an uninterrupted run writes."""
    out = tmp_path / "killed"
    vary = ["drive.omega=1:30:24", "links.rod.length=0.03:0.2:15"]  # a slider-crank: the general route, ~2 ms a row
    cmd = [sys.executable, "-m", "linkgen", "sweep", str(ROOT / "models/slider_crank_offset.toml"),
           *[a for v in vary for a in ("--vary", v)], "--workers", "1", "--chunk", "12", "-o", str(out)]
    env = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    deadline = time.monotonic() + 60
    while len(list((out / "chunks").glob("*.parquet"))) < 2 and time.monotonic() < deadline:
        assert proc.poll() is None, "the sweep ended before it could be killed"
        time.sleep(0.005)
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    written = len(list((out / "chunks").glob("*.parquet")))
    assert 2 <= written < 30 and not (out / "sweep.parquet").exists()
    again = subprocess.run(cmd, env=env, capture_output=True, text=True, timeout=120)
    assert again.returncode == 0, again.stderr
    assert f"resuming, {written} chunks already written" in again.stderr
    study = make_study(str(ROOT / "models/slider_crank_offset.toml"), vary)
    whole = write_outputs(run_study(study, tmp_path / "whole", workers=1, progress=False), study, tmp_path / "whole")
    assert (out / "sweep.parquet").read_bytes() == whole["parquet"].read_bytes()
