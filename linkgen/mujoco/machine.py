"""A machine in MuJoCo: the full linkage (nothing reduced), its crank driven by the motor with no
prescribed speed. The rotor and flywheel are the crank joint's armature (J_rotor·u² + J_f); a
constant or linear motor is the drive actuator with an affine bias, u·η·M0 − u²·η·(M0/ω0)·q̇,
which MuJoCo integrates exactly like the closed form's law (no control input); an induction or DC
motor and the process load are torques computed each step at the step's mid-point (crank angle,
speed, and the DC current advanced exactly over half a step at that speed), held over one RK4
step (qfrc_applied): a mid-point rule, second order in the timestep.

An elastic shaft makes the rotor a body of its own on the crank's axis (joint ``machine:rotor``,
its armature J_rotor·u², angles reduced to the crank), joined to the crank by a fixed tendon
(rotor − crank) whose stiffness, damping and dead band (springlength ±backlash/2) are the
shaft's; the motor (``machine:motor``) then acts on the rotor.

The mechanism's own [[force]]/[[torque]] loads are body wrenches (``xfrc_applied``): each step
applies their mean over the crank angles the step sweeps (predicted from the speed and the last
acceleration), read from a table over one turn (LOAD_GRID cells, linear between them, a
stroke-switched force's switch angles exact; the closed-form positions at each grid angle: the
linkage has one degree of freedom, so its loads are functions of φ alone). Gravity is MuJoCo's own.
The motor's schedule and the brake are applied each step for the share of the step they act
(``mujoco.machine_schedule``).

Friction in the pairs ([[friction]]), which MuJoCo's frictionloss cannot model (``mujoco.friction``),
is applied each step as a wrench: the closed form's friction (through its table,
``machine.friction_table``) at the step's mid-point crank angle and speed (MuJoCo's own state,
not the ODE's) and at the crank acceleration the machine's equation gives there with the last
step's friction moment (MuJoCo's own qacc lags a step and carries its
soft loops' ripple: with it, extrapolated, ω erred by 4.3e-7 over 0.1 s of machine_friction, with
this 3.4e-8), regularised near rest as the machine's equation is (``machine.friction.scale``); an
elastic shaft's machine extrapolates qacc from the last two steps instead."""

from __future__ import annotations

import math
import time
from dataclasses import dataclass

import mujoco
import numpy as np

from linkgen.machine import motors
from linkgen.machine.reduced import process_torque_function
from linkgen.errors import SimulationError
from linkgen.model.machine import Machine
from linkgen.mujoco.log import no_log_file
from linkgen.mujoco.machine_schedule import StepSwitching
from linkgen.mujoco.mjcf import write_mjcf
from linkgen.mujoco.options import PLACEHOLDER
from linkgen.mujoco.settings import apply, derive, set_armature
from linkgen.mujoco.state import initial_state
from linkgen.mujoco.timing import settle_window
from linkgen.mujoco.tree import DRIVE_ACTUATOR
from linkgen.families.planar.assembly import Assembly
from linkgen.model.names import GROUND

ROTOR, SHAFT, MOTOR = "machine:rotor", "machine:shaft", "machine:motor"
# Cells of the load table over one turn: linear interpolation errs by (2π/LOAD_GRID)²/8 of the
# loads' second derivative in φ, 3e-9 of a load that varies like cos φ.
LOAD_GRID = 16384
# Passes of the friction's loop through MuJoCo's acceleration at a sample (and at the start): the
# friction depends on ε only through the inertia loads' share of the reactions (~μ·r/arm of them),
# so each pass shrinks the gap by that factor, ~1e-2 on the bundled models; the first starts from the
# last step's acceleration (friction included), already within ~dt·|dε/dt| of it: 2 passes suffice.
SAMPLE_PASSES = 2
# Seconds of wall time between progress reports of a long run.
PROGRESS_EVERY = 2.0


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
    twist: np.ndarray | None = None  # rotor angle (reduced to the crank) − crank angle [rad], elastic shaft
    epsilon: np.ndarray | None = None  # crank acceleration [rad/s²] (with ``reactions``)
    reactions: dict | None = None  # revolute reactions {name: (n, 2) [N]} read from MuJoCo (with ``reactions``)
    settle: float = 0.0  # [s] the loops' constraint forces need after a start or a load step (timing.settle_window)


