"""Cost of a validated revolution against crank speed and size: steps, wall time and peak
memory per revolution of the bundled four-bar (with gravity) at ω = 0.1 … 1000 rad/s and
scaled to 1 cm, 1 m and 30 m, each in a fresh process (peak memory is the process's).

    python validation/scaling.py            # the table
    python validation/scaling.py --one fourbar.toml 10 1.0   # one case (used internally)
"""

from __future__ import annotations

import json
import resource
import subprocess
import sys
import time
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
OMEGAS = (0.1, 1.0, 10.0, 100.0, 1000.0)
SIZES = (0.01, 1.0, 30.0)  # scale factor on the four-bar's lengths (its size is ~1.2 m)


def one(path: str, omega: float, factor: float) -> dict:
    from linkgen import assemble, from_dict
    from linkgen.families.planar.corpus import scaled
    from linkgen.crosscheck.run import crosscheck

    t0 = time.perf_counter()
    desc = scaled(tomllib.loads(Path(path).read_text()), factor, omega)
    cc = crosscheck(assemble(from_dict(desc)), practical=False,
                    progress=lambda f, e: print(f"  {100 * f:.0f}% after {e:.0f} s", file=sys.stderr, flush=True))
    j = cc.to_json()
    return {"omega": omega, "factor": factor, "ok": j["ok"], "steps": j.get("steps"),
            "steps_per_revolution": j.get("steps_per_revolution"), "wall_s": time.perf_counter() - t0,
            "timestep": j.get("settings", {}).get("timestep"), "timeconst": j.get("settings", {}).get("timeconst"),
            "loop_gap_relative": j.get("loop_gap", {}).get("relative"),
            "worst": max(((q["relative_error"] / q["tolerance"], k) for k, q in j.get("quantities", {}).items()),
                         default=(None, None)),
            "peak_rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
            "diagnosis": [d["cause"] for d in j["diagnosis"]]}


def main() -> None:
    if sys.argv[1:2] == ["--one"]:
        print(json.dumps(one(sys.argv[2], float(sys.argv[3]), float(sys.argv[4]))))
        return
    model = str(ROOT / "models" / "fourbar.toml")
    cases = [(w, 1.0) for w in OMEGAS] + [(10.0, f) for f in SIZES if f != 1.0]
    print("| ω [rad/s] | size [m] | ok | timestep [s] | loop τ [s] | steps/rev | wall [s] (incl. start-up) "
          "| peak memory [MB] | loop gap / L | worst error / tolerance |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for w, f in cases:
        t0 = time.perf_counter()
        res = subprocess.run([sys.executable, __file__, "--one", model, str(w), str(f)], capture_output=True, text=True)
        wall = time.perf_counter() - t0
        if res.returncode:
            print(f"| {w:g} | {1.2 * f:.3g} | error: {res.stderr.strip().splitlines()[-1]} |")
            continue
        r = json.loads(res.stdout)
        ratio, name = r["worst"]
        print(f"| {w:g} | {1.24 * f:.3g} | {'yes' if r['ok'] else 'no ' + ','.join(r['diagnosis'])} | "
              f"{r['timestep']:.3g} | {r['timeconst']:.3g} | {r['steps_per_revolution']:.0f} | {wall:.2f} | "
              f"{r['peak_rss_mb']:.0f} | {r['loop_gap_relative']:.1e} | {ratio:.2f} ({name}) |", flush=True)


if __name__ == "__main__":
    main()
