"""A machine in MuJoCo: the full linkage (nothing reduced), its crank driven by the motor with no
prescribed speed. The rotor and flywheel are the crank joint's armature (J_rotor·u² + J_f); a
constant or linear motor is the drive actuator with an affine bias, u·η·M0 − u²·η·(M0/ω0)·q̇,
which MuJoCo integrates exactly like the closed form's law (no control input); an induction or DC
motor and the process load are torques computed each step at the step's mid-point crank angle
(qfrc_applied, held over one RK4 step: a mid-point rule, second order in the timestep).

Not covered here: an elastic shaft (rotor as a second body) and the mechanism's own
[[force]]/[[torque]] loads (gravity is MuJoCo's own); such a machine raises SimulationError."""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from linkgen.dynamics import motors
from linkgen.dynamics.reduced import process_torque_function
from linkgen.errors import SimulationError
from linkgen.model.machine import Machine
from linkgen.mujoco.log import no_log_file
from linkgen.mujoco.mjcf import write_mjcf
from linkgen.mujoco.options import PLACEHOLDER
from linkgen.mujoco.settings import apply, derive, set_armature
from linkgen.mujoco.state import initial_state
from linkgen.mujoco.tree import DRIVE_ACTUATOR
from linkgen.planar.assembly import Assembly


@dataclass(frozen=True)
class MujocoMachineRun:
    """MuJoCo's machine at the step times t (n,) [s] nearest to those asked for (within half a
    timestep): crank angle [rad], speed [rad/s], motor torque on the motor shaft [N·m]; steps
    and timestep [s]."""

    t: np.ndarray
    phi: np.ndarray
    omega: np.ndarray
    motor_torque: np.ndarray
    steps: int
    timestep: float


def _peak_speed(machine: Machine, asm: Assembly) -> float:
    m, u = machine.motor, machine.gear_ratio
    w = max(asm.mechanism.drive.omega, machine.start_speed)
    if m.kind == "linear":
        w = max(w, m.no_load_speed / u)
    elif m.kind == "induction":
        w = max(w, m.synchronous_speed / u)
    elif m.kind == "dc":
        w = max(w, m.voltage / m.emf_constant / u)
    return w


@no_log_file()
def run_machine_mujoco(asm: Assembly, machine: Machine, t: np.ndarray) -> MujocoMachineRun:
    """Run the machine in MuJoCo from its start speed and sample at times ``t`` (n,) [s]."""
    mech = asm.mechanism
    if machine.shaft is not None:
        raise SimulationError("the MuJoCo machine does not model an elastic shaft yet; compare the closed form only")
    if mech.forces or mech.torques:
        raise SimulationError("the MuJoCo machine applies gravity, the motor and the process load only; this "
                              "description also has [[force]]/[[torque]] loads")
    model = mujoco.MjModel.from_xml_string(write_mjcf(asm, PLACEHOLDER))
    settings, _ = derive(asm, model, omega=_peak_speed(machine, asm))
    apply(model, settings, mech.drive.joint)
    dof = model.joint(mech.drive.joint).dofadr[0]
    set_armature(model, dof, machine.added_inertia)
    u, eta, mot = machine.gear_ratio, machine.gear_efficiency, machine.motor
    model.actuator_gainprm[:] = 0.0
    model.actuator_biasprm[:] = 0.0
    act = model.actuator(DRIVE_ACTUATOR).id
    model.actuator_gaintype[act] = mujoco.mjtGain.mjGAIN_FIXED
    model.actuator_biastype[act] = mujoco.mjtBias.mjBIAS_AFFINE
    model.actuator_ctrllimited[act] = 0
    model.actuator_forcelimited[act] = 0
    per_step = mot.kind in ("induction", "dc")
    if mot.kind == "constant":
        model.actuator_biasprm[act, 0] = u * eta * mot.torque
    elif mot.kind == "linear":
        model.actuator_biasprm[act, 0] = u * eta * mot.stall_torque
        model.actuator_biasprm[act, 2] = -u * u * eta * mot.stall_torque / mot.no_load_speed
    data = mujoco.MjData(model)
    load = process_torque_function(machine.process_load)
    phi0 = mech.drive.start
    qpos, qvel = initial_state(asm, model, phi0, machine.start_speed)
    data.qpos[:], data.qvel[:] = qpos, qvel
    current = float(motors.dc_static_current(mot, u * machine.start_speed)) if motors.has_current(mot) and machine.start_speed > 0 else 0.0
    dt = model.opt.timestep
    t = np.asarray(t, dtype=float)
    out_t, out_phi, out_w, out_m = (np.empty_like(t) for _ in range(4))
    phi_c = phi0  # the crank angle, unwrapped
    adr = model.joint(mech.drive.joint).qposadr[0]
    q_prev = float(data.qpos[adr])
    k, steps = 0, 0
    while k < t.size:
        while k < t.size and t[k] <= data.time + 0.5 * dt:
            w = float(data.qvel[dof])
            out_t[k], out_phi[k], out_w[k] = data.time, phi_c, w
            out_m[k] = _motor_torque(mot, u * w, current)
            k += 1
        if k >= t.size:
            break
        w = float(data.qvel[dof])
        mid = phi_c + 0.5 * dt * w
        tau = -float(load(mid))
        if per_step:
            w_mid = w + 0.5 * dt * float(data.qacc[dof]) if steps else w
            tau += u * eta * _motor_torque(mot, u * w_mid, current)
        data.qfrc_applied[dof] = tau
        mujoco.mj_step(model, data)
        steps += 1
        if motors.has_current(mot):
            current += dt * float(motors.dc_current_rate(mot, u * float(data.qvel[dof]), current))
        q = float(data.qpos[adr])
        phi_c += (q - q_prev + math.pi) % (2 * math.pi) - math.pi
        q_prev = q
        if not np.isfinite(data.qvel).all():
            raise SimulationError(f"the MuJoCo machine diverged at t = {data.time:.6g} s")
    return MujocoMachineRun(out_t, out_phi, out_w, out_m, steps, dt)


def _motor_torque(mot, w_motor: float, current: float) -> float:
    if mot.kind == "dc":
        i = current if motors.has_current(mot) else float(motors.dc_static_current(mot, w_motor))
        return float(motors.torque(mot, w_motor, i))
    return float(motors.torque(mot, w_motor))


__all__ = ["MujocoMachineRun", "run_machine_mujoco"]