class _LoadTable:
    """The mechanism's [[force]]/[[torque]] wrenches (nbody, 6) over one turn (or the drive's range), with their jumps
    (``dynamics.tables``)."""

    def __init__(self, asm: Assembly, model: mujoco.MjModel):
        from linkgen.machine.tables import PeriodicTable, jump_grid, switch_angles
        from linkgen.mujoco.forces import load_schedule

        d = asm.mechanism.drive
        span = min(d.stop - d.start, 2 * math.pi)  # a crank that does not turn fully: its range
        grid, where = jump_grid(d.start, LOAD_GRID, switch_angles(asm.mechanism, d.start), span)
        self.table = PeriodicTable(grid, load_schedule(asm, model, where, friction=False))
        self.shape = (model.nbody, 6)

    def over(self, a: float, b: float) -> np.ndarray:
        """The mean wrench while the crank turns from a to b [rad]."""
        return np.asarray(self.table.mean(a, b)).reshape(self.shape)


@no_log_file()
def run_machine_mujoco(asm: Assembly, machine: Machine, t: np.ndarray, reactions: bool = False,
                       omega: float | None = None, progress=None) -> MujocoMachineRun:
    """Run the machine in MuJoCo from its start speed and sample at times ``t`` (n,) [s]; with
    ``reactions``, also the crank acceleration and every revolute reaction at the samples, read
    from MuJoCo's constraint and joint forces with every load of that instant applied. The
    settings are derived for the largest crank speed [rad/s]: the motor's top speed or ``omega``
    (the speed the ODE reaches) if higher. ``progress(fraction, elapsed s)`` is called every
    PROGRESS_EVERY s of a run that lasts longer than that."""
    mech = asm.mechanism
    xml = write_mjcf(asm, PLACEHOLDER)
    model = mujoco.MjModel.from_xml_string(xml)
    settings, scales = _settings(asm, machine, model, omega)
    if machine.shaft is not None:
        model = mujoco.MjModel.from_xml_string(_with_shaft(xml, mech, machine))
    apply(model, settings, mech.drive.joint)
    crank = model.joint(mech.drive.joint).dofadr[0]
    if machine.shaft is not None:
        set_armature(model, crank, machine.flywheel_inertia)
        dof = model.joint(ROTOR).dofadr[0]
        set_armature(model, dof, machine.rotor_inertia * machine.gear_ratio**2)
    else:
        dof = crank
        set_armature(model, dof, machine.added_inertia)
    u, eta, mot = machine.gear_ratio, machine.gear_efficiency, machine.motor
    model.actuator_gainprm[:] = 0.0
    model.actuator_biasprm[:] = 0.0
    act = model.actuator(MOTOR if machine.shaft is not None else DRIVE_ACTUATOR).id
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
    base_bias = model.actuator_biasprm[act].copy()
    switching = StepSwitching(machine) if machine.schedule is not None or machine.brake is not None else None
    data = mujoco.MjData(model)
    load = process_torque_function(machine.process_load)
    # the friction is not a function of φ alone: applied at each step's own state below
    wrenches = any(f.link != GROUND for f in mech.forces) or any(t.link != GROUND for t in mech.torques)
    table = _LoadTable(asm, model) if wrenches else None
    rotor_adr = model.joint(ROTOR).qposadr[0] if machine.shaft is not None else None
    phi0 = machine.start(mech.drive.start)
    qpos, qvel = initial_state(asm, model, phi0, machine.start_speed)
    adr = model.joint(mech.drive.joint).qposadr[0]
    if machine.shaft is not None:  # the rotor starts with the crank: no twist
        qpos[model.joint(ROTOR).qposadr[0]], qvel[dof] = qpos[adr], qvel[crank]
    data.qpos[:], data.qvel[:] = qpos, qvel
    current = (float(motors.dc_static_current(mot, u * machine.start_speed))
               if motors.has_current(mot) and machine.start_speed != 0
               and (switching is None or switching.motor_at(0.0) > 0) else 0.0)
    dt = model.opt.timestep
    t = np.asarray(t, dtype=float)
    out_t, out_phi, out_w, out_m, out_twist, out_eps = (np.empty_like(t) for _ in range(6))
    out_r: dict[str, np.ndarray] = {}
    phi_c = phi0  # the crank angle, unwrapped
    q_prev = float(data.qpos[adr])
    k, steps = 0, 0
    fric, ode = None, None
    if mech.frictions:  # the pairs' friction at a state (``machine.friction``): the machine equation's own
        from linkgen.machine.friction import PairFriction

        if machine.shaft is None:
            from linkgen.machine.equation import Model
            from linkgen.machine.reduced import reduce

            ode = Model(machine, reduce(asm, machine.process_load))
        fric = ode.red.friction if ode is not None else PairFriction(asm)
    start_eps = _start_acceleration(asm, model, data, crank, phi0, fric) if mech.frictions else 0.0
    switches = _switches(asm)
    e_last, mf_last = start_eps, 0.0
    wall0 = time.perf_counter()
    report_at = PROGRESS_EVERY
    while k < t.size:
        while k < t.size and t[k] <= data.time + 0.5 * dt:
            out_t[k], out_phi[k], out_w[k] = data.time, phi_c, float(data.qvel[crank])
            on = 1.0 if switching is None else switching.motor_at(data.time)
            out_m[k] = _motor_torque(mot, u * float(data.qvel[dof]), current) * on
            if rotor_adr is not None:
                out_twist[k] = float(data.qpos[rotor_adr] - data.qpos[adr])
            if reactions:
                if switching is not None:  # this instant's motor and brake
                    model.actuator_biasprm[act] = base_bias * on
                    brake = switching.brake_now(data.time, float(data.qvel[crank]))
                eps, forces = _sample_forces(asm, model, data, phi_c, load, table, crank, dof, per_step,
                                             lambda w: u * eta * _motor_torque(mot, u * w, current) * on,
                                             0.0 if switching is None else brake, fric)
                out_eps[k] = eps
                for name, r in forces.reactions.items():
                    out_r.setdefault(name, np.empty((t.size, 2)))[k] = r
            k += 1
        if k >= t.size:
            break
        mid = phi_c + 0.5 * dt * float(data.qvel[crank])
        data.qfrc_applied[:] = 0.0
        data.qfrc_applied[crank] = -float(load(mid))
        if table is not None:
            w_c = float(data.qvel[crank])
            sweep = dt * w_c + (0.5 * dt * dt * float(data.qacc[crank]) if steps else 0.0)
            data.xfrc_applied[:] = table.over(phi_c, phi_c + sweep)
        w_mid = float(data.qvel[dof]) + (0.5 * dt * float(data.qacc[dof]) if steps else 0.0)
        share, braked = 1.0, 0.0
        if switching is not None:  # the motor's and the brake's shares of this step
            w_c = float(data.qvel[crank])
            a_c = float(data.qacc[crank]) if steps else 0.0
            switching.step(data.time, dt, phi_c, dt * w_c + 0.5 * dt * dt * a_c, w_c)
            share = switching.motor_share
            model.actuator_biasprm[act] = base_bias * share
            braked = switching.brake_torque(w_c + a_c * dt * (1.0 - 0.5 * switching.brake_share))
            data.qfrc_applied[crank] += braked
        if mech.frictions:
            if table is None:
                data.xfrc_applied[:] = 0.0
            # the crank's acceleration at the step's mid-point, extrapolated from the last two steps'
            e_c = (1.5 * float(data.qacc[crank]) - 0.5 * e_last) if steps > 1 else (float(data.qacc[crank]) if steps else start_eps)
            e_last = float(data.qacc[crank]) if steps else start_eps
            w_c = float(data.qvel[crank]) + 0.5 * dt * e_c
            sweep = dt * float(data.qvel[crank]) + 0.5 * dt * dt * e_c
            if ode is not None:  # ε from the machine's equation at this state with the last friction moment
                red = ode.red
                mm, _ = ode.motor(w_c, np.array([mid, w_c, current]))
                free = (float(red.moment(mid, w_c)) + u * eta * float(mm) * share + braked
                        - 0.5 * float(red.dj(mid)) * w_c * w_c)
                e_c = (free - mf_last) / (float(red.j(mid)) + machine.added_inertia)
            mf_last = _add_friction(asm, model, data, fric, mid, w_c, e_c, _split(switches, phi_c, phi_c + sweep))
        if per_step:
            i_mid = _current_after(mot, u * w_mid, current, 0.5 * dt) if motors.has_current(mot) else current
            data.qfrc_applied[dof] += u * eta * _motor_torque(mot, u * w_mid, i_mid) * share
        mujoco.mj_step(model, data)
        steps += 1
        if progress is not None and steps % 1000 == 0 and time.perf_counter() - wall0 >= report_at:
            report_at = time.perf_counter() - wall0 + PROGRESS_EVERY
            progress(min(data.time / max(float(t[-1]), dt), 1.0), time.perf_counter() - wall0)
        if motors.has_current(mot):  # the circuit opened while the motor is off: no current
            current = (_current_after(mot, u * w_mid, current, dt * share) if share > 0 else 0.0)
            if switching is not None and switching.motor_at(data.time) == 0.0:
                current = 0.0
        q = float(data.qpos[adr])
        phi_c += (q - q_prev + math.pi) % (2 * math.pi) - math.pi
        q_prev = q
        if not np.isfinite(data.qvel).all():
            raise SimulationError(f"the MuJoCo machine diverged at t = {data.time:.6g} s")
    return MujocoMachineRun(out_t, out_phi, out_w, out_m, steps, dt, out_twist if rotor_adr is not None else None,
                            out_eps if reactions else None, out_r if reactions else None,
                            settle_window(settings, scales, 0.0, gravity=float(np.hypot(*mech.gravity))))


