"""Benchmark: closed-form kinematics of the four-bar over 10^6 crank angles against pylinkage.

Run by hand (``make bench``); not a test. Baseline, measured in the same run: pylinkage's
numba-compiled ``Linkage.step_fast_with_kinematics`` on the same four-bar (OA 0.3, AB 1.0,
BC 0.7, C = (1, 0)), 10^6 steps, positions + velocities + accelerations of every joint.

linkgen is timed on the same job and a little more: ``solve_motion`` (positions, velocities,
accelerations, and jerks, which pylinkage does not give), and for reference
``solve(...).motion(...)``, which also keeps the transfer functions.

Targets (issue 23): warm, all cores, <= 30 ms and >= 20x pylinkage's warm speed, the seven-link
in proportion; the kinetostatics >= 2 M angles/s (the seven-link >= 1 M); cold (fresh process, imports included, to the first result)
<= 0.25 s. Two more yardsticks are measured in the same run: the memory-bandwidth limit (the
time to write as many bytes as ``solve_motion``'s results hold, into fresh memory as a solve
does and into memory already mapped), and the CPU time of each timed run. On this shared
2-core machine a busy neighbour stretches wall times several-fold while CPU times hardly move
(measured: solve_motion single-threaded, 377 ms wall for 115 ms of CPU at load average 5.5):
compare CPU times across runs, and read the load average printed at the start and the end.

Where the time goes (issue 23; CPU times, one thread, 10^6 angles, on this machine while
it was shared, so +-10 %). The fall from 72-95 ms (6b94d89, 22 November) to 336-378 ms is
mostly not in the code: the same run of that commit and of today's code cost 85-101 ms and
115-137 ms of CPU. The rest was a busy machine (377 ms wall for 115 ms of CPU at load 5.5).
The code's own +30-35 % is the jerk: third transfer functions in every primitive and a fourth
result array per quantity (results 152 -> 200 bytes per angle). Per angle: the crank's point
19.7 ns (np.cos + np.sin of φ 16 ns: libm, NumPy has no SIMD float64 cos/sin), the RRR
intersection with three orders of transfer functions 27 ns, the two link poses 23 ns, the
points and finiteness checks ~12 ns, velocities/accelerations/jerks 11 ns, the results'
fresh memory and the copy out of each block ~25 ns. Two threads gain ~1.2x only: each block
holds the GIL between its ~1500 NumPy calls. The kinetostatics spent ~48 % of its time in
np.linalg.solve's 6x6 LAPACK call per group and angle (330 ns each); each group's six equations
are now solved in closed form (families/planar/equilibrium.py: the inner pair first from each
link's own equations), which took ``forces`` on one thread from 807 to 347 ms per 10^6 angles. Memory beyond the
results is flat: ~50 MB at 0.25, 1 and 4 x 10^6 angles. A compiled kernel (numba) was
measured and not taken: ``import numba`` alone is 0.25 s of CPU (the whole cold budget), and
numba's arctan2 (libm) differs from NumPy's (SVML) in the last bit for 7.7 % of 10^6 random
arguments, so its results could not stay bit-for-bit the same as today's.

Cold runs come in two kinds on this machine. Back to back, a fresh process reuses memory
the previous one just freed. After a few seconds idle, the virtual machine has handed freed
memory back to its host, and the first touch of each page costs far more (measured: 200 MB
filled in 0.04-0.08 s back to back, 0.64-0.95 s after 8 s idle). The benchmark reports
both; ``--idle 0`` skips the idle ones.
"""

from __future__ import annotations

import argparse
import math
import statistics
import subprocess
import sys
import os
import time
from pathlib import Path
from typing import NamedTuple

import numpy as np

N = 1_000_000
ROOT = Path(__file__).resolve().parent.parent
MODEL = ROOT / "models" / "fourbar.toml"
# The seven-link (three class-II groups to the four-bar's one): "in proportion" means its time
# over the four-bar's at most this ratio of groups.
SEVEN = ROOT / "models" / "seven_link.toml"
SEVEN_GROUPS = 3
REPEATS = 10
COLD_RUNS = 5

