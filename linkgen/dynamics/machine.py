"""The real motion of a machine: the mechanism reduced to its crank, driven by a motor.

One-mass machine (rigid shaft), φ and ω the crank's angle and speed:

    (J(φ) + J_add)·ω̇ + ½·J′(φ)·ω² = M(φ) + u·η·M_m(u·ω[, i]),

J_add = J_rotor·u² + J_flywheel (u the gear ratio, η its efficiency), M the reduced moment of the
loads (gravity, forces, torques, the process load). With an elastic shaft the rotor (angle θ and
speed ω_r, reduced to the crank) is a second mass:

    J_rotor·u²·ω̇_r = u·η·M_m(u·ω_r) − T,   (J(φ) + J_flywheel)·ω̇ + ½·J′·ω² = M(φ) + T,
    T = c·dz(θ − φ) + b·(ω_r − ω),  dz the dead zone of the backlash.

A DC motor with inductance adds its current i (``motors.dc_current_rate``). Integrated by scipy's
``solve_ivp`` (DOP853; Radau when a current or a shaft makes it stiff) from the start speed to
``duration``; the steady cycle is the first turn whose ω(φ) repeats the previous turn's to
STEADY_TOL of the mean speed.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from linkgen.dynamics import motors
from linkgen.dynamics.reduced import Reduced
from linkgen.errors import SimulationError
from linkgen.model.machine import Machine

# Relative tolerance of the integration; the absolute one is this times the state's scale.
RTOL = 1e-10
# Two successive turns are the same cycle when ω(φ) differs by less than this fraction of the
# mean speed at every one of CYCLE_POINTS crank angles (100× the integration's tolerance).
STEADY_TOL = 1e-8
CYCLE_POINTS = 256
# The start-up ends where ω enters, for good, the steady cycle's band widened by this fraction
# of the mean speed.
STARTUP_BAND = 0.01


@dataclass(frozen=True)
class SteadyCycle:
    """One steady turn: start time [s], period [s], mean speed 2π/period, ω_min, ω_max [rad/s],
    δ = (ω_max − ω_min)/ω_mean."""

    t_start: float
    period: float
    omega_mean: float
    omega_min: float
    omega_max: float

    @property
    def delta(self) -> float:
        return (self.omega_max - self.omega_min) / self.omega_mean

    def to_json(self) -> dict:
        return {"t_start": self.t_start, "period": self.period, "omega_mean": self.omega_mean,
                "omega_min": self.omega_min, "omega_max": self.omega_max, "delta": self.delta}


@dataclass(frozen=True)
class MachineRun:
    """Samples (n,) of time t [s], crank angle φ [rad], speed ω [rad/s], acceleration ε [rad/s²],
    motor torque [N·m] on the motor shaft, current [A] (DC motor, else None), shaft twist θ − φ
    [rad] and shaft torque [N·m] (elastic shaft, else None); the steady cycle (None if not
    reached within the duration) and the start-up time [s]."""

    t: np.ndarray
    phi: np.ndarray
    omega: np.ndarray
    epsilon: np.ndarray
    motor_torque: np.ndarray
    current: np.ndarray | None
    twist: np.ndarray | None
    shaft_torque: np.ndarray | None
    steady: SteadyCycle | None
    startup_time: float | None
    solution: object = field(default=None, repr=False, compare=False)  # dense output, t → state
    rate: object = field(default=None, repr=False, compare=False)  # the ODE's right-hand side, (t, y) → dy/dt

    def state_at(self, t) -> tuple[np.ndarray, np.ndarray]:
        """Crank angle [rad] and speed [rad/s] at times t [s] from the solver's dense output."""
        y = self.solution(np.asarray(t, dtype=float))
        return y[0], y[1]


class _Model:
    """The right-hand side, state layout [φ, ω, (θ, ω_r), (i)]."""

    def __init__(self, machine: Machine, red: Reduced):
        self.m, self.red = machine, red
        self.u, self.eta = machine.gear_ratio, machine.gear_efficiency
        self.shaft = machine.shaft
        self.current = motors.has_current(machine.motor)
        self.n = 2 + (2 if self.shaft else 0) + (1 if self.current else 0)

    def motor(self, omega_rotor, y):
        """Motor torque on its shaft and its current (or None), from the rotor speed at the crank."""
        w_m = self.u * omega_rotor
        mot = self.m.motor
        if self.current:
            i = y[-1]
            return motors.torque(mot, w_m, i), i
        if mot.kind == "dc":
            i = motors.dc_static_current(mot, w_m)
            return motors.torque(mot, w_m, i), i
        return motors.torque(mot, w_m), None

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
        mm, i = self.motor(w_rotor, y)
        drive = self.u * self.eta * mm
        if self.shaft:
            ts = self.shaft_torque(y)
            dy[1] = (red.moment(phi) + ts - 0.5 * red.dj(phi) * w * w) / (red.j(phi) + self.m.flywheel_inertia)
            dy[2] = y[3]
            jr = self.m.rotor_inertia * self.u**2
            if not jr > 0:
                raise SimulationError("an elastic shaft needs a rotor inertia > 0 ([machine] rotor_inertia)")
            dy[3] = (drive - ts) / jr
        else:
            dy[1] = (red.moment(phi) + drive - 0.5 * red.dj(phi) * w * w) / (red.j(phi) + self.m.added_inertia)
        if self.current:
            dy[-1] = motors.dc_current_rate(self.m.motor, self.u * w_rotor, i)
        return dy

    def y0(self, phi0: float) -> np.ndarray:
        w0 = self.m.start_speed
        y = [phi0, w0] + ([phi0, w0] if self.shaft else [])
        if self.current:
            y.append(float(motors.dc_static_current(self.m.motor, self.u * w0)) if w0 > 0 else 0.0)
        return np.array(y, dtype=float)


