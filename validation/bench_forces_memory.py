"""Peak memory of ``linkgen.families.planar.kinetostatics.forces`` on the four-bar, each size in a fresh process.

Prints, per number of crank angles, the process's peak resident memory (VmHWM) after imports
and after the call, the bytes of the returned arrays, and the peak beyond imports and results
(what the blocks need: independent of the number of angles when forces run in blocks).

    .venv/bin/python validation/bench_forces_memory.py [N ...]     (default 100000 1000000)
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

CHILD = r"""
import json, sys, time
import numpy as np
from linkgen import assemble, load
from linkgen.families.planar.kinetostatics import forces

def hwm():
    for line in open("/proc/self/status"):
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) * 1024
n = int(sys.argv[1])
asm = assemble(load(sys.argv[2]))
phi = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
forces(asm, phi[:1000], 3.0, 1.0)  # imports and first-call caches
before = hwm()
t0 = time.perf_counter()
f = forces(asm, phi, 3.0, 1.0)
dt = time.perf_counter() - t0
arrays = [f.phi, f.omega, f.epsilon, f.balancing_torque, f.power_balance_torque, f.singular,
          *f.reactions.values(), *f.normal_force.values(), *f.moment.values(),
          f.reduced.inertia, f.reduced.inertia_derivative, f.reduced.moment]
results = sum(a.nbytes for a in {id(a): a for a in arrays}.values() if a.strides[0] != 0)
print(json.dumps({"n": n, "before": before, "after": hwm(), "results": results, "seconds": dt}))
"""


def main(sizes: list[int]) -> None:
    model = str(ROOT / "models" / "fourbar.toml")
    print(f"{'angles':>9} {'peak after imports [MB]':>24} {'peak after [MB]':>16} {'results [MB]':>13} "
          f"{'peak - imports - results [MB]':>30} {'time [s]':>9}")
    for n in sizes:
        out = subprocess.run([sys.executable, "-c", CHILD, str(n), model], capture_output=True, text=True,
                             check=True).stdout
        r = json.loads(out)
        mb = 1 / 2**20
        print(f"{n:>9} {r['before'] * mb:>24.1f} {r['after'] * mb:>16.1f} {r['results'] * mb:>13.1f} "
              f"{(r['after'] - r['before'] - r['results']) * mb:>30.1f} {r['seconds']:>9.3f}")


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [100_000, 1_000_000])
