"""A machine in MuJoCo against its ODE (``linkgen.machine``): the machine file's run over the
first COMPARE_SECONDS or over its start-up and steady cycles, and MuJoCo's own dcmotor element."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkgen.errors import SimulationError
from linkgen.families.planar.assembly import Assembly, assemble
from linkgen.families.planar.reader import load
from linkgen.families.planar.kinetostatics import forces
from linkgen.machine.machine import MachineRun, run_machine
from linkgen.machine.reduced import Reduced, reduce
from linkgen.model.machine import Machine, machine_from_dict
from linkgen.model.toml_file import read_toml

# The machine comparison in ``linkgen validate``: MuJoCo's full linkage against the ODE over the
# first COMPARE_SECONDS of the start-up (or the whole duration if shorter); ``linkgen dynamics
# --mujoco`` and validation/machines.py compare the start-up and STEADY_CYCLES steady cycles.
# Each quantity within this of its peak (measured 7e-11 to 1.2e-7 over the first second on the
# bundled machines, see tests/test_dynamics.py and the closing figures of validation/machines.py).
COMPARE_SECONDS = 1.0
STEADY_CYCLES = 10
MACHINE_TOL = 1e-6
# Samples of the compared window.
COMPARE_SAMPLES = 2001
# A machine with friction in its pairs is compared over at most this many MuJoCo steps: each step
# solves the pairs' friction at MuJoCo's state in Python (``mujoco.machine``: ~0.3 ms of CPU a step
# with MuJoCo's own), so validate's 1 s at machine_friction's 7.5 µs steps (133 333 steps) would take
# ~40 s of CPU (~10 min before the friction table); 20 000 steps keep its whole validation at ~13 s
# of CPU and still cover 0° to 300° of the crank from its start, across its friction switches at
# 90°, 180° and 270°. The window is stated in the result ("window": seconds, steps, why) and the
# CLI's line.
FRICTION_STEPS = 20000


def _window(asm: Assembly, machine: Machine, cycles: int | None, progress=None, seconds: float = COMPARE_SECONDS
            ) -> tuple[MachineRun, float, Reduced, int | None]:
    """The ODE run over the compared window: the first COMPARE_SECONDS, or with ``cycles`` the
    start-up and that many steady cycles (the ODE is run long enough to find them); a machine
    that never settles (e.g. a constant torque without friction) is compared over its whole
    duration instead (then the cycles compared are None). A run that stops after its
    ``[machine] turns`` is compared up to there (the window returned is the run's)."""
    red = reduce(asm, machine.process_load, exact=not machine.tables)
    if machine.schedule is not None or machine.brake is not None:  # the whole run: on, off, braked to rest
        run = run_machine(machine, red, samples=COMPARE_SAMPLES, progress=progress)
        return run, float(run.t[-1]), red, None
    if cycles is None:
        duration = min(machine.duration, seconds)
        run = run_machine(machine, red, samples=COMPARE_SAMPLES, duration=duration, progress=progress)
        return run, float(run.t[-1]), red, None  # the run's end: its duration, or its [machine] turns
    run = run_machine(machine, red, samples=16, progress=progress)
    if run.steady is None:
        run = run_machine(machine, red, samples=COMPARE_SAMPLES, duration=machine.duration, progress=progress)
        return run, float(run.t[-1]), red, None
    duration = run.steady.t_start + cycles * run.steady.period
    run = run_machine(machine, red, samples=COMPARE_SAMPLES, duration=duration, progress=progress)
    if run.t[-1] < duration:  # it stopped first, after its [machine] turns: the cycles it ran
        cycles = int((run.t[-1] - run.steady.t_start) // run.steady.period)
    return run, float(run.t[-1]), red, cycles


def _settled(asm: Assembly, mj, stopping=None) -> np.ndarray:
    """Samples outside the loops' settling window after the start, after each switch of a
    stroke-switched force and after the motor's switches and the brake's engagement
    (``stopping``, ``machine.schedule.Stopping``): there MuJoCo's soft loop closures are still
    catching up with a load step (``mujoco.timing.settle_window``), as the prescribed-speed
    comparison leaves out too."""
    from linkgen.machine.tables import switch_angles

    keep = mj.t >= mj.t[0] + mj.settle
    if stopping is not None:
        for ts in (stopping.motor_on, stopping.motor_off, stopping.brake_at):
            if ts is not None and ts > 0:
                keep &= ~((mj.t >= ts - 0.5 * mj.timestep) & (mj.t <= ts + mj.settle))
    for s in switch_angles(asm.mechanism, asm.mechanism.drive.start):
        turn = np.floor((mj.phi - s) / (2 * math.pi))
        for k in np.flatnonzero(np.diff(turn) != 0):
            keep &= ~((mj.t >= mj.t[k]) & (mj.t <= mj.t[k + 1] + mj.settle))
    return keep


def _error(mj: np.ndarray | None, ref: np.ndarray | None, mask: np.ndarray, scale: float | None = None
           ) -> float | None:
    """The largest |mj − ref| over ``mask`` relative to ``scale`` (default the peak of ref)."""
    if mj is None or ref is None or not mask.any():
        return None
    peak = float(np.abs(ref).max()) if scale is None else scale
    return float(np.abs(mj[mask] - ref[mask]).max() / (peak if peak > 0 else 1.0))


def compare_machine_run(asm: Assembly, machine: Machine, cycles: int | None = None, native: bool = False,
                        progress=None):
    """MuJoCo's machine against the ODE (see COMPARE_SECONDS): JSON-ready errors relative to each
    quantity's peak — ω (start-up, and steady cycles with ``cycles``), the motor torque, the
    shaft twist — and φ [rad], the reactions relative to the mechanism's largest reaction (one
    scale for every joint: a joint that carries little is not judged on its own small peak);
    "ok" when each is within MACHINE_TOL, "worst" naming the largest. MuJoCo's settings come
    from the largest speed the ODE reaches. With ``native``, a DC machine also reports MuJoCo's
    own dcmotor element ("dcmotor", not part of "ok"). ``progress(fraction, elapsed)`` during
    the long runs. Returns the dict, MuJoCo's run and the ODE's."""
    from linkgen.machine.machine import motor_torque_at
    from linkgen.mujoco.machine import machine_timestep, run_machine_mujoco

    budget = asm.mechanism.frictions and cycles is None
    seconds = min(COMPARE_SECONDS, FRICTION_STEPS * machine_timestep(asm, machine)) if budget else COMPARE_SECONDS
    run, duration, red, cycles = _window(asm, machine, cycles, progress, seconds)
    reached = float(np.abs(run.omega).max())
    t, window = run.t, None
    if budget:  # the speed reached may shorten MuJoCo's timestep: the samples within the budget's steps
        dt = machine_timestep(asm, machine, reached)
        t = run.t[run.t <= FRICTION_STEPS * dt * (1 + 1e-12)]
        duration = float(t[-1])
        window = {"seconds": duration, "step_budget": FRICTION_STEPS, "timestep": dt,
                  "why": f"friction in the pairs: MuJoCo's run is compared over its first {FRICTION_STEPS} steps "
                         f"(the pairs' friction is solved at each step's state), not over {COMPARE_SECONDS:g} s"}
    mj = run_machine_mujoco(asm, machine, t, reactions=True, omega=reached, progress=progress)
    y = run.solution(mj.t)
    w, phi = y[1], y[0]
    twist = (y[2] - y[0]) if machine.shaft is not None else None
    torque = motor_torque_at(machine, red, y, mj.t)
    everything = np.ones(mj.t.shape, dtype=bool)
    steady_from = run.steady.t_start if (cycles is not None and run.steady is not None) else None
    errors = {"omega": _error(mj.omega, w, everything),
              "motor_torque": _error(mj.motor_torque, torque, everything),
              "twist": _error(mj.twist, twist, everything)}
    if steady_from is not None:
        errors["omega_startup"] = _error(mj.omega, w, mj.t < steady_from)
        errors["omega_steady"] = _error(mj.omega, w, mj.t >= steady_from)
    if mj.reactions:  # the kinetostatics at MuJoCo's own crank states against MuJoCo's reactions
        f = forces(asm, mj.phi, mj.omega, mj.epsilon)
        settled = _settled(asm, mj, run.stopping)
        scale = max(float(np.linalg.norm(np.asarray(f.reactions[k]), axis=-1).max()) for k in mj.reactions)
        errors["reactions"] = max(_error(mj.reactions[k], np.asarray(f.reactions[k]), settled, scale)
                                  for k in mj.reactions)
        out_extra = {"reactions_left_out": int((~settled).sum()), "settle_window_s": mj.settle,
                     "reaction_scale_n": scale,
                     "reactions_error_with_transients": max(_error(mj.reactions[k], np.asarray(f.reactions[k]),
                                                                   everything, scale) for k in mj.reactions)}
    else:
        out_extra = {}
    name = max((k for k, v in errors.items() if v is not None), key=lambda k: errors[k])
    worst = errors[name]
    out = {"ok": worst <= MACHINE_TOL, "omega_error_relative": errors["omega"], "errors_relative": errors,
           "worst": name, "worst_error_relative": worst,
           "tolerance": MACHINE_TOL, "phi_error_rad": float(np.abs(mj.phi - phi).max()), "duration_s": duration,
           "steps": mj.steps, "timestep": mj.timestep, "omega_reached": reached}
    out |= out_extra
    if window is not None:
        out["window"] = window
    if steady_from is not None:
        out |= {"steady_from_s": steady_from, "cycles": cycles}
    if run.steady is None:
        out["no_steady_cycle"] = True
    if machine.free:
        out["free"] = True  # no motor: the mechanism released from its start state
    if run.stopping is not None:
        out["stopping"] = run.stopping.to_json()
    if native and machine.motor.kind == "dc":
        out["dcmotor"] = _native_dc(asm, machine, run, mj.t)
    return out, mj, run


# MuJoCo's own dcmotor element (what ``linkgen dynamics --mjcf`` writes) is compared over at most
# this much of the window [s]: its error is first order in the timestep, not a pass/fail check.
NATIVE_SECONDS = 0.5


def _native_dc(asm: Assembly, machine: Machine, run: MachineRun, t: np.ndarray) -> dict:
    """ω of the machine file's dcmotor run against the ODE, relative to its peak, at the file's
    timestep and at half of it: the ratio shows the order in the timestep."""
    from linkgen.mujoco.machine_mjcf import run_native

    t = t[t <= NATIVE_SECONDS]
    y = run.solution(t)
    peak = float(np.abs(y[1]).max()) or 1.0
    first = run_native(asm, machine, t)
    half = run_native(asm, machine, t, timestep=0.5 * first.timestep)
    e1 = float(np.abs(first.omega - run.solution(first.t)[1]).max() / peak)
    e2 = float(np.abs(half.omega - run.solution(half.t)[1]).max() / peak)
    return {"omega_error_relative": e1, "timestep": first.timestep, "omega_error_relative_half_step": e2,
            "order": math.log2(e1 / e2) if e2 > 0 else None, "duration_s": float(t[-1]) if t.size else 0.0,
            "note": "MuJoCo's dcmotor element: its error falls in proportion to the timestep (order ≈ 1), the "
                    "circuit's current being integrated to first order while the linkage is integrated by RK4; "
                    "the comparison above applies the same circuit's torque at each step's mid-point instead"}


def compare_machine(path, cycles: int | None = None, progress=None, asm: Assembly | None = None) -> dict | None:
    """The dynamics comparison for a description with a ``[machine]`` table (None without one);
    a machine MuJoCo does not model here says so in "skipped". ``asm``: the file's assembly if at
    hand (its tables, such as the friction's, are then built once)."""
    data = read_toml(path)
    machine = machine_from_dict(data)
    if machine is None:
        return None
    asm = assemble(load(path)) if asm is None else asm
    try:
        return compare_machine_run(asm, machine, cycles, progress=progress)[0]
    except SimulationError as exc:
        return {"ok": False, "skipped": str(exc), "duration_s": None}


@dataclass(frozen=True)
class MachineCheck:
    """A planar file's validation with its ``[machine]`` table: the linkage's check at the
    prescribed speed (``check``: a ``crosscheck.run.CrossCheck``) and the machine driven by its
    motor in MuJoCo against its ODE (``machine``: ``compare_machine``'s dict); ok when both are."""

    check: object
    machine: dict

    @property
    def model(self) -> str:
        return self.check.model

    @property
    def ok(self) -> bool:
        return bool(self.check.ok and self.machine["ok"])

    @property
    def comparison(self):
        return self.check.comparison

    @property
    def diagnosis(self) -> tuple:
        return self.check.diagnosis

    def summary(self, wall: str | None = None) -> str:
        """The linkage's line (``crosscheck.run.headline``), FAIL when the machine missed."""
        from linkgen.crosscheck.run import headline

        return headline(self.to_json(), wall)

    def to_json(self) -> dict:
        return self.check.to_json() | {"dynamics": self.machine, "ok": self.ok}

    def to_dict(self) -> dict:
        """The result as ``linkgen validate --json`` gives it."""
        return self.to_json()


__all__ = ["COMPARE_SECONDS", "FRICTION_STEPS", "MACHINE_TOL", "STEADY_CYCLES", "MachineCheck", "compare_machine", "compare_machine_run"]
