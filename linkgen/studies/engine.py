"""Running a study: its variants cut into chunks, the chunks run on local processes (every core
by default) or on a Dask cluster (``scheduler``: a ``dask.distributed`` scheduler's address),
each chunk written to ``OUT/chunks/`` as it finishes, then the table assembled from them.

Chunks last at least ``MIN_CHUNK_SECONDS`` (their size from a timed probe of the study's
first rows), so that a cluster's per-task cost (~1 ms a task for dask.distributed) stays below
1 %. An interrupted study resumes: ``OUT/chunks/study.json`` records the study (the
description's hash, the fields, the variants' hash, the chunk size) and a rerun of the same
study computes only the chunks not yet written."""

from __future__ import annotations

import hashlib
import json
import math
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from linkgen.errors import ArgumentError
from linkgen.studies.chunk import Task, run
from linkgen.studies.fields import Field

# A chunk's least duration [s]: dask.distributed's overhead is ~1 ms per task (its docs' "best
# practices": tasks of 100 ms or more keep it below 1 %).
MIN_CHUNK_SECONDS = 0.1
# What the chunks aim at [s]: long enough for the scheduler, short enough that a killed study
# loses little and every worker gets several chunks.
TARGET_CHUNK_SECONDS = 0.5
# Rows the probe times to size the chunks.
PROBE_ROWS = 256
# Progress lines at most this often [s].
PROGRESS_EVERY = 1.0


@dataclass(frozen=True)
class Study:
    """A study: the description (its path and TOML text), the varied fields, the variants'
    values (V, n_fields) [SI], the sampling (``{"method": "grid"}`` or ``{"method": "lhs",
    "n": N, "seed": S}``) and the crank angles per variant."""

    source: str
    text: str
    fields: tuple[Field, ...]
    values: np.ndarray
    sampling: dict
    angles: int

    @property
    def digest(self) -> str:
        """SHA-256 of the description's text."""
        return hashlib.sha256(self.text.encode("utf-8")).hexdigest()

    @property
    def key(self) -> str:
        """What identifies the study's rows: the description, the fields, the values, the angles."""
        h = hashlib.sha256(self.digest.encode())
        h.update(json.dumps([f.path for f in self.fields]).encode())
        h.update(np.ascontiguousarray(self.values, dtype="<f8").tobytes())
        h.update(str(self.angles).encode())
        return h.hexdigest()

    def task(self, first: int, stop: int) -> Task:
        return Task(self.source, self.text, tuple(f.path for f in self.fields), first, self.values[first:stop],
                    self.angles)


def _say(text: str) -> None:
    print(text, file=sys.stderr, flush=True)


def chunk_size(study: Study) -> int:
    """Rows per chunk: as many as the probe says last TARGET_CHUNK_SECONDS (at least
    MIN_CHUNK_SECONDS' worth)."""
    n = min(PROBE_ROWS, study.values.shape[0])
    t0 = time.perf_counter()
    run(study.task(0, n))
    per_row = max((time.perf_counter() - t0) / n, 1e-9)
    return max(1, math.ceil(TARGET_CHUNK_SECONDS / per_row))


def _plan(study: Study, out: Path, chunk: int | None) -> tuple[Path, int]:
    """The chunk directory and the chunk size: the recorded ones when resuming the same study."""
    chunks = out / "chunks"
    record = chunks / "study.json"
    if record.exists():
        got = json.loads(record.read_text(encoding="utf-8"))
        if got.get("key") != study.key:
            raise ArgumentError(f"{out}: holds the chunks of another study (another description, fields, variants or "
                                f"crank angles); give another -o directory or remove {chunks}")
        if chunk is not None and chunk != got["chunk"]:
            raise ArgumentError(f"--chunk {chunk}: the interrupted study in {out} was cut into chunks of "
                                f"{got['chunk']} rows; resume it with the same --chunk or none")
        return chunks, int(got["chunk"])
    size = chunk if chunk is not None else chunk_size(study)
    chunks.mkdir(parents=True, exist_ok=True)
    tmp = record.with_name("study.json.part")
    tmp.write_text(json.dumps({"key": study.key, "chunk": size, "rows": int(study.values.shape[0])}),
                   encoding="utf-8")
    os.replace(tmp, record)
    return chunks, size


def _executor(workers: int | None, scheduler: str | None):
    """(submit(task) → future, as_completed, close) for the local processes or the cluster."""
    if scheduler is not None:
        try:
            from distributed import Client, as_completed
        except ImportError:
            raise ArgumentError("--scheduler: running on a Dask cluster needs dask.distributed "
                                "(pip install 'linkgen[cluster]')") from None

        client = Client(scheduler, timeout="20s")
        return (lambda task: client.submit(run, task, pure=False)), as_completed, client.close
    import concurrent.futures as cf
    import multiprocessing
    import threading

    # Forked workers start at once with linkgen already imported; a process running threads
    # (a Dask client, a GUI) is not forked safely, and its workers are spawned instead.
    method = "fork" if threading.active_count() == 1 and "fork" in multiprocessing.get_all_start_methods() \
        else "spawn"
    pool = cf.ProcessPoolExecutor(max_workers=workers, mp_context=multiprocessing.get_context(method))
    return (lambda task: pool.submit(run, task)), cf.as_completed, pool.shutdown


def run_study(study: Study, out: Path, *, workers: int | None = None, scheduler: str | None = None,
              chunk: int | None = None, progress: bool = True):
    """Run (or resume) ``study`` into ``out``: its chunks, then the table (``table``); returns
    the pyarrow Table. ``workers``: local processes (None: every core; 1: in this process)."""
    from linkgen.studies.table import read_parquet, to_arrow, write_parquet

    rows = study.values.shape[0]
    chunks, size = _plan(study, out, chunk)
    spans = [(i, min(i + size, rows)) for i in range(0, rows, size)]
    path_of = {s: chunks / f"{s[0]:09d}.parquet" for s in spans}
    todo = [s for s in spans if not path_of[s].exists()]
    columns = [f.column for f in study.fields]
    start, last = time.perf_counter(), 0.0
    done = len(spans) - len(todo)
    if progress:
        _say(f"sweep: {rows} variants in {len(spans)} chunks of {size}"
             + (f"; resuming, {done} chunks already written" if done else ""))

    def finished(span, result) -> None:
        nonlocal done, last
        write_parquet(to_arrow(result, columns), path_of[span])
        done += 1
        now = time.perf_counter() - start
        if progress and (now - last >= PROGRESS_EVERY or done == len(spans)):
            last = now
            _say(f"sweep: {done}/{len(spans)} chunks, {now:.1f} s")

    if todo and (workers == 1 and scheduler is None):
        for span in todo:
            finished(span, run(study.task(*span)))
    elif todo:
        submit, as_completed, close = _executor(workers or os.cpu_count(), scheduler)
        try:
            futures = {submit(study.task(*span)): span for span in todo}
            for fut in as_completed(list(futures)):
                finished(futures[fut], fut.result())
        finally:
            close()
    import pyarrow as pa

    return pa.concat_tables([read_parquet(path_of[s]) for s in spans])


__all__ = ["MIN_CHUNK_SECONDS", "Study", "TARGET_CHUNK_SECONDS", "chunk_size", "run_study"]
