"""A study's table: one row per variant — its index, the varied fields' values, ``status``
("ok" or "failed"), for a failed row ``error`` (the error's class: AssemblyError,
SingularityError, DescriptionError, …) and ``reason`` (its message), then the metrics
(``metrics.Layout.columns``; empty where a metric does not apply or the row failed, never NaN).
Column names carry their unit as linkgen's CSVs do (``links.coupler.length [m]``).

Written as Parquet (the provenance in the file's metadata under ``linkgen``) and CSV, with a
JSON sidecar holding the same provenance: linkgen's, numpy's and MuJoCo's versions, the
description's SHA-256, the varied fields, the sampling and its seed. Nothing in the table
depends on how the study ran (executor, workers, chunks, time): the same study gives the same
bytes."""

from __future__ import annotations

import json
import os
from pathlib import Path

import numpy as np

PROVENANCE_KEY = b"linkgen"


def to_arrow(result: dict, columns: list[str]):
    """The pyarrow Table of one chunk's result (``chunk.run``); ``columns`` the varied fields'."""
    import pyarrow as pa

    data = {"variant": pa.array(result["variant"], pa.int64())}
    for i, name in enumerate(columns):
        data[name] = pa.array(result["values"][:, i], pa.float64())
    data["status"] = pa.array(result["status"], pa.string())
    data["error"] = pa.array(result["error"], pa.string())
    data["reason"] = pa.array(result["reason"], pa.string())
    for name, v in result["metrics"].items():
        v = np.asarray(v, dtype=float)
        data[name] = pa.array(v, pa.float64(), mask=~np.isfinite(v))
    return pa.table(data)


def write_parquet(table, path: Path, provenance: dict | None = None) -> None:
    """``table`` to ``path`` atomically (a temporary file renamed into place: a killed run
    leaves the file whole or absent), with ``provenance`` in its metadata."""
    import pyarrow.parquet as pq

    if provenance is not None:
        table = table.replace_schema_metadata({PROVENANCE_KEY: json.dumps(provenance, sort_keys=True).encode()})
    tmp = path.with_name(path.name + ".part")
    pq.write_table(table, tmp, compression="zstd")
    os.replace(tmp, path)


def read_parquet(path: Path):
    import pyarrow.parquet as pq

    return pq.read_table(path)


def write_csv(table, path: Path) -> None:
    """The table as CSV (pyarrow's writer): numbers at full precision (the shortest text that
    reads back to the same float), an empty cell where the Parquet has none."""
    import pyarrow.csv as pcsv

    tmp = path.with_name(path.name + ".part")
    pcsv.write_csv(table, tmp, pcsv.WriteOptions(quoting_style="needed"))
    os.replace(tmp, path)


def provenance(source: str, digest: str, fields, sampling: dict, angles: int) -> dict:
    """What made the table: versions, the description's hash, the fields and the sampling."""
    from importlib.metadata import PackageNotFoundError, version

    def ver(name: str) -> str:
        try:
            return version(name)
        except PackageNotFoundError:
            return "(not installed)"

    return {"description": source, "description_sha256": digest, "linkgen": ver("linkgen"), "numpy": np.__version__,
            "mujoco": ver("mujoco"), "pyarrow": ver("pyarrow"),
            "fields": [{"path": f.path, "start": f.start, "stop": f.stop, "count": f.count, "unit": f.unit}
                       for f in fields],
            "sampling": sampling, "crank_angles": angles}


__all__ = ["PROVENANCE_KEY", "provenance", "read_parquet", "to_arrow", "write_csv", "write_parquet"]
