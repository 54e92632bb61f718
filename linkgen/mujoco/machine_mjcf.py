"""A machine as a MuJoCo file a user can run without linkgen: the full linkage, the rotor and
flywheel as inertia (armature), an elastic shaft as a rotor body joined to the crank by a fixed
tendon, and the motor as MuJoCo's own element where MuJoCo has one — ``dcmotor`` (armature
circuit with its inductance; control = the supply voltage) for a DC motor, a ``general``
actuator with an affine bias for a linear or constant characteristic — and a plain ``motor``
(control = torque on the motor shaft) for an induction motor, whose Kloss law MuJoCo has no
element for. A process load and the mechanism's [[force]]/[[torque]] are not elements either:
the file says so, and ``run_native`` applies them each step.

The keyframe ``start`` is the machine's start: the drive's start angle, its start speed, the
supply voltage as the control and the DC current at the start speed."""

from __future__ import annotations

import math
from dataclasses import replace

import mujoco
import numpy as np
from lxml import etree

from linkgen.machine import motors
from linkgen.model.machine import Machine
from linkgen.mujoco.mjcf import write_mjcf
from linkgen.mujoco.options import PLACEHOLDER
from linkgen.mujoco.scene import KEY, SERVO
from linkgen.mujoco.settings import derive
from linkgen.mujoco.tree import DRIVE_ACTUATOR
from linkgen.families.planar.assembly import Assembly
from linkgen.mujoco.log import no_log_file

ROTOR, SHAFT, MOTOR = "machine:rotor", "machine:shaft", "machine:motor"
START_KEY = "start"


def _f(x: float) -> str:
    return repr(float(x))


@no_log_file()  # MuJoCo's warnings stay out of the user's folder (linkgen.mujoco.log)
def machine_settings(asm: Assembly, machine: Machine):
    """The validation settings of the linkage at the machine's peak speed, with the crank's
    armature the machine's own inertia on the crank (rotor and flywheel, or the flywheel alone
    behind an elastic shaft)."""
    model = mujoco.MjModel.from_xml_string(write_mjcf(asm, PLACEHOLDER))
    settings, _ = derive(asm, model, omega=machine.top_speed(asm.mechanism.drive.omega))
    crank = machine.flywheel_inertia if machine.shaft is not None else machine.added_inertia
    return replace(settings, armature=crank)


def machine_mjcf(asm: Assembly, machine: Machine) -> str:
    """The machine's MJCF text (see the module docstring)."""
    mech = asm.mechanism
    root = etree.fromstring(write_mjcf(asm, machine_settings(asm, machine)).encode())
    actuator = root.find("actuator")
    for act in list(actuator):
        if act.get("name") in (SERVO, DRIVE_ACTUATOR) or not isinstance(act.tag, str):
            actuator.remove(act)
    for joint in root.iter("joint"):
        if joint.get("name") == mech.drive.joint:
            joint.attrib.pop("limited", None)
            joint.attrib.pop("range", None)
    target = mech.drive.joint
    if machine.shaft is not None:
        target = ROTOR
        pivot = mech.points[mech.revolute(mech.drive.joint).point]
        body = etree.SubElement(root.find("worldbody"), "body", name=ROTOR, pos=f"{_f(pivot[0])} {_f(pivot[1])} 0")
        etree.SubElement(body, "inertial", pos="0 0 0", mass="1", diaginertia="1e-6 1e-6 1e-6")
        etree.SubElement(body, "joint", name=ROTOR, type="hinge", axis="0 0 1",
                         armature=_f(machine.rotor_inertia * machine.gear_ratio**2))
        s = machine.shaft
        tendon = root.find("tendon") if root.find("tendon") is not None else etree.SubElement(root, "tendon")
        fixed = etree.SubElement(tendon, "fixed", name=SHAFT, stiffness=_f(s.stiffness), damping=_f(s.damping),
                                 springlength=f"{_f(-s.backlash / 2)} {_f(s.backlash / 2)}")
        etree.SubElement(fixed, "joint", joint=ROTOR, coef="1")
        etree.SubElement(fixed, "joint", joint=mech.drive.joint, coef="-1")
    _motor(actuator, target, machine)
    _start_key(root, asm, machine)
    notes = (["no motor: machine:motor exerts no torque (free motion under the loads)"] if machine.free else
             ["the motor is machine:motor"])
    if machine.motor.kind == "induction":
        notes.append("an induction motor's Kloss torque has no MuJoCo element: set machine:motor's control to "
                     "the motor-shaft torque each step")
    if machine.process_load is not None:
        notes.append("the process load (a torque on the crank over its angle) is applied by linkgen each step")
    if mech.forces or mech.torques:
        notes.append("the mechanism's [[force]]/[[torque]] loads are applied by linkgen each step (xfrc_applied)")
    if machine.schedule is not None:
        s = machine.schedule
        notes.append(f"the motor runs only from t = {s.motor_on:g} s" + (f" to {s.motor_off:g} s" if math.isfinite(
            s.motor_off) else "") + ": MuJoCo has no switch; linkgen scales machine:motor by the share of each step it "
            "runs (set its bias, or its control, to 0 outside)")
    if machine.brake is not None:
        b = machine.brake
        when = f"t = {b.from_time:g} s" if b.from_time is not None else f"a crank angle of {b.from_angle:g} rad"
        law = (f"{b.value:g} N·m against the crank's motion" if b.kind == "constant" else
               f"{b.value:g} N·m·s/rad times the crank's speed, against it")
        notes.append(f"the brake, {law} from {when}, is no MuJoCo element: linkgen applies it on the crank each "
                     "step (qfrc_applied)")
    root.insert(0, etree.Comment(" machine: " + "; ".join(notes) + ". Keyframe 'start' is the machine at t = 0. "))
    return etree.tostring(root, encoding="unicode", pretty_print=True)


