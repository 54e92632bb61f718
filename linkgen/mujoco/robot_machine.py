"""What the robot build's header says of a description's [machine] (``robot.RobotOptions.machine``):
its rotor and flywheel are the driven joint's armature, the rest is not in the file and the header
tells how to apply it, "{P}" standing for the names' prefix:

    * the motor law (constant, linear, induction (Kloss), DC with its current) as the motor
      actuator's control each step, through the gear ratio and efficiency;
    * the process load, a resisting torque tabulated over the crank angle, as a joint torque on
      the driven joint through ``data.qfrc_applied``;
    * an elastic shaft: the file lumps the rotor rigidly onto the crank (its stiffness and damping
      named, with how to keep it);
    * the start speed, as the driven joint's velocity at the start."""

from __future__ import annotations

import math


def machine_loads(machine, joint: str, gear: float) -> tuple[str, ...]:
    """How to apply what ``machine`` (a ``linkgen.model.machine.Machine``, or None) has that MJCF
    does not carry, on the driven joint ``joint`` (its name without the prefix) whose motor
    actuator has the gear ``gear``."""
    if machine is None:
        return ()
    u, eta = machine.gear_ratio, machine.gear_efficiency
    speed = f"data.qvel[model.joint('{{P}}{joint}').dofadr[0]]"
    angle = f"data.qpos[model.joint('{{P}}{joint}').qposadr[0]]"
    out = [f"[machine.motor] the {machine.motor.kind} motor law through the gear ratio u = {u:g} of efficiency "
           f"η = {eta:g}: each step (with the motor actuator, the build's default) set "
           f"data.ctrl[model.actuator('{{P}}drive:motor').id] = u·η·M_m(u·ω)/{gear:g}, ω = {speed}, "
           f"{_law(machine.motor)}; the actuator's ctrlrange, from the closed form's duty, clips a larger torque: "
           "widen it to the motor's"]
    if machine.process_load is not None:
        load = machine.process_load
        out.append(f"[machine.process_load] a torque resisting the crank tabulated at {len(load.angles)} crank angles "
                   f"over a turn ({min(load.torque):g} to {max(load.torque):g} N·m, periodic; linkgen interpolates it by "
                   f"a periodic cubic spline): each step data.qfrc_applied[model.joint('{{P}}{joint}').dofadr[0]] -= "
                   f"the table at φ = {angle}")
    if machine.shaft is not None:
        s = machine.shaft
        rotor = machine.rotor_inertia * u**2
        backlash = f", backlash {s.backlash:g} rad" if s.backlash else ""
        out.append(f"[machine.shaft] the elastic shaft between the rotor and the crank (stiffness {s.stiffness:g} N·m/rad, "
                   f"damping {s.damping:g} N·m·s/rad{backlash}): the file lumps the rotor ({rotor:g} kg·m² at the crank) "
                   f"rigidly onto the crank, with the flywheel, as the driven joint's armature, so the shaft's twist "
                   f"and its torsion mode (about {_shaft_hz(machine):.3g} Hz) are absent; to keep them, give the rotor a "
                   "hinge of its own on the mount, the motor's actuator on it, and tie it to the crank by a fixed "
                   "tendon of the two joints (coefficients 1, −1) with that stiffness and damping")
    if machine.start_speed:
        out.append(f"[machine] start_speed {machine.start_speed:g} rad/s: set {speed} to it at the start (the "
                   "keyframe is at rest)")
    return tuple(out)


def _law(m) -> str:
    """The motor torque M_m [N·m] at the motor shaft's speed ω_m = u·ω, in numbers."""
    from linkgen.machine.motors import kloss_constants

    if m.kind == "constant":
        return f"M_m = {m.torque:g} N·m"
    if m.kind == "linear":
        return f"M_m = {m.stall_torque:g}·(1 − ω_m/{m.no_load_speed:g}) N·m"
    if m.kind == "induction":
        mk, sk = kloss_constants(m)
        return (f"M_m by Kloss's formula 2·M_k·s·s_k/(s² + s_k²), s = ({m.synchronous_speed:.6g} − ω_m)/"
                f"{m.synchronous_speed:.6g}, M_k = {mk:.6g} N·m, s_k = {sk:.6g}")
    if m.kind == "dc" and m.inductance == 0:
        return (f"M_m = {m.torque_constant:g}·i N·m, i = ({m.voltage:g} − {m.emf_constant:g}·ω_m)/{m.resistance:g} A")
    if m.kind == "dc":
        return (f"M_m = {m.torque_constant:g}·i N·m, the current i [A] integrated alongside: "
                f"{m.inductance:g}·di/dt = {m.voltage:g} − {m.resistance:g}·i − {m.emf_constant:g}·ω_m")
    return f"the {m.kind} law"


def _shaft_hz(machine) -> float:
    """The torsion mode of the rotor on the shaft against a held crank [Hz]."""
    rotor = machine.rotor_inertia * machine.gear_ratio**2
    return math.sqrt(machine.shaft.stiffness / rotor) / (2 * math.pi) if rotor > 0 else math.inf


__all__ = ["machine_loads"]
