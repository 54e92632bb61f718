"""The library path of validation/fuzz_commands.py, in-process: one description through
load → structure → kinematics → forces → summary, and with ``deep`` the MJCF string (compiled
by MuJoCo) and the machine run and flywheel, by family, each result walked for NaN/inf.

``run_library(path, timeout)`` returns (class, detail): "ok", "clean error" (a LinkgenError),
"crash" (any other exception, or an MJCF MuJoCo refuses), "hang" (past ``timeout`` s, by
SIGALRM) or "non-finite" (a NaN or inf in a result).
"""

from __future__ import annotations

import dataclasses
import math
import signal
import time
import traceback
from pathlib import Path

import numpy as np

# Machine time simulated by the library path [s]: enough for start-up and a few turns of every
# bundled machine (their [machine] durations are 1-6 s) while keeping a mutant under a second or two.
MACHINE_DURATION = 2.0
# Crank angles sampled by the library path: a coarse turn, the cost of a mutant stays small.
SAMPLES = 24


class Hang(BaseException):
    """Raised by SIGPROF or SIGALRM when the library path runs past its time limit."""


def _alarm(signum, frame):
    raise Hang()


def non_finite(obj, where: str = "result", depth: int = 0, seen=None) -> str | None:
    """The first place in ``obj`` (arrays, numbers, dicts, lists, dataclasses) holding NaN or
    inf, or None."""
    seen = set() if seen is None else seen
    if depth > 8 or id(obj) in seen:
        return None
    if isinstance(obj, (bool, str, bytes, type(None))):
        return None
    if isinstance(obj, (float, int, np.floating, np.integer)):
        return None if math.isfinite(float(obj)) else f"{where} = {obj}"
    if isinstance(obj, np.ndarray):
        if obj.dtype.kind in "fc" and not np.all(np.isfinite(obj)):
            return f"{where} has {int(np.count_nonzero(~np.isfinite(obj)))} non-finite of {obj.size}"
        return None
    seen.add(id(obj))
    if isinstance(obj, dict):
        items = obj.items()
    elif isinstance(obj, (list, tuple)):
        items = enumerate(obj)
    elif dataclasses.is_dataclass(obj):
        items = ((f.name, getattr(obj, f.name, None)) for f in dataclasses.fields(obj))
    else:
        return None
    for k, v in items:
        found = non_finite(v, f"{where}.{k}", depth + 1, seen)
        if found:
            return found
    return None


def _compile(xml: str) -> None:
    import mujoco

    from linkgen.mujoco.log import no_log_file

    try:
        with no_log_file():
            mujoco.MjModel.from_xml_string(xml)
    except ValueError as exc:  # MuJoCo refusing what linkgen wrote is linkgen's failure
        raise RuntimeError(f"MuJoCo rejects the MJCF: {str(exc).strip()[:200]}") from None


def _planar(mech, path: Path, deep: bool) -> list:
    import linkgen
    from linkgen.families.planar.kinetostatics import forces
    from linkgen.families.planar.summary import summarize
    from linkgen.model.machine import machine_from_dict
    from linkgen.model.toml_file import read_toml
    from linkgen.mujoco.mjcf import write_mjcf

    asm = linkgen.assemble(mech)
    d = mech.drive
    phi = np.linspace(d.start, d.stop, SAMPLES)
    kin = linkgen.solve(asm, phi, on_singular="mark")  # singular rows: finite by contract, not an error
    ok = ~np.asarray(kin.singular, bool)
    out = [("structure", linkgen.decompose(mech).formula), ("points", kin.points), ("sliders", kin.sliders),
           ("links", kin.links)]
    if np.any(ok):
        out.append(("forces", forces(asm, phi[ok], d.omega, d.epsilon)))
    out.append(("summary", summarize(asm, d.omega, d.epsilon).to_dict()))
    if deep:
        _compile(write_mjcf(asm))
        if machine_from_dict(read_toml(path)) is not None:  # the machine layer over the linkage
            out += _machine(path)
    return out


def _machine(path: Path) -> list:
    from linkgen.machine.machine import run_machine
    from linkgen.machine.reduced import reduce
    from linkgen.machine.study import cycle_forces, flywheel_study, load_machine
    from linkgen.mujoco.machine_mjcf import machine_mjcf

    asm, machine = load_machine(path)
    run = run_machine(machine, reduce(asm, machine.process_load), samples=400,
                      duration=min(machine.duration, MACHINE_DURATION))
    f = cycle_forces(asm, run)
    out = [("run.omega", run.omega), ("run.motor_torque", run.motor_torque),
           ("steady", run.steady.to_json() if run.steady else None), ("cycle_forces", f.to_json() if f else None)]
    fw, delta = flywheel_study(asm, machine, 0.02)
    out += [("flywheel", fw), ("delta_integrated", delta)]
    _compile(machine_mjcf(asm, machine))
    return out


