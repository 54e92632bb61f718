"""The command path of validation/fuzz_commands.py: one ``linkgen`` command on one mutant, as a
subprocess in a sandbox, classified.

The sandbox is a fresh folder holding ``cwd/`` (the empty working directory, where outputs are
named), ``home/`` (HOME), ``tmp/`` (TMPDIR), ``in/model.toml`` (the description) and
``victim/`` (targets of planted symlinks). Before the run a plant may be set at the output's
name: a symlink into ``victim/`` (its target must keep its content), a file of mode 0600 (its
mode must be kept), or for ``assemble --write`` a symlinked 0600 description (the link must stay
a link, the mode kept); or SIGTERM is sent mid-run (no file may be left but the outputs). The
whole tree is compared before and after: a change anywhere but the requested outputs is an
unsafe write.

Classes: ok, clean error (exit status non-zero, a message, no traceback), interrupted (SIGTERM,
nothing left behind), crash (a traceback, or death by a signal we did not send), hang (past the
time limit), non-finite (nan/inf in stdout or in an output's numbers), unsafe write.
"""

from __future__ import annotations

import hashlib
import os
import re
import shutil
import signal
import subprocess
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from fuzz_outputs import output_non_finite, text_non_finite

REPO = Path(__file__).resolve().parent.parent
VICTIM = b"VICTIM: a file the user did not name as an output\n"
OLD = b"an existing output file of mode 0600\n"
# Exit statuses of a clean refusal: 2 error, 3 singular samples written marked, 1 validate's
# "the two sides disagree" (linkgen.cli.main's docstring).
CLEAN = (1, 2, 3)

