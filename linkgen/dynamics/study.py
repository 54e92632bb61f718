"""A machine study from a description: load the mechanism and its ``[machine]`` table, integrate
the machine, the forces along its real motion over the steady cycle, the flywheel check, and the
MuJoCo comparison."""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, replace
from pathlib import Path

import numpy as np

from linkgen.dynamics.flywheel import Flywheel, size_flywheel
from linkgen.dynamics.machine import MachineRun, run_machine
from linkgen.dynamics.reduced import Reduced, reduce
from linkgen.errors import DescriptionError, SimulationError
from linkgen.model.machine import Machine, Motor, machine_from_dict
from linkgen.model.reader import load
from linkgen.planar.assembly import Assembly, assemble
from linkgen.planar.kinetostatics import forces

# Samples of the steady cycle at which the forces along the real motion are evaluated.
CYCLE_SAMPLES = 720


def load_machine(path: str | Path) -> tuple[Assembly, Machine]:
    """The assembled mechanism and its machine; DescriptionError naming the file if it has no
    ``[machine]`` table."""
    asm = assemble(load(path))
    data = tomllib.loads(Path(path).read_bytes().decode("utf-8-sig"))
    machine = machine_from_dict(data)
    if machine is None:
        raise DescriptionError("machine", "is missing: a machine study needs a [machine] table with a "
                               "[machine.motor] (see docs/format.md)", str(path))
    return asm, machine


@dataclass(frozen=True)
class CycleForces:
    """Peak balancing torque [N·m] and peak reaction per revolute [N] over the steady cycle,
    with the crank angles [rad] where they occur."""

    balancing_torque: float
    balancing_torque_at: float
    reactions: dict[str, tuple[float, float]]

    def to_json(self) -> dict:
        return {"peak_balancing_torque": self.balancing_torque,
                "peak_balancing_torque_at_deg": math.degrees(self.balancing_torque_at) % 360.0,
                "peak_reactions": {k: {"force": f, "at_deg": math.degrees(a) % 360.0}
                                   for k, (f, a) in self.reactions.items()}}


def cycle_forces(asm: Assembly, run: MachineRun, samples: int = CYCLE_SAMPLES) -> CycleForces | None:
    """Kinetostatics at the actual φ(t), ω(t), ε(t) over the steady cycle (None without one)."""
    s = run.steady
    if s is None:
        return None
    t = np.linspace(s.t_start, s.t_start + s.period, samples, endpoint=False)
    y = run.solution(t)
    eps = np.gradient(y[1], t)  # checked against the ODE's own ε in tests/test_dynamics.py
    f = forces(asm, y[0], y[1], eps)
    k = int(np.argmax(np.abs(f.balancing_torque)))
    reactions = {}
    for name, r in f.reactions.items():
        mag = np.linalg.norm(r, axis=1)
        j = int(np.argmax(mag))
        reactions[name] = (float(mag[j]), float(y[0][j]))
    return CycleForces(float(f.balancing_torque[k]), float(y[0][k]), reactions)


def constant_drive(machine: Machine, torque: float, flywheel: float, start_speed: float) -> Machine:
    """The machine driven by a constant torque at the crank [N·m] with a given flywheel."""
    return replace(machine, motor=Motor("constant", (("torque", torque),)), gear_ratio=1.0, gear_efficiency=1.0,
                   rotor_inertia=0.0, flywheel_inertia=flywheel, start_speed=start_speed, shaft=None)


def check_flywheel(red: Reduced, machine: Machine, fw: Flywheel) -> float:
    """δ = (ω_max − ω_min)/((ω_max + ω_min)/2) over one cycle of the machine integrated with a
    constant driving torque and the sized flywheel (plus the rotor), from the sized start speed."""
    added = machine.rotor_inertia * machine.gear_ratio**2
    m = constant_drive(machine, fw.driving_torque, fw.inertia + added, fw.start_speed)
    period = 2 * math.pi / fw.omega_mean
    run = run_machine(m, red, samples=16, duration=1.5 * period)
    t = np.linspace(0.0, 1.5 * period, 20000)
    phi, w = run.state_at(t)
    one = phi - phi[0] <= 2 * math.pi
    if not (phi[-1] - phi[0] > 2 * math.pi):
        raise SimulationError("the flywheel check did not complete a turn")
    w = w[one]
    return float((w.max() - w.min()) / (0.5 * (w.max() + w.min())))


def flywheel_study(asm: Assembly, machine: Machine, delta: float, omega_mean: float | None = None) -> tuple[Flywheel, float]:
    """The sized flywheel (beyond the mechanism and the rotor) and δ of its integration check."""
    red = reduce(asm, machine.process_load)
    w = asm.mechanism.drive.omega if omega_mean is None else omega_mean
    fw = size_flywheel(red, w, delta, added=machine.rotor_inertia * machine.gear_ratio**2)
    return fw, check_flywheel(red, machine, fw)




# The machine comparison in ``linkgen validate``: MuJoCo's full linkage against the ODE over the
# first COMPARE_SECONDS of the start-up (or the whole duration if shorter), ω within this of its
# peak (measured 2.7e-9 to 1.3e-7 on the bundled machines, see tests/test_dynamics.py).
COMPARE_SECONDS = 1.0
MACHINE_TOL = 1e-6


def compare_machine(path) -> dict | None:
    """The dynamics comparison for a description with a ``[machine]`` table (None without one):
    JSON-ready, with "ok", the relative ω error and the steps; a machine MuJoCo does not model
    here says so in "skipped"."""
    from linkgen.mujoco.machine import run_machine_mujoco

    data = tomllib.loads(Path(path).read_bytes().decode("utf-8-sig"))
    machine = machine_from_dict(data)
    if machine is None:
        return None
    asm = assemble(load(path))
    duration = min(machine.duration, COMPARE_SECONDS)
    run = run_machine(machine, reduce(asm, machine.process_load), samples=201, duration=duration)
    try:
        mj = run_machine_mujoco(asm, machine, run.t)
    except SimulationError as exc:
        return {"ok": False, "skipped": str(exc), "duration_s": duration}
    phi, w = run.state_at(mj.t)
    err = float(np.abs(mj.omega - w).max() / max(float(np.abs(w).max()), 1e-300))
    return {"ok": err <= MACHINE_TOL, "omega_error_relative": err, "tolerance": MACHINE_TOL,
            "phi_error_rad": float(np.abs(mj.phi - phi).max()), "duration_s": duration, "steps": mj.steps,
            "timestep": mj.timestep}


__all__ = ["CycleForces", "check_flywheel", "compare_machine", "cycle_forces", "flywheel_study", "load_machine"]
