"""A machine study from a description: load the mechanism and its ``[machine]`` table, integrate
the machine, the forces along its real motion over the steady cycle, the flywheel check, and the
flywheel sizing. (Its MuJoCo comparison: ``linkgen.crosscheck.machine``.)"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np

from linkgen.machine.flywheel import Flywheel, size_flywheel
from linkgen.machine.machine import MachineRun, run_machine, speed_range
from linkgen.machine.reduced import Reduced, reduce, require_full_turn
from linkgen.errors import DescriptionError, SimulationError
from linkgen.extrema import peak, samples as grid
from linkgen.model.summary import Extreme
from linkgen.model.machine import Machine, Motor, machine_from_dict
from linkgen.families.planar.reader import load
from linkgen.model.toml_file import read_toml
from linkgen.families.planar.assembly import Assembly, assemble
from linkgen.families.planar.kinetostatics import forces

# Samples of the steady cycle at which the forces along the real motion are evaluated.
CYCLE_SAMPLES = 720


def load_machine(path: str | Path) -> tuple[Assembly, Machine]:
    """The assembled mechanism and its machine; DescriptionError naming the file if it has no
    ``[machine]`` table."""
    asm = assemble(load(path))
    data = read_toml(path)
    machine = machine_from_dict(data)
    if machine is None:
        raise DescriptionError("machine", "is missing: a machine study needs a [machine] table (with a "
                               "[machine.motor], or none for free motion; see docs/machine.md)", str(path))
    return asm, machine


@dataclass(frozen=True)
class CycleForces:
    """Over the steady cycle, in the design summary's vocabulary (``linkgen.model.summary``): the
    peak balancing torque's magnitude [N·m] and each revolute's peak reaction [N], each with the
    crank angle φ [rad, in [0, 2π)] where it occurs."""

    peak_balancing_torque: Extreme
    peak_reactions: dict[str, Extreme]

    def to_dict(self) -> dict:
        return {"peak_balancing_torque": asdict(self.peak_balancing_torque),
                "peak_reactions": {k: asdict(v) for k, v in self.peak_reactions.items()}}

    to_json = to_dict


def cycle_forces(asm: Assembly, run: MachineRun, samples: int = CYCLE_SAMPLES) -> CycleForces | None:
    """Kinetostatics at the actual φ(t), ω(t), ε(t) over the steady cycle (None without one):
    each peak found on ``samples`` times over the cycle and refined between them
    (``linkgen.extrema``, round the cycle's wrap)."""
    s = run.steady
    if s is None:
        return None
    t = grid(s.t_start, s.t_start + s.period, samples, periodic=True)

    def at(tt):
        """Crank angles and forces at times tt (m,) [s], ε the ODE's own at each state."""
        y = run.solution(tt)
        eps = np.array([run.rate(tk, y[:, k])[1] for k, tk in enumerate(tt)])
        return y[0], forces(asm, y[0], y[1], eps)

    _, f = at(t)
    k_at, torque = peak(lambda tt: np.abs(at(tt)[1].balancing_torque), t, np.abs(f.balancing_torque),
                        period=s.period)
    reactions = {}
    for name, r in f.reactions.items():
        j_at, mag = peak(lambda tt, n=name: np.linalg.norm(at(tt)[1].reactions[n], axis=1), t,
                         np.linalg.norm(r, axis=1), period=s.period)
        reactions[name] = Extreme(float(mag), float(run.solution(np.array([j_at]))[0][0]) % (2 * math.pi))
    return CycleForces(Extreme(float(abs(torque)), float(run.solution(np.array([k_at]))[0][0]) % (2 * math.pi)),
                       reactions)


def constant_drive(machine: Machine, torque: float, flywheel: float, start_speed: float) -> Machine:
    """The machine driven by a constant torque at the crank [N·m] with a given flywheel, running
    steadily: no motor schedule, no brake."""
    return replace(machine, motor=Motor("constant", (("torque", torque),)), gear_ratio=1.0, gear_efficiency=1.0,
                   rotor_inertia=0.0, flywheel_inertia=flywheel, start_speed=start_speed, shaft=None, schedule=None,
                   brake=None)


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
    low, high = speed_range(run.solution, 0.0, float(t[one][-1]), periodic=False, n=int(np.count_nonzero(one)))
    return float((high - low) / (0.5 * (high + low)))


def flywheel_study(asm: Assembly, machine: Machine, delta: float, omega_mean: float | None = None) -> tuple[Flywheel, float]:
    """The sized flywheel (beyond the mechanism and the rotor) and δ of its integration check."""
    red = reduce(asm, machine.process_load)
    require_full_turn(red, "a flywheel")
    w = asm.mechanism.drive.omega if omega_mean is None else omega_mean
    fw = size_flywheel(red, w, delta, added=machine.rotor_inertia * machine.gear_ratio**2)
    return fw, check_flywheel(red, machine, fw)


__all__ = ["CycleForces", "check_flywheel", "constant_drive", "cycle_forces", "flywheel_study", "load_machine"]