M = "{model}"
# name: (argv after "linkgen", outputs relative to cwd (a trailing "/" marks a folder), the
# output a plant goes to: a file name, or "report:<pattern>" for a file inside a report folder)
COMMANDS: dict[str, tuple[list[str], list[str], str | None]] = {
    "structure": (["structure", M], [], None),
    "assemble_write": (["assemble", M, "--write"], [], "model"),
    "analyze": (["analyze", M], [], None),
    "analyze_json": (["analyze", M, "--json", "--transfer"], [], None),
    "analyze_csv": (["analyze", M, "-o", "out.csv", "--samples", "{samples}"], ["out.csv"], "out.csv"),
    "analyze_summary": (["analyze", M, "--summary"], [], None),
    "analyze_summary_json": (["analyze", M, "--summary", "--json"], [], None),
    "forces": (["forces", M], [], None),
    "forces_json": (["forces", M, "--json"], [], None),
    "forces_csv": (["forces", M, "-o", "out.csv", "--samples", "{samples}"], ["out.csv"], "out.csv"),
    "draw_svg": (["draw", M, "-o", "out.svg"], ["out.svg"], "out.svg"),
    "draw_pdf": (["draw", M, "-o", "out.pdf", "--angles", "0:360:90"], ["out.pdf"], "out.pdf"),
    "draw_png": (["draw", M, "-o", "out.png"], ["out.png"], "out.png"),
    "draw_vectors": (["draw", M, "--vectors", "forces", "-o", "out.png"], ["out.png"], "out.png"),
    "draw_plan": (["draw", M, "--plan", "acceleration", "-o", "out.png"], ["out.png"], "out.png"),
    "page": (["page", M, "-o", "out.html", "--frames", "12"], ["out.html"], "out.html"),
    "build": (["build", M, "-o", "out.xml"], ["out.xml"], "out.xml"),
    "simulate_npz": (["simulate", M, "--samples", "60", "-o", "out.npz"], ["out.npz"], "out.npz"),
    "simulate_csv": (["simulate", M, "--samples", "60", "-o", "out.csv"], ["out.csv"], "out.csv"),
    "profile": (["profile", M, "-o", "out.csv", "--points", "{samples}"], ["out.csv"], "out.csv"),
    "dynamics": (["dynamics", M, "--samples", "300"], [], None),
    "dynamics_csv": (["dynamics", M, "--samples", "300", "-o", "out.csv"], ["out.csv"], "out.csv"),
    "dynamics_report": (["dynamics", M, "--samples", "300", "--json", "-o", "rep"], ["rep/"],
                        "report:{name}_machine.png"),
    "flywheel": (["flywheel", M, "--delta", "0.02", "--json"], [], None),
    "flywheel_report": (["flywheel", M, "--delta", "0.05", "-o", "rep"], ["rep/"], "report:{name}_flywheel.png"),
    "validate": (["validate", M, "--no-practical", "--max-steps", "20000"], [], None),
    "validate_report": (["validate", M, "--no-practical", "--max-steps", "20000", "--json", "-o", "rep"],
                        ["rep/"], "report:README.md"),
    "check_settings": (["check-settings", M, "--no-search"], [], None),
    "check_settings_json": (["check-settings", M, "--no-search", "-o", "out.json"], ["out.json"], "out.json"),
    "build_robot": (["build", M, "--robot", "--prefix", "p_", "-o", "out.xml"], ["out.xml"], "out.xml"),
    "build_coupling": (["build", M, "--loops", "coupling", "-o", "out.xml"], ["out.xml"], "out.xml"),
    "render": (["render", M, "-o", "out.png", "--width", "160", "--height", "120"], ["out.png"], "out.png"),
    "animate": (["animate", M, "-o", "out.gif", "--frames", "3"], ["out.gif"], "out.gif"),
    "sweep": (["sweep", M, "--vary", "drive.omega=5:10:2", "-o", "study"], ["study/"], None),
    "optimize": (["optimize", M, "--vary", "drive.omega=5:10", "--minimize", "peak_balancing_torque", "-o", "best.toml",
                  "--no-validate"], ["best.toml"], "best.toml"),
    "referee": (["referee", M, "answers.csv"], [], None),
    "suite_export": (["suite", "export", "suite", "--count", "1", "--no-mujoco"], ["suite/"], None),
}
_LINKAGE = ["structure", "assemble_write", "analyze", "analyze_json", "analyze_csv", "analyze_summary",
            "analyze_summary_json", "forces", "forces_json", "forces_csv", "draw_svg", "draw_pdf", "draw_png", "draw_vectors", "draw_plan", "page", "build",
            "simulate_npz", "simulate_csv", "validate", "validate_report", "render", "animate", "check_settings",
            "check_settings_json", "build_robot", "build_coupling", "sweep", "optimize"]
FOR_FAMILY = {
    "planar": _LINKAGE, "gears": _LINKAGE, "cam_linkage": _LINKAGE,
    "machine": _LINKAGE + ["dynamics", "dynamics_csv", "dynamics_report", "flywheel", "flywheel_report"] * 2,
    "cam": ["structure", "analyze", "analyze_json", "analyze_csv", "analyze_summary", "analyze_summary_json", "draw_svg",
            "draw_png", "draw_vectors", "draw_plan", "page", "build", "profile", "profile", "validate", "validate_report", "render", "animate"],
    "spatial": ["structure", "analyze", "analyze_json", "analyze_csv", "analyze_summary", "analyze_summary_json",
                "forces", "forces_json", "forces_csv", "draw_svg", "draw_pdf", "draw_vectors", "draw_plan", "page", "build",
                "build_robot", "validate",
                "validate_report", "render", "animate"],
    "special": list(COMMANDS),
}
PLANTS = ("none", "none", "symlink", "mode", "sigterm")


@dataclass
class CliResult:
    command: str
    argv: list[str]
    plant: str
    cls: str
    detail: str
    returncode: int | None
    seconds: float
    stderr: str = field(repr=False, default="")


