"""Fuzz every model family through the library and every command, and count what goes wrong.

    python validation/fuzz_commands.py --count 3000 --seed 1 --jobs 1 --out /tmp/fuzz-repro
    python validation/fuzz_commands.py --count 200 --families cam,spatial --commands build,profile --cli-every 2 \
        --out /tmp/fuzz-repro --max-seconds 600

Mutant k of seed S (validation/fuzz_mutants.py) comes from a bundled model of family
k mod 7 (planar, gears, cam_linkage, cam, machine, spatial, special): 15 % of its text mutated
(a number replaced, a span cut; comments kept), 40 % one or two numbers scaled (by 0, 1e-300 …
1e300, negated: values the loader mostly accepts, which reach the solvers), 45 % 1–3 mutations
of its tables (numbers: 0, negative, tiny, huge, 1e308, nan/inf, 10**400, strings with units;
types: a list or table for a scalar and back; names: control characters, ``--``, unicode,
duplicates; keys removed or added); "special" stands for /dev/zero, a FIFO, a folder, an empty
or a binary file. Each mutant runs

- through the library in-process (validation/fuzz_library.py): load → structure → kinematics →
  forces → summary, and for every third mutant of a family also the MJCF compiled by MuJoCo and
  the machine run and flywheel; past ``--timeout`` s of its own CPU, or 10 × that on the clock
  (5 s on the clock for a special file: reading one has no reason to take long), it is a hang;
- and every ``--cli-every``-th mutant through one command as a subprocess in a sandbox
  (validation/fuzz_cli.py): a command of its family (one in ten drawn from all), with a
  symlink or a 0600 file planted at its output's name, or SIGTERM sent mid-run, or neither; cwd,
  HOME and TMPDIR are empty folders of the sandbox (HOME with Matplotlib's caches filled) and
  the whole sandbox is compared before and after. Outputs are scanned by
  validation/fuzz_outputs.py.

Classes: ok, clean error (a LinkgenError; for a command a message and status 1-3, no
traceback), interrupted (SIGTERM, nothing left behind), and the failures: crash (any other
exception, a traceback, death by a signal, an MJCF MuJoCo refuses), hang, non-finite (NaN/inf in
a result, stdout or an output file), unsafe write (a file changed outside the requested outputs,
a symlink's target written, a mode changed, a symlinked description replaced). Progress goes to
stderr; stdout gets a table by class and family for each path, one by command, and the distinct
failures (a signature without numbers and quoted names, its count, its first reproducer).
Each failure's mutant is saved under ``--out`` (required, never the cwd) as
``<class>/<family>_<k>_<command or library>.toml`` with a ``.txt`` beside it (seed, mutations,
the command line, stderr), at most ``--keep`` per signature. Exit status 1 if any failure.

Reproducible: the same --seed gives the same mutants, commands and plants whatever --jobs and
--count (the SIGTERM's moment is drawn from the seed too; what it interrupts depends on the
machine's speed). --max-seconds stops drawing mutants after a time budget. Memory is capped
(RLIMIT_AS, ``MEMORY_LIMIT``) in the workers and the commands they run; BLAS runs one thread.
"""

from __future__ import annotations

import os

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # one core per job: the machine is shared
os.environ.setdefault("OMP_NUM_THREADS", "1")

import argparse  # noqa: E402
import collections  # noqa: E402
import multiprocessing  # noqa: E402
import re  # noqa: E402
import resource  # noqa: E402
import shutil  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
from dataclasses import dataclass  # noqa: E402
import tomllib  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import fuzz_cli  # noqa: E402
import fuzz_library  # noqa: E402
import fuzz_mutants  # noqa: E402

# Address space of a worker and of every command it runs [bytes]: MuJoCo, SciPy and Matplotlib
# take about 1.5 GB of it; /dev/zero read whole must end in a MemoryError, not in the machine's swap.
MEMORY_LIMIT = 3 << 30
# Time limit of a run on a special file (/dev/zero, a FIFO) [s]: the bundled models load in
# milliseconds, so a load still running after this is waiting on the file, not computing.
SPECIAL_TIMEOUT = 5.0
FAILURES = ("crash", "hang", "non-finite", "unsafe write")
CLASSES = ("ok", "clean error", "interrupted") + FAILURES


def _limit_memory() -> None:
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_LIMIT, MEMORY_LIMIT))


def _name_of(data: bytes) -> str:
    """The mechanism's name as the CLI will use it for report figures (``model`` when absent)."""
    try:
        name = tomllib.loads(data.decode())["mechanism"]["name"]
        return name if isinstance(name, str) else "model"
    except Exception:  # noqa: BLE001 — an unreadable mutant has no name; the plant just misses
        return "model"


