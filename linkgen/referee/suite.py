"""A reference suite for solver authors (``linkgen suite export DIR``) and the referee of a
whole suite's answers (``linkgen referee --suite DIR ANSWERS``).

The suite holds mechanisms of every family: ``count`` drawn from a seed, in turn a random planar
linkage (``families.planar.corpus``: one to three Assur groups of every kind), a bundled
stand-alone cam and a bundled spatial four-bar (from the source tree's models/, when there).
Each mechanism's folder holds its description (``description.toml``), its MJCF (``model.xml``),
the closed form at sampled crank angles (``kinematics.csv``, ``forces.csv``: linkgen's headers
with their units) and MuJoCo's agreement with the closed form (``mujoco.json``, when run).
``manifest.json`` lists them with the drive's ω and ε and states the tolerance the referee
applies. An answer is a CSV in ``ANSWERS/<folder>/`` (any name) headed like the suite's."""

from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path
from typing import Callable

import numpy as np

from linkgen.errors import DescriptionError
from linkgen.outputs import atomic_write_text, output_folder
from linkgen.pipeline.registry import family_of, loads, stage
from linkgen.referee.compare import DEFAULT_TOLERANCE, referee
from linkgen.referee.reference import NOT_QUANTITIES

MANIFEST = "manifest.json"
FORMAT = 1
# Crank angles per mechanism in the suite's tables: 5° steps over a full turn.
SAMPLES = 72
_BUNDLED = Path(__file__).resolve().parents[2] / "models"


def _bundled(family: str) -> list[Path]:
    if not _BUNDLED.is_dir():
        return []
    from linkgen.pipeline.registry import family_of_file

    return [p for p in sorted(_BUNDLED.glob("*.toml")) if (f := family_of_file(p)) is not None and f.name == family]


def _draw(count: int, seed: int) -> list[tuple[str, str]]:
    """(name, TOML text) of ``count`` mechanisms drawn from ``seed``."""
    from linkgen.families.planar.corpus import random_description
    from linkgen.model.toml_text import to_toml

    rng = np.random.default_rng(seed)
    others = {f: _bundled(f) for f in ("cam", "spatial")}
    out = []
    for i in range(count):
        kind = ("planar", "cam", "spatial")[i % 3]
        if kind != "planar" and others[kind]:
            path = others[kind][int(rng.integers(len(others[kind])))]
            out.append((f"{i + 1:02d}_{path.stem}", path.read_text(encoding="utf-8")))
            continue
        desc = random_description(rng, max_groups=3)
        desc["mechanism"]["name"] = f"suite_{seed}_{i + 1:02d}"
        out.append((f"{i + 1:02d}_planar", to_toml(desc)))
    return out


def _csv(cols: dict[str, np.ndarray]) -> str:
    keep = {k: v for k, v in cols.items() if k not in NOT_QUANTITIES or k == "phi [rad]"}
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow(list(keep))
    for row in zip(*(np.asarray(v, dtype=float) for v in keep.values())):
        w.writerow([repr(float(x)) for x in row])
    return buf.getvalue()


def export(out: str | Path, *, count: int = 6, seed: int = 0, mujoco: bool = True,
           progress: Callable[[str], None] | None = None) -> Path:
    """Write the suite into the folder ``out``; returns the manifest's path."""
    folder = output_folder(out)
    entries = []
    for name, text in _draw(count, seed):
        if progress:
            progress(f"{name}: closed form" + (", MuJoCo" if mujoco else ""))
        desc = loads(text, name)
        fam = family_of(desc)
        sub = output_folder(folder / name)
        atomic_write_text(sub / "description.toml", text)
        atomic_write_text(sub / "model.xml", stage(desc, "mjcf")(desc))
        phi = stage(desc, "angles")(desc, SAMPLES)
        files = {}
        for what in ("kinematics", "forces"):
            if what in fam.stages:
                r = stage(desc, what)(desc, phi, on_singular="mark")
                atomic_write_text(sub / f"{what}.csv", _csv(r.columns(transfer=True)))
                files[what] = f"{name}/{what}.csv"
                omega, epsilon = float(np.ravel(r.omega)[0]), float(np.ravel(r.epsilon)[0])
        entry = {"folder": name, "family": fam.name, "model": desc.name if hasattr(desc, "name") else name,
                 "description": f"{name}/description.toml", "mjcf": f"{name}/model.xml", "tables": files,
                 "samples": SAMPLES, "omega": omega, "epsilon": epsilon, "mujoco": None}
        if mujoco:
            entry["mujoco"] = _mujoco(desc, sub / "mujoco.json", name)
        entries.append(entry)
    manifest = {"format": FORMAT, "seed": seed, "count": count, "tolerance": {
        "relative": DEFAULT_TOLERANCE,
        "scale": "per column, the largest magnitude over the sampled angles of every closed-form column in its unit",
        "angles": "angles compared modulo 2π"},
        "answers": "a CSV per mechanism in ANSWERS/<folder>/, headed as the suite's tables (phi [rad] or phi [deg], "
                   "any subset of the quantities, any units written in brackets); `linkgen referee --suite DIR ANSWERS`",
        "mechanisms": entries}
    path = folder / MANIFEST
    atomic_write_text(path, json.dumps(manifest, indent=2, allow_nan=False) + "\n")
    return path