COLD = f"""
import time; t0 = time.perf_counter()
import numpy as np
from linkgen import load, solve_motion
mo = solve_motion(load({str(MODEL)!r}), np.linspace(0.0, 2*np.pi, {N}, endpoint=False), 10.0, 0.0)
t = time.perf_counter() - t0
print(t, next(int(l.split()[1]) for l in open("/proc/self/status") if l.startswith("VmHWM")) / 1024, time.process_time())
"""

PYLINKAGE_COLD = f"""
import time; t0 = time.perf_counter()
import sys; sys.path.insert(0, {str(Path(__file__).resolve().parent)!r})
from bench_kinematics import pylinkage_fourbar
pylinkage_fourbar().step_fast_with_kinematics(iterations={N})
t = time.perf_counter() - t0
print(t, next(int(l.split()[1]) for l in open("/proc/self/status") if l.startswith("VmHWM")) / 1024, time.process_time())
"""


class Timing(NamedTuple):
    wall: float  # [s], the best of the repeats
    cpu: float  # [s], user + system time of every thread of this process during that run


def best_of(fn, repeats: int = REPEATS) -> Timing:
    fn()
    best = Timing(math.inf, math.inf)
    for _ in range(repeats):
        c, t = time.process_time(), time.perf_counter()
        fn()
        run = Timing(time.perf_counter() - t, time.process_time() - c)
        best = min(best, run)
    return best


def drive_angles(asm) -> np.ndarray:
    """N angles over the model's drive range (the four-bar's: a full turn)."""
    drive = asm.mechanism.drive
    return np.linspace(drive.start, drive.stop, N, endpoint=False)


def ours_warm(threads: int | None, model: Path = MODEL) -> tuple[Timing, Timing]:
    from linkgen import assemble, load, solve, solve_motion

    asm = assemble(load(model))
    phi = drive_angles(asm)
    fused = best_of(lambda: solve_motion(asm, phi, 10.0, 0.0, threads=threads))
    full = best_of(lambda: solve(asm, phi, threads=threads).motion(10.0, 0.0))
    return fused, full


def forces_warm(threads: int | None, model: Path = MODEL) -> Timing:
    from linkgen import assemble, load
    from linkgen.families.planar.kinetostatics import forces

    asm = assemble(load(model))
    phi = drive_angles(asm)
    return best_of(lambda: forces(asm, phi, 10.0, 0.0, threads=threads), 3)


def result_bytes() -> int:
    """Bytes of the per-angle arrays ``solve_motion`` returns for the benchmark's job (arrays
    constant along φ are views and take none)."""
    from linkgen import load, solve_motion
    from linkgen.families.planar.blocks import leaves
    from linkgen.families.planar.primitives import constant_along

    mo = solve_motion(load(MODEL), np.linspace(0.0, 2 * np.pi, N, endpoint=False), 10.0, 0.0)
    arrays = leaves((mo.points, mo.links, mo.sliders, mo.jerk))
    return sum(a.nbytes for a in arrays if not constant_along(a))


def bandwidth_limit(nbytes: int) -> tuple[Timing, Timing]:
    """The time to write ``nbytes`` on one thread: into fresh memory (allocated and first
    touched in the timed run, as a solve's results are) and into memory already mapped."""
    words = nbytes // 8
    mapped = np.empty(words)
    return best_of(lambda: np.ones(words)), best_of(lambda: mapped.fill(1.0))


def cold(script: str, runs: int, idle: float) -> tuple[list[float], float, list[float]]:
    """Wall times [s] to the first result inside fresh processes (imports included), the
    largest peak resident memory [MB] among them (VmHWM: ru_maxrss would carry this parent's
    peak across exec), and each process's CPU time to its result [s]."""
    times, peak, cpus = [], 0.0, []
    for _ in range(runs):
        if idle:
            time.sleep(idle)
        res = subprocess.run([sys.executable, "-c", script], check=True, capture_output=True, text=True)
        t, rss, cpu = map(float, res.stdout.strip().splitlines()[-1].split())
        times.append(t)
        cpus.append(cpu)
        peak = max(peak, rss)
    return times, peak, cpus


