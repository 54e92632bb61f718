"""check-settings' prediction against MuJoCo's runs, over the bundled planar models and generated
mechanisms: per model and setting the predicted and measured relative errors (loop gap and point
positions to the size, reactions to the peak reaction, crank torque to its peak) and their ratio;
the worst ratio overall.

    python validation/check_settings_corpus.py              # bundled models + 20 generated (seeds 0..19)
    python validation/check_settings_corpus.py --n 40 --seed 100 --json out.json

Settings: MuJoCo's defaults (2 ms, Euler, solref "0.02 1", solimp "0.9 0.95 0.001 0.5 2"),
the same at implicitfast (no joint damping here: it steps as Euler does) and 2 ms RK4 with the
stiffest loops MuJoCo allows (solref 2·timestep). One process, one MuJoCo thread: the runs are
one revolution (or the range) each. Progress on stderr.
"""

from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
SETTINGS = {"defaults (2 ms, Euler)": dict(timestep=2e-3, integrator="Euler"),
            "2 ms implicitfast": dict(timestep=2e-3, integrator="implicitfast"),
            "2 ms RK4, solref 4 ms": dict(timestep=2e-3, integrator="RK4", solref=(4e-3, 1.0))}


def one(name: str, asm) -> list[dict]:
    from linkgen.crosscheck.check_settings import check_settings, user_settings

    rows = []
    for label, kw in SETTINGS.items():
        t0 = time.perf_counter()
        r = check_settings(asm, user_settings(**kw), search=False)
        d = r.to_dict()
        finite = [x for x in d["ratios"].values() if x is not None]
        worst = max(finite, key=lambda x: max(x, 1 / x)) if finite else None
        rows.append({"model": name, "settings": label, "predicted": d["predicted"]["errors"],
                     "measured": d["measured"]["errors"] or dict.fromkeys(d["predicted"]["errors"]), "ratios": d["ratios"], "agrees": d["agrees"],
                     "worst_ratio": worst, "failure": d["measured"]["failure"], "wall_s": time.perf_counter() - t0})
    return rows


def mechanisms(n: int, seed: int):
    """(name, assembled mechanism or the reason it is not covered) for every bundled planar model and
    ``n`` generated ones."""
    from linkgen import LinkgenError, assemble, from_dict
    from linkgen.families.planar.corpus import random_description
    from linkgen.mujoco.accuracy import check_supported
    from linkgen.pipeline.registry import family_of, load

    for path in sorted((ROOT / "models").glob("*.toml")):
        desc = load(path)
        if family_of(desc).name != "planar":
            continue
        try:
            asm = assemble(desc)
            check_supported(asm)
        except LinkgenError as exc:
            yield path.stem, f"not covered: {exc}"
            continue
        yield path.stem, asm
    for s in range(seed, seed + n):
        desc = random_description(np.random.default_rng(s))
        yield f"generated seed {s} (ω {desc['drive']['omega']:.3g} rad/s)", assemble(from_dict(desc))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=20, help="generated mechanisms (default 20)")
    ap.add_argument("--seed", type=int, default=0, help="first seed of the generated ones (default 0)")
    ap.add_argument("--json", type=Path, help="write every row as JSON to this file")
    args = ap.parse_args()
    t0 = time.perf_counter()
    rows, skipped = [], []
    for i, (name, asm) in enumerate(mechanisms(args.n, args.seed)):
        if isinstance(asm, str):
            skipped.append((name, asm))
            continue
        got = one(name, asm)
        rows += got
        print(f"[{time.perf_counter() - t0:6.1f} s] {name}", file=sys.stderr, flush=True)
        for r in got:
            cells = "  ".join(f"{q} {r['predicted'][q]:.2e}/{r['measured'][q]:.2e}" if r["measured"][q] is not None
                              else f"{q} {r['predicted'][q]:.2e}/run failed" for q in r["predicted"])
            worst = "" if r["worst_ratio"] is None else f"worst ratio {r['worst_ratio']:.2f}"
            flag = "" if all(v is not False for v in r["agrees"].values()) else "  OUTSIDE A FACTOR 3"
            print(f"{name:<34} {r['settings']:<24} {cells}  {worst}{flag}"
                  + (f"  run failed: {r['failure']}" if r["failure"] else ""))
    for name, why in skipped:
        print(f"{name:<34} {why}")
    judged = [r for r in rows if r["worst_ratio"] is not None]
    out = [r for r in rows if any(v is False for v in r["agrees"].values())]
    worst = max(judged, key=lambda r: max(r["worst_ratio"], 1 / r["worst_ratio"])) if judged else None
    print(f"\n{len(rows)} runs of {len(rows) // len(SETTINGS)} mechanisms in {time.perf_counter() - t0:.0f} s; "
          f"{len(out)} outside a factor 3"
          + (f"; worst ratio {worst['worst_ratio']:.2f} ({worst['model']}, {worst['settings']})" if worst else ""))
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1, default=lambda x: None if isinstance(x, float) and not math.isfinite(x) else x))
    return 0


if __name__ == "__main__":
    sys.exit(main())
