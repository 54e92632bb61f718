"""The referee's diagnosis on a seeded corpus: the hit rate per kind of mistake and the
false-alarm rate on correct results (docs/referee.md quotes them).

    PYTHONPATH=. python validation/referee_rates.py [--random N] [--seed S] [--samples 72]

Mechanisms: the bundled linkages named in MODELS, the six-bar of tests/data and N random planar
linkages (``families.planar.corpus``). Each is refereed at its drive's ω with ε = 0 and with
ε = ω²/4 (the constant-speed mistake needs ε ≠ 0; finite differences are seeded at ε = 0).
Mistakes come from validation/referee_seeds.py (made from the closed form); a seed that changes
its column by less than the tolerance is not a mistake and is not counted. A hit is the
diagnosis kind expected; a correct table (every column, printed to 10 digits) is a false alarm
if any column is diagnosed or found to differ."""

from __future__ import annotations

import argparse
import sys
import time
from collections import Counter
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

import referee_seeds  # noqa: E402

import linkgen  # noqa: E402
from linkgen.families.planar.assembly import assemble  # noqa: E402
from linkgen.pipeline.registry import from_dict, stage  # noqa: E402

MODELS = ("fourbar", "slider_crank_offset", "ga31", "ga32", "g123", "press", "seven_link", "planetary_lever_rrr")


def corpus(random: int, seed: int):
    root = HERE.parent
    for name in MODELS:
        yield name, assemble(linkgen.load(root / "models" / f"{name}.toml"))
    yield "referee_sixbar", assemble(linkgen.load(root / "tests" / "data" / "referee_sixbar.toml"))
    from linkgen.families.planar.corpus import random_description

    rng = np.random.default_rng(seed)
    for i in range(random):
        yield f"random_{i}", assemble(from_dict(random_description(rng, max_groups=3, size=1.0, omega=10.0)))


def run(random: int, seed: int, samples: int, per_kind: int) -> dict:
    hits, total, misses = Counter(), Counter(), []
    alarms = checked = 0
    rng = np.random.default_rng(seed)
    for name, asm in corpus(random, seed):
        phi = stage(asm, "angles")(asm, samples)
        omega = float(asm.mechanism.drive.omega)
        for epsilon in (0.0, omega**2 / 4):
            checked += 1
            v = linkgen.referee(asm, referee_seeds.correct(asm, phi, omega, epsilon), omega=omega, epsilon=epsilon)
            bad = [c for c in v.columns if c.diagnosis is not None or not c.routes["closed_form"].agrees]
            if bad:
                alarms += 1
                misses.append(f"FALSE ALARM {name} ε={epsilon:g}: {bad[0].header} {bad[0].routes['closed_form'].error:.2e}")
            for table, seeds in referee_seeds.packed(referee_seeds.seeded(asm, phi, omega, epsilon, rng, per_kind)):
                try:
                    v = linkgen.referee(asm, table, omega=omega, epsilon=epsilon)
                except linkgen.LinkgenError as exc:
                    for s in seeds:
                        total[s.kind] += 1
                        misses.append(f"{s.kind} {name} {s.key}: error {exc}")
                    continue
                by_key = {c.key: c for c in v.columns}
                for s in seeds:
                    c = by_key[s.key]
                    if c.routes["closed_form"].agrees:
                        continue  # the seed changed nothing measurable
                    total[s.kind] += 1
                    got = c.diagnosis.kind if c.diagnosis else "none"
                    if got == s.expected:
                        hits[s.kind] += 1
                    else:
                        misses.append(f"{s.kind} {name} ε={epsilon:g} {s.key}: got {got}: "
                                      f"{c.diagnosis.text if c.diagnosis else ''}")
    return {"hits": hits, "total": total, "alarms": alarms, "checked": checked, "misses": misses}


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--random", type=int, default=12, help="random planar linkages besides the bundled ones")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--samples", type=int, default=72)
    p.add_argument("--per-kind", type=int, default=3, help="columns seeded per kind of mistake and mechanism")
    p.add_argument("--verbose", action="store_true", help="list every miss")
    a = p.parse_args()
    t0 = time.perf_counter()
    r = run(a.random, a.seed, a.samples, a.per_kind)
    print(f"{'kind':<16} {'hits':>6} {'seeded':>7} {'rate':>7}")
    for kind in referee_seeds.EXPECTED:
        n = r["total"][kind]
        print(f"{kind:<16} {r['hits'][kind]:>6} {n:>7} {r['hits'][kind] / n if n else float('nan'):>7.1%}")
    all_hits, all_n = sum(r["hits"].values()), sum(r["total"].values())
    print(f"{'all':<16} {all_hits:>6} {all_n:>7} {all_hits / max(all_n, 1):>7.1%}")
    print(f"false alarms on correct tables: {r['alarms']} of {r['checked']}")
    print(f"({time.perf_counter() - t0:.1f} s)")
    for m in r["misses"][: None if a.verbose else 30]:
        print("  " + m)


if __name__ == "__main__":
    main()