def cli_cold(runs: int) -> list[float]:
    """Wall times [s] of whole ``linkgen analyze`` processes at one angle, back to back (the
    command as a user types it: interpreter start, imports, the answer printed)."""
    times = []
    for _ in range(runs):
        t = time.perf_counter()
        subprocess.run([sys.executable, "-m", "linkgen", "analyze", str(MODEL), "--angle", "30deg"], check=True,
                       capture_output=True)
        times.append(time.perf_counter() - t)
    return times


def pylinkage_fourbar():
    import pylinkage as pl

    o = pl.Ground(0.0, 0.0, name="O")
    c = pl.Ground(1.0, 0.0, name="C")
    a = pl.Crank(o, 0.3, angular_velocity=2 * math.pi / N, name="A")
    b = pl.RRRDyad(a, c, 1.0, 0.7, x=1.0143, y=0.6999, name="B")
    linkage = pl.Linkage((o, c, a, b), name="fourbar")
    linkage.set_input_velocity(a, 10.0, 0.0)
    return linkage


def pylinkage_warm() -> tuple[Timing, float]:
    t = time.perf_counter()
    pylinkage_fourbar().step_fast_with_kinematics(iterations=N)  # first call compiles
    first = time.perf_counter() - t
    return best_of(lambda: pylinkage_fourbar().step_fast_with_kinematics(iterations=N)), first


def cross_check() -> dict[str, float]:
    """Largest disagreement between pylinkage and linkgen over the benchmark's N angles, for the
    moving joints A and B: pylinkage's step k is at crank angle (k + 1)·2π/N, ω = 10 rad/s."""
    from linkgen import load, solve_motion

    pos, vel, acc = pylinkage_fourbar().step_fast_with_kinematics(iterations=N)
    mo = solve_motion(load(MODEL), (np.arange(N) + 1.0) * (2 * np.pi / N), 10.0, 0.0)
    out = {}
    for j, name in ((2, "A"), (3, "B")):
        for label, theirs, ours in zip(("position [m]", "velocity [m/s]", "acceleration [m/s²]"),
                                       (pos, vel, acc), mo.points[name]):
            peak = float(np.abs(ours).max())
            out[f"{name} {label}"] = float(np.abs(theirs[:, j] - ours).max()) / peak
    return out


