"""A sample of a study's variants validated in MuJoCo: the extremes of the main metrics (each
one's least and greatest among the variants that work) and a seeded random sample of the
others, each through the MuJoCo cross-check (``linkgen.validate``, MuJoCo's run of the
variant's own MJCF compared with the closed form), one variant after another.

Written to ``validation.json`` in the study's folder: per variant its row, its fields and the
cross-check's verdict and summary."""

from __future__ import annotations

import json
import sys
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from linkgen.studies.plots import MAIN


@dataclass(frozen=True)
class SampleValidation:
    """The variants validated: (row, why chosen, ok, the cross-check's summary line)."""

    rows: tuple[tuple[int, str, bool, str], ...]

    @property
    def ok(self) -> bool:
        return all(r[2] for r in self.rows)

    def text(self) -> str:
        lines = [f"validated {len(self.rows)} variants in MuJoCo: "
                 f"{sum(r[2] for r in self.rows)} ok, {sum(not r[2] for r in self.rows)} failed"]
        lines += [f"  variant {row} ({why}): {summary}" for row, why, _, summary in self.rows]
        return "\n".join(lines)


def choose(table, k: int, seed: int = 0) -> list[tuple[int, str]]:
    """Up to ``k`` rows that work: the extremes of the main metrics first, then a random sample."""
    ok = np.array([s == "ok" for s in table.column("status").to_pylist()])
    rows = np.flatnonzero(ok)
    picked: list[tuple[int, str]] = []
    for m in MAIN:
        if m not in table.column_names or not rows.size:
            continue
        v = np.array([np.nan if x is None else x for x in table.column(m).to_pylist()], dtype=float)[rows]
        for which, idx in (("least", int(rows[np.nanargmin(v)])), ("greatest", int(rows[np.nanargmax(v)]))):
            if idx not in [p[0] for p in picked]:
                picked.append((idx, f"{which} {m.split(' [')[0]}"))
    rest = np.setdiff1d(rows, [p[0] for p in picked])
    extra = np.random.default_rng(seed).permutation(rest)[:max(0, k - len(picked))]
    return (picked + [(int(r), "random") for r in np.sort(extra)])[:k]


def validate_sample(study, table, k: int, out: Path) -> SampleValidation:
    """Validate ``k`` variants of ``table`` in MuJoCo; their verdicts, also in ``out/validation.json``."""
    from linkgen.model.toml_file import parse_toml
    from linkgen.outputs import atomic_write_text
    from linkgen.pipeline.registry import from_dict, stage
    from linkgen.studies.design import variant_data

    data = parse_toml(study.text, study.source)
    paths = [f.path for f in study.fields]
    results, entries = [], []
    for i, (row, why) in enumerate(choose(table, k, study.sampling.get("seed", 0))):
        values = study.values[row].tolist()
        mech = from_dict(variant_data(data, study.source, dict(zip(paths, values))), study.source)
        print(f"sweep: validating variant {row} ({why}) in MuJoCo, {i + 1} of {k}", file=sys.stderr, flush=True)
        result = stage(mech, "validate")(mech, practical=False)
        results.append((row, why, bool(result.ok), result.summary()))
        entries.append({"variant": row, "chosen": why, "fields": dict(zip(paths, values)), "ok": bool(result.ok),
                        "summary": result.summary()})
    atomic_write_text(out / "validation.json", json.dumps(entries, indent=2, ensure_ascii=False) + "\n")
    return SampleValidation(tuple(results))


__all__ = ["SampleValidation", "choose", "validate_sample"]