def motor_torque_at(machine: Machine, red: Reduced, y: np.ndarray) -> np.ndarray:
    """The motor torque [N·m] on the motor shaft at ODE states ``y`` (k, n) (``MachineRun.solution``)."""
    model = _Model(machine, red)
    w_rotor = y[3] if model.shaft else y[1]
    mm, _ = model.motor(w_rotor, y)
    return np.asarray(mm, dtype=float) * np.ones(y.shape[1])


def run_machine(machine: Machine, red: Reduced, *, samples: int = 2000, duration: float | None = None) -> MachineRun:
    """Integrate the machine from its start speed over ``duration`` [s] (default the
    description's) and sample it at ``samples`` equal time steps (the steady cycle and the
    start-up come from the solver's dense output, not from the samples)."""
    model = _Model(machine, red)
    T = machine.duration if duration is None else float(duration)
    phi0 = float(red.phi[0])
    stiff = model.current or model.shaft is not None
    scale = np.ones(model.n)
    sol = solve_ivp(model.rhs, (0.0, T), model.y0(phi0), method="Radau" if stiff else "DOP853", rtol=RTOL,
                    atol=RTOL * scale * 1e-3, dense_output=True)
    if not sol.success:
        raise SimulationError(f"the machine's integration stopped at t = {sol.t[-1]:.6g} s: {sol.message}")
    t = np.linspace(0.0, T, samples)
    y = sol.sol(t)
    eps = np.array([model.rhs(tk, y[:, k])[1] for k, tk in enumerate(t)])
    w_rotor = y[3] if model.shaft else y[1]
    mm, cur = model.motor(w_rotor, y)
    twist = (y[2] - y[0]) if model.shaft else None
    ts = model.shaft_torque(y) if model.shaft else None
    steady = steady_cycle(sol, phi0)
    startup = None
    if steady is not None:
        band = STARTUP_BAND * steady.omega_mean
        out = np.flatnonzero((y[1] < steady.omega_min - band) | (y[1] > steady.omega_max + band))
        startup = 0.0 if out.size == 0 else (float(t[out[-1] + 1]) if out[-1] + 1 < t.size else None)
    return MachineRun(t, y[0], y[1], eps, np.asarray(mm, dtype=float) * np.ones_like(t),
                      None if cur is None else np.asarray(cur, dtype=float) * np.ones_like(t), twist, ts, steady,
                      startup, sol.sol, model.rhs)


def speed_range(solution, a: float, b: float, *, periodic: bool, n: int = 64 * CYCLE_POINTS) -> tuple[float, float]:
    """ω_min and ω_max [rad/s] of the dense output ``solution`` (t → state) over times [a, b]
    (a cycle, if ``periodic``): n samples, each extreme refined between them (``linkgen.extrema``)."""
    from linkgen.extrema import peak, samples

    t = samples(a, b, n, periodic)
    w = solution(t)[1]
    period = (b - a) if periodic else None
    speed = lambda tt: solution(tt)[1]  # noqa: E731
    return peak(speed, t, w, kind="min", period=period)[1], peak(speed, t, w, period=period)[1]


def _turn_times(sol, phi0: float) -> np.ndarray:
    """Times [s] at which the crank has turned by 2π·k from φ0 (k = 1, 2, …), from the dense
    output (root of φ(t) − φ0 − 2πk by bisection between the solver's steps)."""
    turns = (sol.y[0] - phi0) / (2 * math.pi)
    out = []
    for k in range(1, int(math.floor(turns.max())) + 1):
        j = int(np.argmax(turns >= k))
        a, b = sol.t[j - 1], sol.t[j]
        for _ in range(100):
            mid = 0.5 * (a + b)
            if (sol.sol(mid)[0] - phi0) / (2 * math.pi) >= k:
                b = mid
            else:
                a = mid
        out.append(0.5 * (a + b))
    return np.array(out)


def steady_cycle(sol, phi0: float) -> SteadyCycle | None:
    """The first turn whose ω(φ) repeats the previous turn's (STEADY_TOL), or None."""
    times = _turn_times(sol, phi0)
    prev = None
    for k in range(len(times) - 1):
        a, b = times[k], times[k + 1]
        ts = np.linspace(a, b, 8 * CYCLE_POINTS)
        y = sol.sol(ts)
        grid = phi0 + 2 * math.pi * (k + 1) + np.linspace(0.0, 2 * math.pi, CYCLE_POINTS, endpoint=False)
        w = np.interp(grid, y[0], y[1])
        if prev is not None:
            mean = 2 * math.pi / (b - a)
            if np.abs(w - prev).max() <= STEADY_TOL * mean:
                low, high = speed_range(sol.sol, a, b, periodic=True)
                return SteadyCycle(float(a), float(b - a), mean, low, high)
        prev = w
    return None


__all__ = ["MachineRun", "RTOL", "STEADY_TOL", "SteadyCycle", "run_machine", "speed_range", "steady_cycle"]
