"""The machine's equation as an ODE's right-hand side (``Model``: the state [φ, ω, (θ, ω_r), (i)]
and its rate, module ``machine``'s docstring gives the equations), the motor's torque at its
states, and the integrator the equation needs (``choose_method``: explicit unless stiff)."""

from __future__ import annotations

import math

import numpy as np

from linkgen.errors import SimulationError
from linkgen.machine import motors
from linkgen.machine.reduced import Reduced
from linkgen.machine.schedule import Switching
from linkgen.model.machine import Machine

# The integrator: DOP853 unless a current or a shaft is present (Radau, as validated) or the
# machine's fastest time constant τ would hold an explicit method to steps far shorter than a
# turn needs for accuracy: its stability bound is a step of about 3τ, so beyond STIFF_STEPS
# such steps per turn at the top speed the implicit Radau takes over (whose step follows the
# accuracy alone). DOP853 takes some hundreds to a few thousand steps per turn at RTOL.
STIFF_STEPS = 1000
# A time constant shorter than this fraction of the duration cannot be resolved at all: a step
# of τ at t = duration would be below the spacing of float64 numbers (2.2e-16 of t) times 1e3.
RESOLVABLE = 1e3 * np.finfo(float).eps


class Model:
    """The right-hand side, state layout [φ, ω, (θ, ω_r), (i)]."""

    def __init__(self, machine: Machine, red: Reduced):
        self.m, self.red = machine, red
        self.u, self.eta = machine.gear_ratio, machine.gear_efficiency
        self.shaft = machine.shaft
        self.current = motors.has_current(machine.motor)
        self.n = 2 + (2 if self.shaft else 0) + (1 if self.current else 0)
        # the motor's schedule and the brake (machine.schedule); ``phase`` (k, braking) fixed while
        # a piece between switches is integrated, None: both from the time
        self.switching, self.phase = Switching.of(machine), None

    def _switched(self, t):
        """(k, braking) at times t: the motor's factor and whether the brake acts."""
        if self.phase is not None:
            return self.phase
        if t is None:
            return 1.0, False
        return self.switching.motor(t), self.switching.braking(t)

    def motor(self, omega_rotor, y, t=None):
        """Motor torque on its shaft and its current (or None), from the rotor speed at the crank;
        at times ``t``, zero where the schedule has the motor off (None: on)."""
        w_m = self.u * omega_rotor
        mot = self.m.motor
        k = self._switched(t)[0]
        if self.current:
            i = y[-1]
            return motors.torque(mot, w_m, i) * k, i * k
        if mot.kind == "dc":
            i = motors.dc_static_current(mot, w_m) * k
            return motors.torque(mot, w_m, i), i
        return motors.torque(mot, w_m) * k, None

    def brake(self, t, w):
        """The brake's moment on the crank [N·m] at times t and speeds w (0 before it is applied)."""
        return self.switching.brake(self._switched(t)[1], w)

    def shaft_torque(self, y):
        s = self.shaft
        twist = y[2] - y[0]
        half = 0.5 * s.backlash
        spring = np.where(twist > half, twist - half, np.where(twist < -half, twist + half, 0.0))
        return s.stiffness * spring + s.damping * (y[3] - y[1])

    def rhs(self, t, y):
        phi, w = y[0], y[1]
        red = self.red
        dy = np.empty_like(y)
        dy[0] = w
        w_rotor = y[3] if self.shaft else w
        mm, i = self.motor(w_rotor, y, t)
        drive = self.u * self.eta * mm
        braked = self.brake(t, w)
        if self.shaft:
            ts = self.shaft_torque(y)
            dy[1] = self.crank_rate(t, phi, w, red.moment(phi, w) + ts + braked - 0.5 * red.dj(phi) * w * w,
                                    red.j(phi) + self.m.flywheel_inertia)
            dy[2] = y[3]
            jr = self.m.rotor_inertia * self.u**2
            if not jr > 0:
                raise SimulationError("an elastic shaft needs a rotor inertia > 0 ([machine] rotor_inertia)")
            dy[3] = (drive - ts) / jr
        else:
            dy[1] = self.crank_rate(t, phi, w, red.moment(phi, w) + drive + braked - 0.5 * red.dj(phi) * w * w,
                                    red.j(phi) + self.m.added_inertia)
        if self.current:
            dy[-1] = motors.dc_current_rate(self.m.motor, self.u * w_rotor, i) * self._switched(t)[0]
        return dy

    def crank_rate(self, t, phi, w, free, inertia):
        """ε from the frictionless right-hand side ``free`` [N·m] and the crank's inertia; with
        friction in the pairs, the solution of the equation with its moment (``machine.friction``)."""
        if self.red.friction is None:
            return free / inertia
        return self.friction_terms(t, phi, w, free, inertia)[0]

    def friction_terms(self, t, phi, w, free, inertia):
        """(ε, the friction's reduced moment s·M_f [N·m]) at the states, shaped as ``phi``."""
        from linkgen.machine.friction import acceleration

        shape = np.shape(phi)
        eps, mf = acceleration(self.red.friction, np.ravel(phi), np.ravel(w), np.ravel(free * np.ones(shape)),
                               np.ravel(inertia * np.ones(shape)), None if t is None else np.ravel(t * np.ones(shape)))
        return (eps.reshape(shape), mf.reshape(shape)) if shape else (float(eps[0]), float(mf[0]))

    def friction_moment(self, y, t=None):
        """s·M_f [N·m] (the friction's reduced moment, ≥ 0 times sgn ω) at states y (n, k) (at times t)."""
        phi, w = y[0], y[1]
        red = self.red
        if self.shaft:
            free = red.moment(phi, w) + self.shaft_torque(y) - 0.5 * red.dj(phi) * w * w
            inertia = red.j(phi) + self.m.flywheel_inertia
        else:
            mm, _ = self.motor(w, y, t)
            free = (red.moment(phi, w) + self.u * self.eta * mm - 0.5 * red.dj(phi) * w * w
                    + (self.brake(t, w) if t is not None else 0.0))
            inertia = red.j(phi) + self.m.added_inertia
        return self.friction_terms(None, phi, w, free, inertia)[1]

    def y0(self, phi0: float) -> np.ndarray:
        w0 = self.m.start_speed
        y = [phi0, w0] + ([phi0, w0] if self.shaft else [])
        if self.current:  # no current while the schedule has the motor off
            on = w0 != 0 and self.switching.motor(0.0) > 0
            y.append(float(motors.dc_static_current(self.m.motor, self.u * w0)) if on else 0.0)
        return np.array(y, dtype=float)


