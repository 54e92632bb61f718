"""Time the structure analysis (``linkgen.decompose``) on chains of class-II groups.

Each group k is an RRR dyad: a coupler from a point of the previous rocker (the crank for the
first) to a rocker pivoted on ground. Prints, per chain length, the time to build the
description (validation included) and the time of ``decompose`` alone, best of three.

    .venv/bin/python validation/bench_structure.py [N ...]     (default 100 1000 5000)
"""

from __future__ import annotations

import sys
import time

from linkgen import assemble, decompose
from linkgen.families.planar.description import Drive, Link, Mechanism


def chain(groups: int) -> Mechanism:
    points = {"O": (0.0, 0.0), "A": (0.0, 1.0)}
    links = [Link("crank", ("O", "A"))]
    ground = ["O"]
    prev = "A"
    for k in range(groups):
        g, b, m = f"G{k}", f"B{k}", f"M{k}"
        points |= {g: (k + 1.0, 0.0), b: (k + 1.0, 1.0), m: (k + 1.0, 0.5)}
        ground.append(g)
        links += [Link(f"c{k}", (prev, b)), Link(f"r{k}", (g, b, m))]
        prev = m
    return Mechanism("chain", points, (Link("ground", tuple(ground)), *links), Drive("O", 1.0))


def best_of(fn, repeat: int = 3) -> tuple[float, object]:
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return min(times), out


def main(sizes: list[int]) -> None:
    print(f"{'groups':>7} {'build+validate [s]':>19} {'decompose [s]':>14} {'assemble [s]':>13}")
    for n in sizes:
        t_build, mech = best_of(lambda: chain(n))
        t_an, s = best_of(lambda: decompose(mech))
        assert len(s.groups) == n, (len(s.groups), n)
        t_asm, _ = best_of(lambda: assemble(mech), repeat=1)
        print(f"{n:>7} {t_build:>19.4f} {t_an:>14.4f} {t_asm:>13.3f}")


if __name__ == "__main__":
    main([int(a) for a in sys.argv[1:]] or [100, 1000, 5000])