def _motor(actuator, joint: str, machine: Machine) -> None:
    m, u, eta = machine.motor, machine.gear_ratio, machine.gear_efficiency
    if m.kind == "dc":
        a, c = dc_scales(machine)
        lag = {"inductance": _f(m.inductance)} if m.inductance > 0 else {}
        actuator.append(etree.Comment(
            f" machine:motor is the DC motor in MuJoCo's dcmotor, whose one motor constant serves torque and "
            f"back-EMF alike: with k_t = {m.torque_constant:g} N·m/A (times the gearbox efficiency {eta:g}) and "
            f"k_e = {m.emf_constant:g} V·s/rad it runs at motor constant 1 through gear {u:g}·{a:.6g}, its voltage "
            f"(the control) and current (the activation) being the motor's times {c:.6g} "))
        etree.SubElement(actuator, "dcmotor", name=MOTOR, joint=joint, gear=_f(u * a), motorconst="1 1",
                         resistance=_f(m.resistance), input="voltage", **lag)
    elif m.kind in ("linear", "constant", "none"):
        m0 = m.stall_torque if m.kind == "linear" else m.torque if m.kind == "constant" else 0.0
        slope = -u * u * eta * m.stall_torque / m.no_load_speed if m.kind == "linear" else 0.0
        etree.SubElement(actuator, "general", name=MOTOR, joint=joint, gainprm="0", biastype="affine",
                         biasprm=f"{_f(u * eta * m0)} 0 {_f(slope)}")
    else:
        etree.SubElement(actuator, "motor", name=MOTOR, joint=joint, gear=_f(u * eta))


def dc_scales(machine: Machine) -> tuple[float, float]:
    """(a, c) that put a DC motor with k_t ≠ k_e into MuJoCo's dcmotor (one constant K = 1): the
    actuator's gear is u·a and its voltage and current are the motor's times c, with
    a·c = η·k_t (torque) and a/c = k_e (back-EMF), so a = √(η·k_t·k_e), c = √(η·k_t/k_e)."""
    m, eta = machine.motor, machine.gear_efficiency
    return math.sqrt(eta * m.torque_constant * m.emf_constant), math.sqrt(eta * m.torque_constant / m.emf_constant)


@no_log_file()  # MuJoCo's warnings stay out of the user's folder (linkgen.mujoco.log)
def _start_key(root, asm: Assembly, machine: Machine) -> None:
    from linkgen.mujoco.state import initial_state

    for key in root.iter("key"):
        if key.get("name") == KEY:
            key.getparent().remove(key)
    try:
        model = mujoco.MjModel.from_xml_string(etree.tostring(root, encoding="unicode"))
    except ValueError:
        return
    qpos, qvel = initial_state(asm, model, machine.start(asm.mechanism.drive.start), machine.start_speed)
    crank = model.joint(asm.mechanism.drive.joint)
    if machine.shaft is not None:
        rotor = model.joint(ROTOR)
        qpos[rotor.qposadr[0]], qvel[rotor.dofadr[0]] = qpos[crank.qposadr[0]], qvel[crank.dofadr[0]]
    attrs = {"name": START_KEY, "qpos": " ".join(_f(x) for x in qpos), "qvel": " ".join(_f(x) for x in qvel)}
    if model.nu:
        ctrl = np.zeros(model.nu)
        if machine.motor.kind == "dc":
            ctrl[model.actuator(MOTOR).id] = dc_scales(machine)[1] * machine.motor.voltage
        attrs["ctrl"] = " ".join(_f(x) for x in ctrl)
    if model.na:
        mot = machine.motor
        i0 = float(motors.dc_static_current(mot, machine.gear_ratio * machine.start_speed)) \
            if machine.start_speed != 0 else 0.0
        attrs["act"] = " ".join(_f(x) for x in np.full(model.na, dc_scales(machine)[1] * i0))
    keyframe = root.find("keyframe") if root.find("keyframe") is not None else etree.SubElement(root, "keyframe")
    etree.SubElement(keyframe, "key", **attrs)