def _cam(cm, path: Path, deep: bool) -> list:
    from linkgen.families.cam.kinetics import state
    from linkgen.families.cam.summary import cam_summary
    from linkgen.mujoco.cam import cam_mjcf

    theta = np.linspace(0.0, 2 * math.pi, 72, endpoint=False)
    s = cam_summary(cm, cm.omega).to_dict()  # leave_speed None: the follower never leaves
    out = [("state", state(cm, theta, cm.omega)), ("summary", s), ("profile", cm.follower.profile(theta)),
           ("pitch", cm.follower.pitch_curve(theta)[0])]
    if deep:
        _compile(cam_mjcf(cm))
    return out


def _spatial(mech, path: Path, deep: bool) -> list:
    from linkgen.crosscheck.spatial import derived_settings
    from linkgen.families.spatial.forces import forces
    from linkgen.families.spatial.kinematics import assembled_chain, solve
    from linkgen.mujoco.spatial_mjcf import write_spatial_mjcf
    from linkgen.families.spatial.summary import summarize

    assembled_chain(mech)
    phi = np.linspace(0.0, 2 * math.pi, SAMPLES, endpoint=False)
    motion = solve(mech, phi)
    f = forces(mech, phi, motion=motion)
    out = [("balancing_torque", f.balancing_torque),
           ("reactions", {n: (r.force, r.moment) for n, r in f.reactions.items()}),
           ("summary", summarize(mech).to_dict())]
    if deep:
        _compile(write_spatial_mjcf(mech, derived_settings(mech)[0]))
    return out


# The library path of each family (by the registry's name for it).
PATHS = {"planar": _planar, "cam": _cam, "spatial": _spatial}


def _dispatch(path: Path, deep: bool) -> list:
    from linkgen.pipeline.registry import family_of, load

    desc = load(path)
    return PATHS[family_of(desc).name](desc, path, deep)


def run_library(path: Path, timeout: float, deep: bool = True, wall: float | None = None) -> tuple[str, str]:
    """The class of ``path``'s library run and a one-line detail; ``deep`` adds the MJCF
    (compiled by MuJoCo) and the machine run and flywheel, the slow half of the path. A hang is
    ``timeout`` seconds of this process's CPU without a result (SIGPROF: the run's own work,
    whatever else the machine runs beside it), or ``wall`` seconds of the clock (SIGALRM, default
    10 × timeout: a run blocked waiting, e.g. on a FIFO)."""
    from linkgen.errors import LinkgenError

    wall = 10 * timeout if wall is None else wall
    old = signal.signal(signal.SIGALRM, _alarm)
    old_prof = signal.signal(signal.SIGPROF, _alarm)
    cpu, t0 = time.process_time(), time.perf_counter()
    try:
        signal.setitimer(signal.ITIMER_REAL, wall)
        signal.setitimer(signal.ITIMER_PROF, timeout)
        try:
            results = _dispatch(path, deep)
        finally:  # disarmed before any handling: a late alarm must not hit the handlers below
            signal.setitimer(signal.ITIMER_REAL, 0)
            signal.setitimer(signal.ITIMER_PROF, 0)
    except Hang:
        return "hang", (f"no result after {time.process_time() - cpu:.1f} s of CPU in {time.perf_counter() - t0:.1f} s "
                        f"(limits: {timeout:g} s of CPU, {wall:g} s of the clock)")
    except LinkgenError as exc:
        return "clean error", f"{type(exc).__name__}: {str(exc).splitlines()[0][:160] if str(exc) else ''}"
    except Exception as exc:  # noqa: BLE001 — the point of the run: any other exception is a finding
        tb = traceback.extract_tb(exc.__traceback__)
        where = next((f"{Path(f.filename).name}:{f.lineno}" for f in reversed(tb) if "/linkgen/" in f.filename), "?")
        return "crash", f"{type(exc).__name__} at {where}: {str(exc).splitlines()[0][:160] if str(exc) else ''}"
    finally:
        signal.signal(signal.SIGALRM, old)
        signal.signal(signal.SIGPROF, old_prof)
    bad = non_finite(dict(results))
    return ("non-finite", bad) if bad else ("ok", "")
