"""A sweep from what the user gives: the description file, ``--vary`` fields, a grid or a
Latin hypercube (``make_study``); its outputs in the directory asked for (``write_outputs``:
``sweep.parquet``, ``sweep.csv``, ``sweep.json``)."""

from __future__ import annotations

import json
from pathlib import Path

from linkgen.errors import ArgumentError, UnsupportedError
from linkgen.studies.engine import Study
from linkgen.studies.fields import check_path, parse_vary
from linkgen.studies.metrics import ANGLES
from linkgen.studies.samples import grid, latin_hypercube


def make_study(path: str | Path, vary: list[str], *, lhs: int | None = None, seed: int = 0,
               angles: int = ANGLES) -> Study:
    """The study of the description at ``path`` over the ``vary`` fields (``FIELD=START:STOP:N``
    on a grid; ``FIELD=START:STOP`` with ``lhs`` variants of a Latin hypercube, seeded).

    Raises:
        DescriptionError: the description itself is invalid.
        ArgumentError: a field that is not a number of the description, a bad range.
        UnsupportedError: a description that is not a planar linkage.
    """
    from linkgen.model.toml_file import parse_toml, read_bytes
    from linkgen.pipeline.registry import family_of, from_dict

    if not vary:
        raise ArgumentError("--vary: give at least one FIELD=START:STOP:N")
    raw = read_bytes(path)
    data = parse_toml(raw, str(path))  # refuses a file that is not UTF-8 TOML, naming it
    text = raw.decode("utf-8-sig")
    desc = from_dict(data, str(path))
    if family_of(desc).name != "planar":
        raise UnsupportedError(f"{path}: `linkgen sweep` is for planar linkages; this is a "
                               f"{family_of(desc).title}")
    fields = tuple(parse_vary(v, grid=lhs is None) for v in vary)
    seen = set()
    for f in fields:
        check_path(data, f.path)
        if f.path in seen:
            raise ArgumentError(f"--vary {f.path}: given twice")
        seen.add(f.path)
    if lhs is None:
        values, sampling = grid(fields), {"method": "grid"}
    else:
        values, sampling = latin_hypercube(fields, lhs, seed), {"method": "lhs", "n": lhs, "seed": seed}
    if not 2 <= angles <= 100_000:
        raise ArgumentError(f"--angles: expected 2 to 100000 crank angles per variant, got {angles}")
    return Study(str(path), text, fields, values, sampling, angles)


def write_outputs(table, study: Study, out: Path) -> dict[str, Path]:
    """The table as Parquet and CSV and the provenance sidecar in ``out``."""
    from linkgen.studies.table import provenance, write_csv, write_parquet

    prov = provenance(Path(study.source).name, study.digest, study.fields, study.sampling, study.angles)
    paths = {"parquet": out / "sweep.parquet", "csv": out / "sweep.csv", "json": out / "sweep.json"}
    write_parquet(table, paths["parquet"], prov)
    write_csv(table, paths["csv"])
    ok = sum(1 for s in table.column("status").to_pylist() if s == "ok")
    side = dict(prov, rows=table.num_rows, ok=ok, failed=table.num_rows - ok,
                columns={c: (c.rsplit(" [", 1)[1][:-1] if c.endswith("]") else None) for c in table.column_names})
    tmp = paths["json"].with_name("sweep.json.part")
    tmp.write_text(json.dumps(side, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")
    tmp.replace(paths["json"])
    return paths


__all__ = ["make_study", "write_outputs"]