def run_one(seed: int, k: int, families: tuple[str, ...], timeout: float, cli_every: int,
            commands: tuple[str, ...] | None = None) -> dict:
    """Mutant ``k``: its library result and, for every ``cli_every``-th, one command's."""
    m = fuzz_mutants.mutant(seed, k, families)
    rng = np.random.default_rng([seed, k, 1])
    deep = (k // len(families)) % 3 == 0
    if m.family == "special":  # reading a file has no reason to take long: a FIFO's wait is a hang at once
        timeout = min(timeout, SPECIAL_TIMEOUT)
    out = {"k": k, "family": m.family, "origin": m.origin, "what": m.what, "data": m.data, "special": m.special}
    with tempfile.TemporaryDirectory(prefix="fuzz-") as tmp:
        box = Path(tmp)
        (box / "in").mkdir()
        (box / "lib").mkdir()
        path = fuzz_mutants.materialise(m, box / "in")
        here = os.getcwd()
        os.chdir(box / "lib")  # the library must write nothing; whatever it does lands here
        try:
            cls, detail = fuzz_library.run_library(path, timeout, deep,
                                                   wall=timeout if m.family == "special" else None)
        finally:
            os.chdir(here)
        stray = sorted(p.name for p in (box / "lib").iterdir())
        if stray and cls in ("ok", "clean error"):
            cls, detail = "unsafe write", "the library wrote into the cwd: " + ", ".join(stray[:4])
        out["lib"] = (cls, detail)
        if cli_every and k % cli_every == 0:
            if m.special == "fifo" and not path.exists():
                path = fuzz_mutants.materialise(m, box / "in")
            cmd, plant = fuzz_cli.choose(m.family, rng, commands)
            samples = int(rng.choice([37, 20000])) if plant == "sigterm" else 37
            r = fuzz_cli.run_cli(cmd, plant, path, box, timeout, _name_of(m.data), samples, rng,
                                 special=m.special is not None or m.family == "special")
            out["cli"] = (r.command, r.plant, r.cls, r.detail, r.returncode, r.seconds, r.argv, r.stderr[-1500:])
    return out


def signature(where: str, cls: str, detail: str, command: str = "") -> str:
    """A failure's kind without its numbers and names: what groups the same bug."""
    d = re.sub(r"'[^']*'|\"[^\"]*\"", "'…'", detail)
    d = re.sub(r"[-+]?\d[\d.e+-]*", "#", d)
    return f"{where} {command} {cls}: {d[:110]}".replace("  ", " ")


def save(out: Path, r: dict, where: str, cls: str, detail: str, kept: collections.Counter, sig: str,
         keep: int, seed: int) -> str | None:
    kept[sig] += 1
    if kept[sig] > keep:
        return None
    folder = out / cls.replace(" ", "_")
    folder.mkdir(parents=True, exist_ok=True)
    stem = f"{r['family']}_{r['k']}_{r['cli'][0] if where == 'cli' else 'library'}"
    model = folder / f"{stem}.toml"
    model.write_bytes(r["data"] if r["special"] is None else f"# special file: {r['special']}\n".encode())
    lines = [f"seed {seed}, mutant {r['k']} of {r['origin']} ({r['family']}): " + "; ".join(r["what"]),
             f"{where}: {cls}: {detail}"]
    if where == "cli":
        lines += [f"command: linkgen {' '.join(r['cli'][6])}  (plant: {r['cli'][1]}, status {r['cli'][4]})",
                  "stderr:", r["cli"][7]]
    (folder / f"{stem}.txt").write_text("\n".join(lines) + "\n", encoding="utf-8", errors="replace")
    return str(model)


def table(title: str, counts: dict[str, collections.Counter]) -> str:
    fams = [f for f in fuzz_mutants.FAMILIES if f in counts] or sorted(counts)
    head = f"{title:<14}" + "".join(f"{c:>13}" for c in CLASSES) + f"{'total':>8}"
    rows = [head]
    for f in fams + ["all"]:
        c = counts[f] if f != "all" else sum(counts.values(), collections.Counter())
        rows.append(f"{f:<14}" + "".join(f"{c[k]:>13}" for k in CLASSES) + f"{sum(c.values()):>8}")
    return "\n".join(rows)


@dataclass
class Report:
    """A campaign's counts: by family and class for the library and the commands, by command
    and class, and the distinct failures: signature → [count, first reproducer, detail]."""

    seed: int
    count: int
    seconds: float
    library: dict[str, collections.Counter]
    commands: dict[str, collections.Counter]
    by_command: dict[str, collections.Counter]
    found: dict[str, list]

    def failures(self, where: str = "") -> int:
        return sum(n for sig, (n, _, _) in self.found.items() if sig.startswith(where))


def parse(argv: list[str] | None = None) -> argparse.Namespace:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--count", type=int, default=1000, help="mutants (default 1000)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jobs", type=int, default=1, help="worker processes (default 1; the machine is shared)")
    ap.add_argument("--out", type=Path, required=True, help="folder for the failures' reproducers")
    ap.add_argument("--families", default=",".join(fuzz_mutants.FAMILIES),
                    help="comma-separated subset of " + ", ".join(fuzz_mutants.FAMILIES))
    ap.add_argument("--commands", default="", help="comma-separated subset of the commands (default all)")
    ap.add_argument("--cli-every", type=int, default=6, help="run a command on every N-th mutant (0: none)")
    ap.add_argument("--timeout", type=float, default=30.0, help="seconds before a run counts as a hang")
    ap.add_argument("--max-seconds", type=float, default=0.0,
                    help="stop drawing new mutants after this many seconds (0: no limit); the table counts those run")
    ap.add_argument("--keep", type=int, default=3, help="reproducers kept per failure signature")
    args = ap.parse_args(argv)
    args.families = tuple(f for f in args.families.split(",") if f)
    unknown = set(args.families) - set(fuzz_mutants.FAMILIES)
    if unknown:
        ap.error(f"unknown families {sorted(unknown)}; choose from {', '.join(fuzz_mutants.FAMILIES)}")
    args.commands = tuple(c for c in args.commands.split(",") if c) or None
    if args.commands and set(args.commands) - set(fuzz_cli.COMMANDS):
        ap.error(f"unknown commands {sorted(set(args.commands) - set(fuzz_cli.COMMANDS))}")
    return args


def campaign(args: argparse.Namespace) -> Report:
    """Run the mutants of ``args`` (see ``parse``); progress on stderr."""
    args.out.mkdir(parents=True, exist_ok=True)
    rep = Report(args.seed, args.count, 0.0, collections.defaultdict(collections.Counter),
                 collections.defaultdict(collections.Counter), collections.defaultdict(collections.Counter), {})
    found, kept = rep.found, collections.Counter()
    t0 = time.perf_counter()
    scratch = tempfile.TemporaryDirectory(prefix="fuzz-home-")
    fuzz_cli.make_home(Path(scratch.name) / "home")  # inherited by the forked workers
    ctx = multiprocessing.get_context("fork")
    backstop = args.timeout * 3 + 60  # a worker stuck where SIGALRM cannot reach it
    task = (args.families, args.timeout, args.cli_every, args.commands)
    pool = ctx.Pool(args.jobs, initializer=_limit_memory, maxtasksperchild=100)
    pending: collections.deque = collections.deque()
    k_next, done, count = 0, 0, args.count

    def record(r: dict) -> None:
        cls, detail = r["lib"]
        rep.library[r["family"]][cls] += 1
        if cls in FAILURES:
            sig = signature("library", cls, detail)
            path = save(args.out, r, "library", cls, detail, kept, sig, args.keep, args.seed)
            found.setdefault(sig, [0, path, detail])[0] += 1
        if "cli" in r:
            command, plant, ccls = r["cli"][:3]
            rep.commands[r["family"]][ccls] += 1
            rep.by_command[command][ccls] += 1
            if ccls in FAILURES:
                sig = signature("cli", ccls, r["cli"][3], command)
                path = save(args.out, r, "cli", ccls, r["cli"][3], kept, sig, args.keep, args.seed)
                found.setdefault(sig, [0, path, r["cli"][3]])[0] += 1

    while done < k_next or k_next < count:
        if args.max_seconds and time.perf_counter() - t0 > args.max_seconds and k_next < count:
            print(f"fuzz: --max-seconds reached: {k_next} mutants drawn, finishing those", file=sys.stderr)
            count = k_next
            continue
        while k_next < count and len(pending) < 2 * args.jobs:
            pending.append((k_next, pool.apply_async(run_one, (args.seed, k_next, *task))))
            k_next += 1
        k, job = pending.popleft()
        try:
            r = job.get(timeout=backstop)
        except multiprocessing.TimeoutError:
            pool.terminate()
            m = fuzz_mutants.mutant(args.seed, k, args.families)
            r = {"k": k, "family": m.family, "origin": m.origin, "what": m.what, "data": m.data,
                 "special": m.special, "lib": ("hang", f"worker stuck past {backstop:g} s")}
            requeue = [kk for kk, _ in pending]
            pending.clear()
            pool = ctx.Pool(args.jobs, initializer=_limit_memory, maxtasksperchild=100)
            for kk in requeue:
                pending.append((kk, pool.apply_async(run_one, (args.seed, kk, *task))))
        record(r)
        done += 1
        if done % 50 == 0 or done == count:
            print(f"fuzz: {done}/{count} mutants, {rep.failures()} failures, {time.perf_counter() - t0:.0f} s",
                  file=sys.stderr, flush=True)
    pool.close()
    pool.join()
    scratch.cleanup()
    rep.count, rep.seconds = done, time.perf_counter() - t0
    return rep


def main(argv: list[str] | None = None) -> int:
    args = parse(argv)
    rep = campaign(args)
    print(f"seed {rep.seed}: {rep.count} mutants of {', '.join(args.families)}; a command on every "
          f"{args.cli_every}-th; {rep.seconds:.0f} s")
    print(table("library", rep.library))
    if rep.commands:
        print()
        print(table("commands", rep.commands))
        print()
        print(table("by command", rep.by_command))
    print(f"\n{len(rep.found)} distinct failures (count, signature, first reproducer):")
    for sig, (n, path, detail) in sorted(rep.found.items(), key=lambda x: -x[1][0]):
        print(f"{n:5d}  {sig}\n       {path}")
    return 1 if rep.found else 0


if __name__ == "__main__":
    sys.exit(main())