def _settings(asm: Assembly, machine: Machine, model: mujoco.MjModel, omega: float | None):
    """The derived settings and scales (``settings.derive``) of the machine's run: for the largest
    crank speed, the motor's top speed or ``omega`` if higher."""
    return derive(asm, model, omega=max(machine.top_speed(asm.mechanism.drive.omega), omega or 0.0))


def machine_timestep(asm: Assembly, machine: Machine, omega: float | None = None) -> float:
    """The timestep [s] ``run_machine_mujoco`` takes with the same ``omega``."""
    model = mujoco.MjModel.from_xml_string(write_mjcf(asm, PLACEHOLDER))
    return float(_settings(asm, machine, model, omega)[0].timestep)


def _sample_forces(asm, model, data, phi: float, load, table, crank: int, dof: int, per_step: bool, drive,
                   brake: float = 0.0, friction=None):
    """The crank acceleration and the forces at the current state with this instant's loads
    (``brake``: the brake's moment on the crank [N·m]; ``friction``: the pairs' friction, see
    ``_add_friction``)."""
    from linkgen.mujoco.forces import forward_forces

    data.qfrc_applied[:] = 0.0
    data.qfrc_applied[crank] = -float(load(phi)) + brake
    data.xfrc_applied[:] = 0.0 if table is None else np.asarray(table.table.at(phi)).reshape(table.shape)
    if per_step:
        data.qfrc_applied[dof] += drive(float(data.qvel[dof]))
    if asm.mechanism.frictions:  # at the last step's acceleration (the ODE's friction is at its own)
        base = data.xfrc_applied.copy()
        for _ in range(SAMPLE_PASSES):
            eps = float(data.qacc[crank])
            data.xfrc_applied[:] = base
            _add_friction(asm, model, data, friction, phi, float(data.qvel[crank]), eps)
            mujoco.mj_forward(model, data)
    mujoco.mj_forward(model, data)
    mujoco.mj_rnePostConstraint(model, data)
    return float(data.qacc[crank]), forward_forces(asm, model, data)


