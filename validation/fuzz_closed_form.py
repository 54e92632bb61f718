"""The property checks of tests/test_properties.py over a larger corpus, with counts.

    python validation/fuzz_closed_form.py [--n 1000] [--hostile 500] [--seed 0] [--out DIR]

Generates ``--n`` mechanisms with ``linkgen.families.planar.corpus.random_description`` and checks each by
the independent code of tests/independent_checks.py: geometry held, the sketch's link angles
reproduced (assembly mode), transfer functions against finite differences, force and moment
balance of every link and virtual work, and four equivalent rewrites of the description.
Then ``--hostile`` files (random bytes and mutations of valid descriptions) must load or
raise DescriptionError, and what loads must solve to finite numbers or raise a LinkgenError.

Prints the count of each outcome class per check (ok, over its tolerance, or the exception
type) and the worst figure per check with the mechanism that gave it; ``--out`` writes every
failing description there as TOML for replay with the CLI. Progress goes to stderr.
"""

from __future__ import annotations

import argparse
import collections
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

import independent_checks as ic  # noqa: E402
import linkgen  # noqa: E402
from linkgen.families.planar.corpus import random_description, to_toml  # noqa: E402
from linkgen.families.planar.kinetostatics import forces  # noqa: E402
from strategies import mutate, reorder_link_points, reorder_tables, reverse_slot, through_other  # noqa: E402
from test_properties import (  # noqa: E402
    BALANCE_TOL,
    EQUIV_TOL,
    FD_RATIO_TOL,
    FD_STEPS,
    GEOMETRY_TOL,
    _angles,
    _compare,
    _epsilon,
    _outcome,
)


def _equivalents(desc: dict, rng: np.random.Generator):
    """(name, other, flip, moved) for each rewrite that applies to ``desc``."""
    yield "tables", reorder_tables(desc, rng), None, None
    other = reorder_link_points(desc, rng)
    if other is not None:
        moved = next(n for n in desc["links"] if desc["links"][n]["points"] != other["links"][n]["points"])
        yield "points", other, None, moved
    prismatic = sorted(desc.get("prismatic", {}))
    if prismatic:
        name = prismatic[rng.integers(len(prismatic))]
        yield "reverse", reverse_slot(desc, name), name, None
        other = through_other(desc, name, rng)
        if other is not None:
            yield "through", other, None, None


def check_mechanism(desc: dict, seed: int):
    """Yield (check, figure or exception name, tolerance) for one mechanism."""
    phi = _angles(desc, 24)
    try:
        mech = linkgen.from_dict(desc)
        asm = linkgen.assemble(mech)
        kin = linkgen.solve(asm, phi)
    except Exception as exc:  # noqa: BLE001 - every failure is counted by type
        yield "load+solve", type(exc).__name__, None
        return
    g = ic.geometry_errors(desc, kin)
    yield "geometry", max(v for k, v in g.items() if k != "sketch_angle"), GEOMETRY_TOL
    yield "sketch_angles", g["sketch_angle"], GEOMETRY_TOL
    try:
        t = ic.transfer_errors(desc, lambda a: linkgen.solve(asm, a), phi[:13], FD_STEPS)
        yield "transfer_d1", t["d1"], FD_RATIO_TOL
        yield "transfer_d2", t["d2"], FD_RATIO_TOL
    except Exception as exc:  # noqa: BLE001
        yield "transfer_d1", type(exc).__name__, None
    omega, eps = desc["drive"]["omega"], _epsilon(desc, seed)
    try:
        b = ic.balance_errors(desc, kin, forces(asm, phi, omega, eps), omega, eps)
        for k, v in b.items():
            yield k, v, BALANCE_TOL
    except Exception as exc:  # noqa: BLE001
        yield "force_balance", type(exc).__name__, None
    for name, other, flip, moved in _equivalents(desc, np.random.default_rng(seed)):
        try:
            yield f"equivalent_{name}", max(_compare(desc, other, flip, moved).values()), EQUIV_TOL
        except Exception as exc:  # noqa: BLE001
            yield f"equivalent_{name}", type(exc).__name__, None


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--n", type=int, default=1000, help="generated mechanisms (default 1000)")
    ap.add_argument("--hostile", type=int, default=500, help="hostile files (default 500)")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--out", type=Path, help="folder for the failing descriptions (TOML)")
    args = ap.parse_args(argv)
    if args.out:
        args.out.mkdir(parents=True, exist_ok=True)
    counts: dict[str, collections.Counter] = collections.defaultdict(collections.Counter)
    worst: dict[str, tuple[float, int]] = {}
    kinds = collections.Counter()
    t0 = time.perf_counter()
    for i in range(args.n):
        desc = random_description(np.random.default_rng([args.seed, i]))
        for g in linkgen.decompose(linkgen.from_dict(desc)).groups:
            kinds[g.kind.value] += 1
        failed = False
        for check, fig, tol in check_mechanism(desc, i):
            if isinstance(fig, str):
                counts[check][f"exception {fig}"] += 1
                failed = True
                continue
            counts[check]["ok" if fig <= tol else "over tolerance"] += 1
            failed |= fig > tol
            if check not in worst or fig > worst[check][0]:
                worst[check] = (fig, i)
        if failed and args.out:
            (args.out / f"mech_{args.seed}_{i}.toml").write_text(to_toml(desc))
        if (i + 1) % 50 == 0:
            print(f"{i + 1}/{args.n} mechanisms, {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    hostile = collections.Counter()
    scratch = tempfile.TemporaryDirectory()
    tmp = Path(scratch.name) / "hostile.toml"
    for j in range(args.hostile):
        rng = np.random.default_rng([args.seed, 10**9 + j])
        if j % 4 == 0:
            data = bytes(rng.integers(0, 256, int(rng.integers(0, 400))).astype(np.uint8))
        else:
            data = mutate(random_description(rng, max_groups=2), rng)
        tmp.write_bytes(data)
        try:
            hostile[_outcome(tmp)] += 1
        except AssertionError as exc:
            hostile[f"assertion: {str(exc).splitlines()[0][:60]}"] += 1
        except BaseException as exc:  # noqa: BLE001 - RecursionError, MemoryError... all counted
            if isinstance(exc, KeyboardInterrupt):
                raise
            hostile[f"crash {type(exc).__name__}"] += 1
            if args.out:
                (args.out / f"hostile_{args.seed}_{j}.toml").write_bytes(data)
        if (j + 1) % 100 == 0:
            print(f"{j + 1}/{args.hostile} hostile files", file=sys.stderr)
    scratch.cleanup()
    print(f"{args.n} mechanisms (groups: {dict(sorted(kinds.items()))}), "
          f"{args.hostile} hostile files, {time.perf_counter() - t0:.0f} s")
    print(f"{'check':24} {'worst':>10}  {'at':>5}  outcomes")
    for check in counts:
        fig, at = worst.get(check, (float('nan'), -1))
        outcomes = ", ".join(f"{k}: {v}" for k, v in sorted(counts[check].items()))
        print(f"{check:24} {fig:10.3g}  {at:5d}  {outcomes}")
    print("hostile files: " + ", ".join(f"{k}: {v}" for k, v in sorted(hostile.items())))
    bad = any(k != "ok" for c in counts.values() for k in c) or any(
        k not in ("ok", "rejected") and not k.startswith("refused") for k in hostile)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