def motor_torque_at(machine: Machine, red: Reduced, y: np.ndarray, t=None) -> np.ndarray:
    """The motor torque [N·m] on the motor shaft at ODE states ``y`` (k, n) (``MachineRun.solution``),
    at times ``t`` [s] (zero where the schedule has the motor off; None: as if on)."""
    model = Model(machine, red)
    w_rotor = y[3] if model.shaft else y[1]
    mm, _ = model.motor(w_rotor, y, t)
    return np.asarray(mm, dtype=float) * np.ones(y.shape[1])



def _jacobian_radius(model: Model, y: np.ndarray) -> float:
    """The largest |eigenvalue| [1/s] of the right-hand side's Jacobian at state y (central
    differences); inf where the machine's rates leave float range."""
    n = y.size
    jac = np.empty((n, n))
    with np.errstate(all="ignore"):
        for j in range(n):
            h = 1e-6 * max(1.0, abs(y[j]))
            a, b = y.copy(), y.copy()
            a[j] -= h
            b[j] += h
            jac[:, j] = (model.rhs(0.0, b) - model.rhs(0.0, a)) / (2 * h)
    if not np.isfinite(jac).all():
        return math.inf
    return float(np.abs(np.linalg.eigvals(jac)).max())


def speed_scale(machine: Machine, red: Reduced) -> float:
    """The crank speed [rad/s] the machine runs at, at most: the motor's no-load or synchronous
    speed, or the start speed; without a motor also the speed the loads' work over a turn can
    give from the start (½·J_min·ω² = ½·J(φ0)·ω0² + max ∫M₀dφ, springs and gravity swinging
    the mechanism); the drive's prescribed speed only where none of these gives one (a constant
    torque from rest)."""
    top = machine.top_speed(0.0)
    if machine.free:
        phi0 = machine.start(float(red.phi[0]))
        table = red.table("moment_grid")
        work = table.integral(red.moment_phi) - table.integral(phi0)
        j = red.j(red.phi) + machine.added_inertia
        energy = float(red.j(phi0) + machine.added_inertia) * machine.start_speed**2 + 2 * max(float(work.max()), 0.0)
        top = max(top, math.sqrt(energy / float(j.min())) if j.min() > 0 else 0.0)
    return top if top > 0 else abs(red.drive_omega)


def choose_method(machine: Machine, red: Reduced, duration: float) -> tuple[str, float]:
    """The integrator (see STIFF_STEPS) and the machine's fastest time constant τ [s] (1/the
    largest |eigenvalue| of the Jacobian at the start and at the top speed); SimulationError if τ
    is beyond what any step can resolve over the duration (RESOLVABLE) or the rates leave float
    range."""
    model = Model(machine, red)
    model.phase = (1.0, True)  # the motor on and a viscous brake applied: every time constant there is
    y0 = model.y0(machine.start(float(red.phi[0])))
    if model.current:
        y0[-1] = float(motors.dc_static_current(machine.motor, machine.gear_ratio * y0[1])) if y0[1] != 0 else 0.0
    top = speed_scale(machine, red)
    states = [y0]
    if model.current:  # at rest with the stall current U/R: the largest current and torque
        stall = y0.copy()
        stall[1:-1] = 0.0
        stall[-1] = float(motors.dc_static_current(machine.motor, 0.0))
        states.append(stall)
    if top > 0 and math.isfinite(top):
        y1 = y0.copy()
        y1[1] = top
        if model.shaft:
            y1[3] = top
        if model.current:
            y1[-1] = float(motors.dc_static_current(machine.motor, machine.gear_ratio * top))
        states.append(y1)
    with np.errstate(all="ignore"):
        finite = all(np.isfinite(model.rhs(0.0, y)).all() for y in states)
    radius = max(_jacobian_radius(model, y) for y in states) if finite else math.inf
    tau = 1.0 / radius if radius > 0 else math.inf
    if not tau > RESOLVABLE * duration:
        what = ("its accelerations leave the range of float64 numbers" if not math.isfinite(radius) else
                f"its fastest time constant is {tau:.3g} s, {tau / duration:.2g} of the duration of {duration:g} s, "
                f"finer than any step can resolve")
        raise SimulationError(f"the machine cannot be integrated: {what}; check the [machine.motor] parameters "
                              f"({', '.join(f'{k} = {v:g}' for k, v in machine.motor.params)}), the gear ratio, "
                              "the inertias, the loads" + (" and the duration" if math.isfinite(radius) else ""))
    scale = min(duration, 2 * math.pi / top) if top > 0 else duration
    stiff = model.current or model.shaft is not None or scale / (3 * tau) > STIFF_STEPS
    return ("Radau" if stiff else "DOP853"), tau


__all__ = ["Model", "RESOLVABLE", "STIFF_STEPS", "choose_method", "motor_torque_at", "speed_scale"]