def _spread(xs: list[float]) -> str:
    return f"median {statistics.median(xs):.3f} s, min {min(xs):.3f}, max {max(xs):.3f} ({len(xs)} runs)"


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--idle", type=float, default=10.0, help="seconds idle before each 'after idle' cold run")
    args = ap.parse_args()
    try:
        import pylinkage  # noqa: F401
    except ImportError:
        sys.exit("pylinkage not installed: pip install -e '.[bench]'")

    print(f"load average at the start: {os.getloadavg()[0]:.2f} (1 min) on {os.cpu_count()} cores")
    base, first = pylinkage_warm()
    fused, full = ours_warm(None)
    fused1, full1 = ours_warm(1)
    kinetostatics = forces_warm(None)
    seven, _ = ours_warm(None, SEVEN)
    seven_forces = forces_warm(None, SEVEN)
    nbytes = result_bytes()
    fresh, mapped = bandwidth_limit(nbytes)

    def line(label: str, t: Timing, what: str) -> str:
        return (f"{label:<16}{t.wall * 1e3:7.1f} ms wall {t.cpu * 1e3:7.1f} ms CPU  {what:<44} "
                f"x{base.wall / t.wall:5.2f} pylinkage (CPU x{base.cpu / t.cpu:5.2f})  "
                f"{t.wall / fresh.wall:5.2f}x the bandwidth limit")

    print(f"{'pylinkage warm:':<16}{base.wall * 1e3:7.1f} ms wall {base.cpu * 1e3:7.1f} ms CPU  "
          f"step_fast_with_kinematics, numba (first call with compilation {first:.2f} s) -- the baseline")
    print(f"{'bandwidth limit:':<16}{fresh.wall * 1e3:7.1f} ms wall {fresh.cpu * 1e3:7.1f} ms CPU  writing the "
          f"results' {nbytes / N:.0f} bytes per angle ({nbytes / 2**20:.0f} MiB) to fresh memory, 1 thread; "
          f"{mapped.wall * 1e3:.1f} ms to memory already mapped")
    print(line("linkgen warm:", fused, "solve_motion, all cores"))
    print(line("", fused1, "solve_motion, 1 thread"))
    print(line("", full, "solve().motion(), all cores (keeps transfer fns)"))
    print(line("", full1, "solve().motion(), 1 thread"))
    print(f"{'kinetostatics:':<16}{kinetostatics.wall * 1e3:7.1f} ms wall {kinetostatics.cpu * 1e3:7.1f} ms CPU  "
          f"forces, all cores: {N / kinetostatics.wall / 1e6:.2f} M angles/s")
    print(f"{'seven-link:':<16}{seven.wall * 1e3:7.1f} ms wall {seven.cpu * 1e3:7.1f} ms CPU  solve_motion, all cores: "
          f"{seven.wall / fused.wall:.2f}x the four-bar's time for {SEVEN_GROUPS}x its groups")
    print(f"{'':<16}{seven_forces.wall * 1e3:7.1f} ms wall {seven_forces.cpu * 1e3:7.1f} ms CPU  forces, all cores: "
          f"{N / seven_forces.wall / 1e6:.2f} M angles/s (target >= 1 M: "
          f"{'met' if N / seven_forces.wall >= 1e6 else 'NOT met'})")
    ratio = base.wall / fused.wall
    print(f"warm targets: <= 30 ms -> {'met' if fused.wall <= 0.030 else 'NOT met'}; >= 20x pylinkage -> "
          f"{'met' if ratio >= 20 else 'NOT met'} (x{ratio:.2f}); kinetostatics >= 2 M angles/s -> "
          f"{'met' if N / kinetostatics.wall >= 2e6 else 'NOT met'}")

    worst = max(cross_check().items(), key=lambda kv: kv[1])
    print(f"same results: largest disagreement with pylinkage, relative to the peak, {worst[1]:.1e} ({worst[0]})")

    ours, ours_mb, ours_cpu = cold(COLD, COLD_RUNS, 0.0)
    print(f"linkgen   cold, back to back: {_spread(ours)}; CPU median {statistics.median(ours_cpu):.3f} s; "
          f"peak memory {ours_mb:.0f} MB")
    theirs, theirs_mb, theirs_cpu = cold(PYLINKAGE_COLD, 3, 0.0)
    print(f"pylinkage cold, back to back: {_spread(theirs)} (numba's compilation included); CPU median "
          f"{statistics.median(theirs_cpu):.3f} s; peak memory {theirs_mb:.0f} MB")
    if args.idle > 0:
        ours_idle, _, _ = cold(COLD, 3, args.idle)
        print(f"linkgen   cold, after {args.idle:g} s idle: {_spread(ours_idle)}")
        theirs_idle, _, _ = cold(PYLINKAGE_COLD, 2, args.idle)
        print(f"pylinkage cold, after {args.idle:g} s idle: {_spread(theirs_idle)}")
    print(f"cold target: <= 0.25 s -> {'met' if statistics.median(ours) <= 0.25 else 'NOT met'} "
          f"(median back to back)")
    cli = cli_cold(COLD_RUNS)
    print(f"CLI cold start, `linkgen analyze models/fourbar.toml --angle 30deg`, whole process: {_spread(cli)}; "
          f"target <= 0.25 s -> {'met' if statistics.median(cli) <= 0.25 else 'NOT met'}")
    print(f"load average at the end: {os.getloadavg()[0]:.2f} (1 min)")


if __name__ == "__main__":
    main()