def choose(family: str, rng: np.random.Generator, commands: tuple[str, ...] | None = None) -> tuple[str, str]:
    """A command for ``family`` (one in ten from any family's list: a refusal must be clean too),
    among ``commands`` if given, and a plant."""
    pool = list(COMMANDS) if rng.random() < 0.1 else FOR_FAMILY[family]
    if commands:
        pool = [c for c in pool if c in commands] or list(commands)
    cmd = pool[int(rng.integers(0, len(pool)))]
    plant = PLANTS[int(rng.integers(0, len(PLANTS)))]
    if COMMANDS[cmd][2] is None and plant in ("symlink", "mode"):
        plant = "none"
    return cmd, plant


# ---------------------------------------------------------------- the tree before and after
def snapshot(root: Path) -> dict[str, tuple]:
    """Every path under ``root`` → (kind, mode, size, content hash or link target)."""
    out = {}
    for dirpath, dirs, files in os.walk(root):
        for name in dirs + files:
            p = Path(dirpath) / name
            st = p.lstat()
            rel = str(p.relative_to(root))
            if p.is_symlink():
                out[rel] = ("link", 0, 0, os.readlink(p))
            elif p.is_dir():
                out[rel] = ("dir", st.st_mode & 0o7777, 0, "")
            elif p.is_file():
                h = hashlib.sha1(p.read_bytes()[:1 << 20]).hexdigest() if st.st_size else ""
                out[rel] = ("file", st.st_mode & 0o7777, st.st_size, h)
            else:
                out[rel] = ("other", st.st_mode & 0o7777, 0, "")
    return out


def _changed(before: dict, after: dict) -> list[str]:
    keys = set(before) | set(after)
    return sorted(k for k in keys if before.get(k) != after.get(k) and
                  not (before.get(k, ("dir",))[0] == "dir" and after.get(k, ("dir",))[0] == "dir"
                       and k in before and k in after))


# ---------------------------------------------------------------- one run
def _traceback(stderr: str) -> str | None:
    """"ExcType at file:line" for a Python traceback in ``stderr``, or None."""
    if "Traceback (most recent call last)" not in stderr:
        return None
    frames = re.findall(r'File "([^"]+)", line (\d+)', stderr)
    where = next((f"{Path(f).name}:{n}" for f, n in reversed(frames) if "/linkgen/" in f), "?")
    last = [ln for ln in stderr.strip().splitlines() if ln and not ln.startswith(" ")][-1]
    return f"{last[:160]} at {where}"


def _plant(kind: str, target: str | None, box: Path, model: Path) -> tuple[Path | None, Path | None]:
    """Set the plant; returns (planted path, victim) to check afterwards."""
    if kind not in ("symlink", "mode") or target is None:
        return None, None
    if target == "model":
        if kind == "symlink":
            real = box / "victim" / "real.toml"
            real.write_bytes(model.read_bytes())
            model.unlink()
            model.symlink_to(real)
        os.chmod(model, 0o600)
        return model, None
    path = box / "cwd" / target.removeprefix("report:")
    path.parent.mkdir(parents=True, exist_ok=True)
    if len(path.name.encode()) > NAME_MAX:  # a figure named after a 250-character mechanism: nothing can sit there
        return None, None
    if kind == "symlink":
        victim = box / "victim" / "target.txt"
        victim.write_bytes(VICTIM)
        path.symlink_to(victim)
        return path, victim
    path.write_bytes(OLD)
    os.chmod(path, 0o600)
    return path, None


# The longest file name the file system takes (bytes; Linux's NAME_MAX).
NAME_MAX = os.pathconf("/tmp", "PC_NAME_MAX")


# A HOME whose caches Matplotlib and fontconfig have already filled (make_home): a fresh one
# would see them written on every run, third-party caches rather than linkgen's outputs.
HOME_TEMPLATE: Path | None = None


def make_home(folder: Path) -> Path:
    """Fill ``folder`` as a HOME with the caches a plotting run writes; set it as the template."""
    global HOME_TEMPLATE
    folder.mkdir(parents=True, exist_ok=True)
    env = env_for(folder.parent)
    env["HOME"] = str(folder)
    subprocess.run([sys.executable, "-c", "import matplotlib; matplotlib.use('Agg'); import matplotlib.pyplot as p; "
                    "p.figure(); p.text(0, 0, 'x'); p.savefig('/dev/null', format='png')"],
                   env=env, check=True, capture_output=True, timeout=120)
    HOME_TEMPLATE = folder
    return folder


