"""Every machine (a description with a ``[machine]`` table) driven by its motor in MuJoCo's full
linkage against the one- or two-mass ODE, over the start-up and ten steady cycles: the error of
ω (start-up and steady), the motor torque, the shaft twist and the joint reactions (MuJoCo's
against the kinetostatics at MuJoCo's own crank states, outside the loops' settling window after
the start and each load switch), each relative to its peak.

    python validation/machines.py                 # every models/*.toml with a [machine] table
    python validation/machines.py FILE.toml ...   # given descriptions
    python validation/machines.py --cycles 3 --json out.json

Machines run side by side in worker processes (one per core). A MuJoCo machine steps in Python
(the motor law and the loads are applied each step), so a machine of ten seconds at a 15 µs
timestep takes minutes: this is why the test suite compares only the first second.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def run_one(path: str, cycles: int) -> dict:
    from linkgen.crosscheck.machine import compare_machine

    t0 = time.perf_counter()
    out = compare_machine(path, cycles=cycles) or {"skipped": "no [machine] table"}
    return {"model": Path(path).stem, "wall_s": time.perf_counter() - t0, **out}


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("files", nargs="*", type=Path, help="descriptions (default: models/*.toml with a [machine] table)")
    p.add_argument("--cycles", type=int, default=10, help="steady cycles compared after the start-up (default 10)")
    p.add_argument("--json", type=Path, help="write the results here")
    args = p.parse_args(argv)
    files = args.files or [f for f in sorted((ROOT / "models").glob("*.toml"))
                            if "[machine]" in f.read_text(encoding="utf-8")]
    results = []
    with ProcessPoolExecutor() as pool:
        jobs = {pool.submit(run_one, str(f), args.cycles): f for f in files}
        for job in as_completed(jobs):
            r = job.result()
            results.append(r)
            print(f"done {r['model']} in {r['wall_s']:.0f} s", file=sys.stderr, flush=True)
    results.sort(key=lambda r: r["model"])
    print("| model | compared [s] | steady from [s] | ω start-up | ω steady | motor torque | twist | reactions | "
          "φ [rad] | steps | wall [s] | ok |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for r in results:
        if "skipped" in r:
            print(f"| {r['model']} | skipped: {r['skipped']} |  |  |  |  |  |  |  |  |  |  |")
            continue
        e = r["errors_relative"]

        def f(x):
            return "–" if x is None else f"{x:.2e}"

        print(f"| {r['model']} | {r['duration_s']:.4g} | {r.get('steady_from_s', float('nan')):.4g} | "
              f"{f(e.get('omega_startup'))} | {f(e.get('omega_steady'))} | {f(e['motor_torque'])} | {f(e['twist'])} | "
              f"{f(e.get('reactions'))} | {r['phi_error_rad']:.2e} | {r['steps']} | {r['wall_s']:.0f} | "
              f"{'yes' if r['ok'] else 'NO'} |")
    if args.json:
        args.json.write_text(json.dumps(results, indent=2), encoding="utf-8")
    return 0 if all(r.get("ok") for r in results) else 1


if __name__ == "__main__":
    sys.exit(main())