def _add_friction(asm, model, data, friction, phi: float, omega: float, epsilon: float, split=None) -> float:
    """Add the pairs' friction (``machine.friction.PairFriction.values``: the closed form's at the
    crank angle, speed and acceleration, scaled by ``machine.friction.scale`` as the machine's
    equation is) to ``xfrc_applied``; returns the friction's reduced moment s·M_f [N·m]. ``split``
    (a step that sweeps a friction switch, ``_split``): the step's mean instead, the friction at the
    middle of the part before the switch and of the part after it weighted by their shares of the
    sweep (the jump is then where it falls in the step, to first order, not at the step's mid-point)."""
    from linkgen.machine.friction import scale
    from linkgen.mujoco.friction import add_friction

    s = float(scale(omega))
    if s == 0.0:
        return 0.0
    mujoco.mj_kinematics(model, data)
    angles, weights = (np.array([phi]), np.ones(1)) if split is None else split
    pairs, moment = friction.values(angles, omega, epsilon)
    add_friction(asm, model, data, {k: s * float(np.dot(weights, v)) for k, v in pairs.items()})
    return s * float(np.dot(weights, moment))


def _switches(asm) -> np.ndarray:
    """The crank angles in [0, 2π) where a pair's friction changes direction (none without friction)."""
    from linkgen.mujoco.friction import friction_switches

    d = asm.mechanism.drive
    if not asm.mechanism.frictions:
        return np.array([])
    return np.unique(np.mod(friction_switches(asm, d.start, d.start + 2 * math.pi), 2 * math.pi))


