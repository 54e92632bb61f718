"""Generated mechanisms through MuJoCo and the closed form: counts of outcomes, the worst
error per quantity kind, and every failure written out as TOML for replay.

    python validation/mujoco_corpus.py            # 240 mechanisms, seeds 0..239
    python validation/mujoco_corpus.py --n 40 --seed 1000 --out failures/

Each mechanism comes from ``linkgen.families.planar.corpus.random_description`` (ranges 5° clear of assembly
limits, sizes 1 cm..30 m, ω 0.1..300 rad/s) and runs ``linkgen.crosscheck.run.crosscheck`` at its own
ω, in worker processes (one per core, one MuJoCo thread each). Progress on stderr.
"""

from __future__ import annotations

import argparse
import multiprocessing
import sys
import time
from collections import Counter
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

import numpy as np

KINDS = {"kinematics": ("points.", "links.", "sliders."), "forces (forward)": ("reactions.", "prismatic.",
         "balancing_torque", "reduced_inertia"), "forces (inverse)": ("inverse.",)}


def run_one(seed: int, margin: float, max_steps: int) -> dict:
    import traceback

    from linkgen import LinkgenError, assemble, from_dict
    from linkgen.families.planar.corpus import random_description, to_toml
    from linkgen.crosscheck.run import crosscheck

    desc = random_description(np.random.default_rng(seed), margin_deg=margin)
    out = {"seed": seed, "toml": to_toml(desc), "omega": desc["drive"]["omega"]}
    t0 = time.perf_counter()
    try:
        cc = crosscheck(assemble(from_dict(desc)), practical=False, nthread=1, max_steps=max_steps)
    except LinkgenError as exc:
        out |= {"outcome": f"error: {type(exc).__name__}", "message": str(exc)}
        return out
    except Exception:  # noqa: BLE001 - a traceback is the finding
        out |= {"outcome": "traceback", "message": traceback.format_exc()}
        return out
    j = cc.to_json()
    out |= {"outcome": "ok" if cc.ok else "explained failure: " + ",".join(sorted({d["cause"] for d in j["diagnosis"]})),
            "wall": time.perf_counter() - t0, "steps": j.get("steps"), "attempts": len(j["attempts"]),
            "gap": j.get("loop_gap", {}).get("relative"), "size": j.get("size_m"),
            "worst": {}, "diagnosis": j["diagnosis"][:3]}
    for kind, prefixes in KINDS.items():
        q = {k: v for k, v in j.get("quantities", {}).items() if k.startswith(prefixes)
             and not (kind != "forces (inverse)" and k.startswith("inverse."))}
        if q:
            k = max(q, key=lambda name: q[name]["relative_error"])
            out["worst"][kind] = (q[k]["relative_error"], k)
    return out


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=240)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--margin", type=float, default=5.0, help="range clearance from assembly limits [deg]")
    ap.add_argument("--out", type=Path, help="write failing mechanisms here as TOML")
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--max-steps", type=int, default=1_000_000,
                    help="step budget per run (a run needing more is reported, not started)")
    args = ap.parse_args()
    t0 = time.perf_counter()
    counts: Counter = Counter()
    worst: dict = {}
    slow = []
    ctx = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(args.workers, mp_context=ctx) as pool:
        futs = [pool.submit(run_one, s, args.margin, args.max_steps) for s in range(args.seed, args.seed + args.n)]
        for i, fut in enumerate(as_completed(futs), 1):
            r = fut.result()
            counts[r["outcome"]] += 1
            for kind, (err, name) in r.get("worst", {}).items():
                if err > worst.get(kind, (0.0,))[0]:
                    worst[kind] = (err, name, r["seed"])
            if r.get("gap") is not None and r["gap"] > worst.get("loop gap / size", (0.0,))[0]:
                worst["loop gap / size"] = (r["gap"], "loop_gap", r["seed"])
            slow.append((r.get("wall", 0.0), r["seed"], r.get("steps")))
            if r["outcome"] != "ok":
                msg = r.get("message") or "; ".join(f"{d['quantity']} {d['relative_error'] or float('inf'):.1e} {d['cause']}"
                                                   for d in r.get("diagnosis", []))
                print(f"seed {r['seed']}: {r['outcome']}: {msg.strip().splitlines()[-1][:300]}", file=sys.stderr)
                if args.out:
                    args.out.mkdir(parents=True, exist_ok=True)
                    (args.out / f"seed_{r['seed']}.toml").write_text(r["toml"])
            print(f"[{i}/{args.n}] {time.perf_counter() - t0:.0f} s", file=sys.stderr, flush=True)
    print(f"{args.n} generated mechanisms (seeds {args.seed}..{args.seed + args.n - 1}, ranges {args.margin:g}° clear "
          f"of assembly limits) in {time.perf_counter() - t0:.0f} s")
    for outcome, n in counts.most_common():
        print(f"  {outcome}: {n}")
    print("worst error per quantity kind (relative to its scale):")
    for kind, (err, name, seed) in worst.items():
        print(f"  {kind}: {err:.2e} ({name}, seed {seed})")
    slow.sort(reverse=True)
    print("slowest:", ", ".join(f"seed {s} {w:.1f} s ({n} steps)" for w, s, n in slow[:5]))
    return 0 if counts.get("ok", 0) == args.n else 1


if __name__ == "__main__":
    sys.exit(main())
