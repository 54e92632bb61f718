"""Benchmark: closed-form kinematics of the four-bar over 10^6 crank angles against pylinkage.

Run by hand (``make bench``); not a test. Baseline, measured in the same run:
pylinkage's numba-compiled ``Linkage.step_fast_with_kinematics`` on the same four-bar
(OA 0.3, AB 1.0, BC 0.7, C = (1, 0)), 10^6 steps, positions + velocities + accelerations.

Targets (issue 2): warm >= 3x pylinkage's warm speed; cold (fresh process, imports
included, to the first result) <= 0.5 s.
"""

from __future__ import annotations

import math
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

N = 1_000_000
ROOT = Path(__file__).resolve().parent.parent
MODEL = ROOT / "models" / "fourbar.toml"
REPEATS = 5

COLD = f"""
import time; t0 = time.perf_counter()
import numpy as np
from linkgen import load, solve
kin = solve(load({str(MODEL)!r}), np.linspace(0.0, 2*np.pi, {N}, endpoint=False))
mo = kin.motion(10.0, 0.0)
print(time.perf_counter() - t0)
"""


def ours_warm() -> float:
    from linkgen import assemble, load, solve

    asm = assemble(load(MODEL))
    phi = np.linspace(0.0, 2 * np.pi, N, endpoint=False)
    best = math.inf
    for _ in range(REPEATS):
        t = time.perf_counter()
        solve(asm, phi).motion(10.0, 0.0)
        best = min(best, time.perf_counter() - t)
    return best


def ours_cold() -> tuple[float, float]:
    t = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", COLD], check=True, capture_output=True, text=True)
    return float(out.stdout.strip()), time.perf_counter() - t


def pylinkage_fourbar():
    import pylinkage as pl

    o = pl.Ground(0.0, 0.0, name="O")
    c = pl.Ground(1.0, 0.0, name="C")
    a = pl.Crank(o, 0.3, angular_velocity=2 * math.pi / N, name="A")
    b = pl.RRRDyad(a, c, 1.0, 0.7, x=1.0143, y=0.6999, name="B")
    linkage = pl.Linkage((o, c, a, b), name="fourbar")
    linkage.set_input_velocity(a, 10.0, 0.0)
    return linkage


def pylinkage_warm() -> tuple[float, float]:
    linkage = pylinkage_fourbar()
    t = time.perf_counter()
    linkage.step_fast_with_kinematics(iterations=N)  # first call compiles
    first = time.perf_counter() - t
    best = math.inf
    for _ in range(REPEATS):
        linkage = pylinkage_fourbar()
        t = time.perf_counter()
        linkage.step_fast_with_kinematics(iterations=N)
        best = min(best, time.perf_counter() - t)
    return best, first


def main() -> None:
    warm = ours_warm()
    cold_inner, cold_wall = ours_cold()
    print(f"linkgen  warm: {warm * 1e3:8.1f} ms for {N} angles (best of {REPEATS})")
    print(f"linkgen  cold: {cold_inner:8.3f} s to the first result inside a fresh process "
          f"(imports included); {cold_wall:.3f} s wall including interpreter start")
    try:
        base, first = pylinkage_warm()
    except ImportError:
        print("pylinkage not installed: pip install -e '.[bench]'")
        return
    print(f"pylinkage warm: {base * 1e3:8.1f} ms (step_fast_with_kinematics, numba; first call with "
          f"compilation {first:.2f} s)")
    print(f"ratio warm pylinkage/linkgen = {base / warm:.2f} (target >= 3)")
    print(f"cold to first result = {cold_wall:.3f} s (target <= 0.5 s)")


if __name__ == "__main__":
    main()