def run_native(asm: Assembly, machine: Machine, t: np.ndarray, timestep: float | None = None):
    """Run ``machine_mjcf``'s model from its keyframe ``start`` with MuJoCo's own motor element
    (what a user of the file gets), applying only what has no element each step at the step's
    mid-point (the process load, the mechanism's loads, a Kloss torque); sample at times ``t``
    (n,) [s] as ``mujoco.machine.run_machine_mujoco`` does; ``timestep`` [s] replaces the file's."""
    from linkgen.machine.reduced import process_torque_function
    from linkgen.mujoco.forces import has_loads
    from linkgen.mujoco.log import no_log_file
    from linkgen.mujoco.machine import MujocoMachineRun, _LoadTable

    mech = asm.mechanism
    model = mujoco.MjModel.from_xml_string(machine_mjcf(asm, machine))
    if timestep is not None:
        model.opt.timestep = timestep
    data = mujoco.MjData(model)
    mujoco.mj_resetDataKeyframe(model, data, model.key(START_KEY).id)
    mot, u, eta = machine.motor, machine.gear_ratio, machine.gear_efficiency
    crank, adr = model.joint(mech.drive.joint).dofadr[0], model.joint(mech.drive.joint).qposadr[0]
    shaft = machine.shaft is not None
    dof = model.joint(ROTOR).dofadr[0] if shaft else crank
    rotor_adr = model.joint(ROTOR).qposadr[0] if shaft else None
    act = model.actuator(MOTOR).id
    load = process_torque_function(machine.process_load)
    table = _LoadTable(asm, model) if has_loads(asm) else None
    dt = model.opt.timestep
    t = np.asarray(t, dtype=float)
    out = {k: np.empty_like(t) for k in ("t", "phi", "w", "m", "twist")}
    phi_c, q_prev, k, steps = machine.start(mech.drive.start), float(data.qpos[adr]), 0, 0

    def shaft_torque(w_motor: float) -> float:
        if mot.kind == "dc":
            i = float(data.act[model.actuator_actadr[act]]) / dc_scales(machine)[1] if model.na else \
                float(motors.dc_static_current(mot, w_motor))
            return mot.torque_constant * i
        return float(motors.torque(mot, w_motor))

    with no_log_file():
        while k < t.size:
            while k < t.size and t[k] <= data.time + 0.5 * dt:
                out["t"][k], out["phi"][k], out["w"][k] = data.time, phi_c, float(data.qvel[crank])
                out["m"][k] = shaft_torque(u * float(data.qvel[dof]))
                out["twist"][k] = float(data.qpos[rotor_adr] - data.qpos[adr]) if shaft else 0.0
                k += 1
            if k >= t.size:
                break
            w_c = float(data.qvel[crank])
            mid = phi_c + 0.5 * dt * w_c
            data.qfrc_applied[:] = 0.0
            data.qfrc_applied[crank] = -float(load(mid))
            if table is not None:
                sweep = dt * w_c + (0.5 * dt * dt * float(data.qacc[crank]) if steps else 0.0)
                data.xfrc_applied[:] = table.over(phi_c, phi_c + sweep)
            if mot.kind == "induction":
                w_mid = float(data.qvel[dof]) + (0.5 * dt * float(data.qacc[dof]) if steps else 0.0)
                data.ctrl[act] = float(motors.torque(mot, u * w_mid))
            mujoco.mj_step(model, data)
            steps += 1
            q = float(data.qpos[adr])
            phi_c += (q - q_prev + math.pi) % (2 * math.pi) - math.pi
            q_prev = q
    return MujocoMachineRun(out["t"], out["phi"], out["w"], out["m"], steps, dt, out["twist"] if shaft else None)


__all__ = ["MOTOR", "ROTOR", "SHAFT", "START_KEY", "machine_mjcf", "machine_settings", "dc_scales", "run_native"]