def _mujoco(desc, path: Path, name: str) -> dict:
    """MuJoCo's agreement with the closed form (``validate`` without the practical-settings runs)."""
    from linkgen.errors import LinkgenError

    try:
        check = stage(desc, "validate")(desc, practical=False)
    except LinkgenError as exc:
        return {"ok": False, "summary": f"not validated: {exc}"}
    atomic_write_text(path, json.dumps(check.to_dict(), indent=2, allow_nan=False, default=_plain) + "\n")
    return {"ok": bool(check.ok), "summary": check.summary(), "details": f"{name}/mujoco.json"}


def _plain(x):
    if isinstance(x, (np.floating, np.integer)):
        return x.item()
    raise TypeError(type(x).__name__)


def read_manifest(suite: str | Path) -> dict:
    path = Path(suite) / MANIFEST
    try:
        data = json.loads(path.read_text(encoding="utf-8"))
    except OSError as exc:
        raise DescriptionError("", f"cannot be read ({exc.strerror or exc}); a suite folder holds the manifest "
                               "`linkgen suite export` writes", str(path)) from None
    except ValueError as exc:
        raise DescriptionError("", f"is not JSON ({exc})", str(path)) from None
    if not isinstance(data, dict) or data.get("format") != FORMAT or not isinstance(data.get("mechanisms"), list):
        raise DescriptionError("format", f"not a suite manifest of format {FORMAT}", str(path))
    return data


def referee_suite(suite: str | Path, answers: str | Path, *, tolerance: float | None = None,
                  mujoco: bool = False) -> list[dict]:
    """Every answer against its mechanism: one entry per mechanism, with its verdicts (one per
    CSV found in ``answers/<folder>/``) or ``missing`` when none is there."""
    suite, answers = Path(suite), Path(answers)
    if not answers.is_dir():
        raise DescriptionError("", "is not a folder (the answers: a folder per mechanism, named as the suite's)",
                               str(answers))
    manifest = read_manifest(suite)
    tol = manifest["tolerance"]["relative"] if tolerance is None else tolerance
    out = []
    for m in manifest["mechanisms"]:
        desc = loads((suite / m["description"]).read_text(encoding="utf-8"), str(suite / m["description"]))
        files = sorted((answers / m["folder"]).glob("*.csv")) if (answers / m["folder"]).is_dir() else []
        verdicts = [referee(desc, f, omega=m["omega"], epsilon=m["epsilon"], tolerance=tol, mujoco=mujoco)
                    for f in files]
        out.append({"folder": m["folder"], "family": m["family"], "verdicts": verdicts, "missing": not files})
    return out


def suite_text(results: list[dict]) -> str:
    lines = []
    for r in results:
        if r["missing"]:
            lines.append(f"{r['folder']}: no answer")
            continue
        for v in r["verdicts"]:
            bad = [c for c in v.columns if not c.routes["closed_form"].agrees]
            state = "ok  " if not bad else "DIFF"
            lines.append(f"{state} {r['folder']}: {Path(v.source).name}: {len(v.columns) - len(bad)} of "
                         f"{len(v.columns)} columns agree")
            for c in bad:
                lines.append(f"       {c.header}: {c.routes['closed_form'].error:.2e} at φ = "
                             f"{math.degrees(c.routes['closed_form'].at_phi):.4g}°; {c.diagnosis.text if c.diagnosis else ''}")
    return "\n".join(lines)