def _split(switches: np.ndarray, a: float, b: float):
    """For a step sweeping the crank from a to b [rad]: None unless a friction switch lies strictly
    between; else (the middles of the parts between a, the switches and b, their shares of b − a)."""
    if not switches.size or a == b:
        return None
    lo, hi = min(a, b), max(a, b)
    inside = (switches[None, :] + 2 * math.pi * np.arange(math.floor(lo / (2 * math.pi)),
                                                         math.floor(hi / (2 * math.pi)) + 1)[:, None]).ravel()
    inside = np.sort(inside[(inside > lo) & (inside < hi)])
    if not inside.size:
        return None
    edges = np.concatenate([[lo], inside, [hi]])
    return 0.5 * (edges[:-1] + edges[1:]), np.diff(edges) / (hi - lo)


def _start_acceleration(asm, model, data, crank: int, phi: float, friction) -> float:
    """The crank's acceleration at the start state with the friction at it (SAMPLE_PASSES passes
    from the frictionless one)."""
    mujoco.mj_forward(model, data)
    for _ in range(SAMPLE_PASSES):
        data.xfrc_applied[:] = 0.0
        _add_friction(asm, model, data, friction, phi, float(data.qvel[crank]), float(data.qacc[crank]))
        mujoco.mj_forward(model, data)
    data.xfrc_applied[:] = 0.0
    return float(data.qacc[crank])


def _with_shaft(xml: str, mech, machine: Machine) -> str:
    """The MJCF with a rotor body on the crank's axis, the shaft as a fixed tendon and the
    motor on the rotor (see the module docstring)."""
    from lxml import etree

    root = etree.fromstring(xml.encode())
    pivot = mech.points[mech.drive.joint.split(":")[0]]
    world = root.find("worldbody")
    body = etree.SubElement(world, "body", name=ROTOR, pos=f"{pivot[0]!r} {pivot[1]!r} 0")
    etree.SubElement(body, "inertial", pos="0 0 0", mass="1", diaginertia="1e-6 1e-6 1e-6")
    etree.SubElement(body, "joint", name=ROTOR, type="hinge", axis="0 0 1")
    s = machine.shaft
    tendon = root.find("tendon") if root.find("tendon") is not None else etree.SubElement(root, "tendon")
    fixed = etree.SubElement(tendon, "fixed", name=SHAFT, stiffness=repr(s.stiffness), damping=repr(s.damping),
                             springlength=f"{-s.backlash / 2!r} {s.backlash / 2!r}")
    etree.SubElement(fixed, "joint", joint=ROTOR, coef="1")
    etree.SubElement(fixed, "joint", joint=mech.drive.joint, coef="-1")
    actuator = root.find("actuator")
    etree.SubElement(actuator, "general", name=MOTOR, joint=ROTOR, gainprm="0", biastype="affine")
    return etree.tostring(root, encoding="unicode")


def _current_after(mot, w_motor: float, current: float, h: float) -> float:
    """The DC armature current after h [s] at a constant motor speed: the exact solution of
    L·di/dt = U − R·i − k_e·ω, i_ss + (i − i_ss)·exp(−R·h/L)."""
    i_ss = float(motors.dc_static_current(mot, w_motor))
    return i_ss + (current - i_ss) * math.exp(-mot.resistance * h / mot.inductance)


def _motor_torque(mot, w_motor: float, current: float) -> float:
    if mot.kind == "dc":
        i = current if motors.has_current(mot) else float(motors.dc_static_current(mot, w_motor))
        return float(motors.torque(mot, w_motor, i))
    return float(motors.torque(mot, w_motor))


__all__ = ["MujocoMachineRun", "machine_timestep", "run_machine_mujoco"]
