"""One chunk of a study, computed where it runs (a local process or a Dask worker): the rows
the four-bar kernel takes through it (``fourbar``), every other row through the general route
(``general``). A row's values do not depend on the chunk it falls in: the kernel works on each
variant's own numbers (elementwise, reductions along its own angles), so a study gives the same
table bit for bit whatever its chunking, executor or number of workers."""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np


@dataclass(frozen=True)
class Task:
    """A chunk: the description (its source name and TOML text), the varied paths, the first
    row's index, the rows' values (V, n_fields) [SI] and the number of crank angles."""

    source: str
    text: str
    paths: tuple[str, ...]
    first: int
    values: np.ndarray
    angles: int


@lru_cache(maxsize=4)
def _base(text: str, source: str):
    from linkgen.model.toml_file import parse_toml
    from linkgen.pipeline.registry import from_dict

    data = parse_toml(text, source)
    return data, from_dict(data, source)


def run(task: Task) -> dict:
    """The chunk's columns: ``variant`` (V,) int, ``status``/``error``/``reason`` lists of
    str (None on a computed row) and each metric column (V,) float (NaN where it does not apply
    or the row failed)."""
    from linkgen.studies.fields import override
    from linkgen.studies.fourbar import solve
    from linkgen.studies.fourbar_params import fourbar_of, params, takes
    from linkgen.studies.general import layout_of, variant
    from linkgen.studies.metrics import angles

    data, mech = _base(task.text, task.source)
    phi, full = angles(mech.drive.start, mech.drive.stop, task.angles)
    rows = task.values.shape[0]
    fb = fourbar_of(mech)
    layout = fb.layout if fb is not None else layout_of(mech)
    error: list = [None] * rows
    reason: list = [None] * rows
    if fb is not None and takes(fb, list(task.paths)):
        cols, failures, general = solve(fb, mech, params(fb, mech, list(task.paths), task.values), phi, full)
        for r, kind, text in failures:
            error[r], reason[r] = kind, text
    else:
        cols = {k: np.full(rows, np.nan) for k in layout.columns}
        general = np.ones(rows, dtype=bool)
    for r in np.flatnonzero(general):
        got, kind, text = variant(override(data, dict(zip(task.paths, task.values[r].tolist()))), task.source, phi,
                                  full, layout)
        if got is None:
            error[r], reason[r] = kind, text
        else:
            for k, v in got.items():
                cols[k][r] = v
    status = ["ok" if e is None else "failed" for e in error]
    return {"variant": np.arange(task.first, task.first + rows, dtype=np.int64), "values": task.values,
            "status": status, "error": error, "reason": reason, "metrics": cols}


__all__ = ["Task", "run"]