def env_for(box: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("XDG_", "MPLCONFIGDIR", "PYTHON"))}
    env.update(HOME=str(box / "home"), TMPDIR=str(box / "tmp"), PYTHONPATH=str(REPO), OPENBLAS_NUM_THREADS="1",
               OMP_NUM_THREADS="1", PYTHONDONTWRITEBYTECODE="1")
    return env


def _cpu_seconds(pid: int) -> str:
    """The CPU time a running process has used, as text: a hang that computes and one that
    waits (a FIFO) look alike on the wall clock of a loaded machine."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
        return f"{(int(fields[11]) + int(fields[12])) / os.sysconf('SC_CLK_TCK'):.1f} s"
    except (OSError, IndexError, ValueError):
        return "? s"


def classify(rc: int, stdout: str, stderr: str, sent: bool, unsafe: list[str], non_finite: str | None
             ) -> tuple[str, str]:
    """(class, detail) of a finished run: status ``rc`` (negative: the signal that ended it),
    ``sent`` whether we sent SIGTERM, ``unsafe`` the writes found, ``non_finite`` the first
    NaN/inf found in its outputs."""
    tb = _traceback(stderr)
    if tb:
        return "crash", tb
    if unsafe:
        return "unsafe write", "; ".join(unsafe)
    if rc < 0:
        return ("interrupted", "SIGTERM, nothing left behind") if sent else ("crash", f"killed by signal {-rc}")
    if rc in (0, 3):
        if non_finite:
            return "non-finite", non_finite[:200]
        return ("ok", "") if rc == 0 else ("clean error", "singular samples marked (status 3)")
    if sent and rc == 143:
        return "interrupted", "SIGTERM handled, nothing left behind"
    if rc in CLEAN:  # the message on stderr, or validate's failing result on stdout
        text = stderr.strip() or stdout.strip()
        return ("clean error", text.splitlines()[-1][:200]) if text else ("crash", f"status {rc} with no message")
    return "crash", f"status {rc}: {stderr.strip()[-200:]}"


# A run that has printed nothing (stdout or stderr, where linkgen reports progress) for the
# command's timeout is a hang; so is one that, however talkative, has not exited after
# HARD_CAP_FACTOR times the timeout. A long run that reports its progress is not a hang.
HARD_CAP_FACTOR = 10


class _Hang(Exception):
    """A command that stopped talking (or never ended): the message says which."""


def _watch(proc: subprocess.Popen, silence: float, min_wait: float | None = None) -> tuple[bytes, bytes]:
    """Wait for ``proc`` and return its (stdout, stderr). With ``min_wait``: raise
    subprocess.TimeoutExpired if it has not exited by then (the caller then interrupts it).
    Otherwise raise _Hang after ``silence`` seconds without output or HARD_CAP_FACTOR·silence in all."""
    import threading

    bufs = {"out": bytearray(), "err": bytearray()}
    last = [time.perf_counter()]

    def pump(stream, key):
        for chunk in iter(lambda: stream.read1(4096), b""):
            bufs[key] += chunk
            last[0] = time.perf_counter()

    if not hasattr(proc, "_fuzz_pumps"):
        proc._fuzz_bufs = bufs
        proc._fuzz_last = last
        proc._fuzz_pumps = [threading.Thread(target=pump, args=(proc.stdout, "out"), daemon=True),
                            threading.Thread(target=pump, args=(proc.stderr, "err"), daemon=True)]
        for t in proc._fuzz_pumps:
            t.start()
    bufs, last = proc._fuzz_bufs, proc._fuzz_last
    t0 = time.perf_counter()
    while proc.poll() is None:
        now = time.perf_counter()
        if min_wait is not None and now - t0 > min_wait:
            raise subprocess.TimeoutExpired(proc.args, min_wait)
        if now - last[0] > silence:
            raise _Hang(f"no output and no exit for {silence:g} s")
        if now - t0 > HARD_CAP_FACTOR * silence:
            raise _Hang(f"no exit in {HARD_CAP_FACTOR * silence:g} s")
        time.sleep(0.05)
    for t in proc._fuzz_pumps:
        t.join(timeout=5)
    return bytes(bufs["out"]), bytes(bufs["err"])


def run_cli(command: str, plant: str, model: Path, box: Path, timeout: float, name: str, samples: int,
            rng: np.random.Generator, special: bool = False) -> CliResult:
    """Run ``command`` on ``model`` (inside ``box/in`` unless ``special``) in the sandbox ``box``."""
    argv_t, outputs, target = COMMANDS[command]
    if HOME_TEMPLATE is not None and not (box / "home").exists():
        shutil.copytree(HOME_TEMPLATE, box / "home", symlinks=True)
    for d in ("cwd", "home", "tmp", "victim"):
        (box / d).mkdir(exist_ok=True)
    if target and target.startswith("report:"):
        target = target.format(name=name)
    planted, victim = (None, None) if special else _plant(plant, target, box, model)
    argv = [a.format(model=model, samples=samples) for a in argv_t]
    before = snapshot(box)
    t0 = time.perf_counter()
    proc = subprocess.Popen([sys.executable, "-m", "linkgen", *argv], cwd=box / "cwd", env=env_for(box),
                            stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            start_new_session=True)
    sent = False
    try:
        if plant == "sigterm":
            try:
                out, err = _watch(proc, timeout, min_wait=float(rng.uniform(0.4, 2.5)))
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGTERM)
                sent = True
                out, err = _watch(proc, timeout)
        else:
            out, err = _watch(proc, timeout)
    except _Hang as hang:
        cpu = _cpu_seconds(proc.pid)
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait()
        return CliResult(command, argv, plant, "hang", f"{hang} ({cpu} of CPU)", None, time.perf_counter() - t0)
    seconds = time.perf_counter() - t0
    stdout, stderr = out.decode(errors="replace"), err.decode(errors="replace")
    rc = proc.returncode
    res = CliResult(command, argv, plant, "ok", "", rc, seconds, stderr)
    # what changed, outside the outputs (and the description itself for assemble --write)
    allowed = {str((box / "cwd" / o.rstrip("/")).relative_to(box)) for o in outputs}
    if command == "assemble_write":
        allowed |= {"in/model.toml", "victim/real.toml"}
    stray = [p for p in _changed(before, snapshot(box))
             if not any(p == a or p.startswith(a + "/") for a in allowed)]
    unsafe = []
    if stray:
        unsafe.append("changed outside the outputs: " + ", ".join(stray[:4]))
    if victim is not None and (not victim.exists() or victim.read_bytes() != VICTIM):
        unsafe.append(f"wrote through the symlink planted at {planted.name} into its target")
    if planted is not None and plant == "mode" and planted.exists() and not planted.is_symlink() \
            and planted.stat().st_mode & 0o777 != 0o600:
        unsafe.append(f"{planted.name}: mode 0600 became {planted.stat().st_mode & 0o777:04o}")
    if planted is not None and target == "model" and plant == "symlink" and not planted.is_symlink():
        unsafe.append("the symlinked description was replaced by a copy")
    found = []
    if rc in (0, 3):  # what was printed or written, NaN/inf anywhere
        found.append(text_non_finite(stdout))
        for o in outputs:
            p = box / "cwd" / o.rstrip("/")
            for f in (sorted(p.rglob("*")) if p.is_dir() else [p]):
                found.append(output_non_finite(f) if f.is_file() and not f.is_symlink() else None)
    res.cls, res.detail = classify(rc, stdout, stderr, sent, unsafe, next((f for f in found if f), None))
    return res
