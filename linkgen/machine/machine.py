"""The real motion of a machine: the mechanism reduced to its crank, driven by a motor.

One-mass machine (rigid shaft), φ and ω the crank's angle and speed:

    (J(φ) + J_add)·ω̇ + ½·J′(φ)·ω² = M(φ) + u·η·M_m(u·ω[, i]),

J_add = J_rotor·u² + J_flywheel (u the gear ratio, η its efficiency), M the reduced moment of the
loads (gravity, forces, torques, the process load). With an elastic shaft the rotor (angle θ and
speed ω_r, reduced to the crank) is a second mass:

    J_rotor·u²·ω̇_r = u·η·M_m(u·ω_r) − T,   (J(φ) + J_flywheel)·ω̇ + ½·J′·ω² = M(φ) + T,
    T = c·dz(θ − φ) + b·(ω_r − ω),  dz the dead zone of the backlash.

A DC motor with inductance adds its current i (``motors.dc_current_rate``). Integrated by scipy's
``solve_ivp`` from the start speed to ``duration``: DOP853, or Radau with a current or a shaft
or where the machine's time constants make it stiff (``choose_method``), in steps of at most a
64th of a turn; the steady cycle, the start-up and the peak motor torque are found on the dense
output (``dynamics.cycle``). The right-hand side and the choice of integrator are
``machine.equation``'s; the energy balance at every sample ``machine.energy``'s.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np
from scipy.integrate import solve_ivp

from linkgen.machine.cycle import CYCLE_POINTS, STEADY_TOL, SteadyCycle, peak, startup_time, steady_cycle
from linkgen.machine.energy import EnergyBalance, energy_balance
from linkgen.machine.equation import Model as _Model, choose_method, motor_torque_at, speed_scale as _speed_scale
from linkgen.machine.reduced import Reduced
from linkgen.machine.schedule import Stopping, Switching, integrate, stopping
from linkgen.errors import DescriptionError, SimulationError
from linkgen.model.machine import DEFAULT_RTOL, FREE, Machine

# Relative tolerance of the integration by default (``[machine] rtol`` sets it); the absolute one
# is 1e-3 of it on every state.
RTOL = DEFAULT_RTOL
# The solver's step is at most this fraction of a turn at the top speed: the load table M(φ) is
# linear between 4096+ angles, and a step over hundreds of its kinks has an error the solver's
# estimate does not see (dynamics.cycle).
STEPS_PER_TURN = 64
# Right-hand sides evaluated at most (about 100 µs each on a 5-body linkage: some minutes).
MAX_EVALUATIONS = 3_000_000
# A motor-driven crank whose speed passes RUNAWAY times the motor's top speed (its no-load or
# synchronous speed at the crank), either way round, is driven by its loads, not by its motor:
# far outside what the motor laws describe, and each turn then costs the integration steps
# without end (a fuzzed process load of 5.6e8 N·m on one table point ran past 150 s). Ten times
# leaves room for a load that drives the motor as a generator (a few per cent over its no-load
# speed) and for any start speed within it; a constant torque has no top speed and no such stop.
RUNAWAY = 10.0
# A crank that completes no new turn over STALL_EVALUATIONS evaluations of the right-hand side is
# stalled, rocking against a load its motor cannot carry it past: the run stops there and says
# where, rather than integrating the rocking for the rest of the duration (a fuzzed load spike of
# 5.6e8 N·m on one table point: 3 M evaluations over 188 s, no result). A turn costs 64 steps
# at most (STEPS_PER_TURN) of ~12 evaluations, ~800, once running; a slow first turn from rest
# is bounded in steps by the same max_step in time: 300 000 leaves it a factor of ~50 beyond
# a crank reaching only a hundredth of its speed scale.
STALL_EVALUATIONS = 300_000
# Progress is reported after this much wall time [s], then every PROGRESS_EVERY s.
PROGRESS_AFTER, PROGRESS_EVERY = 2.0, 2.0


@dataclass(frozen=True)
class MachineRun:
    """Samples (n,) of time t [s], crank angle φ [rad], speed ω [rad/s], acceleration ε [rad/s²],
    motor torque [N·m] on the motor shaft, current [A] (DC motor, else None), shaft twist θ − φ
    [rad] and shaft torque [N·m] (elastic shaft, else None); the steady cycle (None if not
    reached within the duration), the start-up time [s] and the largest |motor torque| [N·m]
    with its time [s] (both refined on the dense output between samples); the method used."""

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
    rate: object = field(default=None, repr=False, compare=False)  # the ODE's right-hand side (t, y) → dy/dt
    peak_motor_torque: float = math.nan
    peak_motor_torque_at: float = math.nan
    method: str = ""
    energy: EnergyBalance | None = field(default=None, repr=False, compare=False)  # checked at every sample
    rtol: float = RTOL  # the solver's relative tolerance (absolute: 1e-3 of it on the state)
    stopping: Stopping | None = None  # the motor's schedule, the brake and the rest (machine.schedule)

    def state_at(self, t) -> tuple[np.ndarray, np.ndarray]:
        """Crank angle [rad] and speed [rad/s] at times t [s] from the solver's dense output."""
        y = self.solution(np.asarray(t, dtype=float))
        return y[0], y[1]

    def acceleration_at(self, t) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """φ [rad], ω [rad/s] and the crank's ε [rad/s²] at times t [s]: ε is the ODE's own
        right-hand side at each state (right-continuous where a load jumps), not a difference."""
        t = np.atleast_1d(np.asarray(t, dtype=float))
        y = self.solution(t)
        return y[0], y[1], np.asarray(self.rate(t, y)[1], dtype=float)


class _Budget:
    """The right-hand side counted: SimulationError past MAX_EVALUATIONS, and progress(fraction,
    elapsed) every PROGRESS_EVERY s once the run has lasted PROGRESS_AFTER s."""

    def __init__(self, rhs, duration: float, progress, phi0: float = 0.0, stall: bool = True):
        self.rhs, self.duration, self.progress, self.stall = rhs, duration, progress, stall
        self.calls, self.t0, self.next, self.t = 0, time.perf_counter(), PROGRESS_AFTER, 0.0
        self.phi0, self.turns, self.turned_at = phi0, 0, 0  # the crank's turns done, and when

    def __call__(self, t, y):
        self.calls += 1
        self.t = t
        turns = abs(y[0] - self.phi0) / (2 * math.pi)  # either way round
        if not math.isfinite(turns):  # a trial state of the solver's own (a Jacobian's probe)
            pass
        elif turns >= self.turns + 1:
            self.turns, self.turned_at = int(turns), self.calls
        elif self.stall and self.calls - self.turned_at > STALL_EVALUATIONS:
            raise SimulationError(f"the machine stalls: the crank has completed no new turn over {STALL_EVALUATIONS:,} "
                                  f"evaluations, rocking near φ = {math.degrees(y[0]):.2f}° at t = {t:.6g} s; its motor "
                                  "(and the flywheel's energy) cannot carry it past the load there; check "
                                  "[machine.process_load], the mechanism's loads and the motor")
        if self.calls % 200 == 0:
            if self.calls > MAX_EVALUATIONS:
                raise SimulationError(f"the machine's integration took more than {MAX_EVALUATIONS:,} evaluations "
                                      f"and stopped at t = {t:.6g} s of {self.duration:g} s; give a shorter "
                                      "duration or check the [machine] parameters")
            elapsed = time.perf_counter() - self.t0
            if self.progress is not None and elapsed >= self.next:
                self.progress(min(t / self.duration, 1.0), elapsed)
                self.next = elapsed + PROGRESS_EVERY
        return self.rhs(t, y)


def run_machine(machine: Machine, red: Reduced, *, samples: int = 2000, duration: float | None = None,
                progress=None, rtol: float | None = None) -> MachineRun:
    """Integrate the machine from its start state (``Machine.start``, ``start_speed``) over
    ``duration`` [s] (default the description's), or until the crank has turned ``turns`` turns
    either way, and sample it at ``samples`` equal time steps (the steady cycle, the start-up and
    the peak motor torque come from the solver's dense output, not from the samples), at the
    relative tolerance ``rtol`` (default the description's ``[machine] rtol``; absolute: 1e-3 of
    it on the state). ``progress(fraction, elapsed seconds)`` is called during a long
    integration. The energy balance is checked at every sample (``MachineRun.energy``)."""
    model = _Model(machine, red)
    rtol = machine.rtol if rtol is None else float(rtol)
    T = machine.duration if duration is None else float(duration)
    phi0 = machine.start(float(red.phi[0]))
    lo, hi = float(red.phi[0]), red.stop
    if hi is not None and not lo <= phi0 <= hi:
        raise DescriptionError("machine.start_angle", f"is {math.degrees(phi0):.6g}°, outside the drive's range "
                               f"[{math.degrees(lo):.6g}°, {math.degrees(hi):.6g}°] (drive.range), where the "
                               "mechanism is known to assemble")
    method, _ = choose_method(machine, red, T)
    top = _speed_scale(machine, red)
    max_step = 2 * math.pi / top / STEPS_PER_TURN if top > 0 else math.inf
    scale = np.ones(model.n)
    # a crank coasting or rocking once its motor is off moves freely: no stall to catch there
    stall = not machine.free and machine.schedule is None and machine.brake is None
    budget = _Budget(model.rhs, T, progress, phi0, stall=stall)
    motor_top = machine.top_speed(0.0)
    # A constant torque has no top speed, nor has free motion: no runaway stop for either.
    limit = (RUNAWAY * motor_top if motor_top > 0 and math.isfinite(motor_top)
             and machine.motor.kind not in ("constant", FREE) else math.inf)

    def runaway(t, y):
        return limit - abs(y[1])

    runaway.terminal = True

    def turned(t, y):
        return 2 * math.pi * machine.turns - abs(y[0] - phi0)

    turned.terminal = True

    def left(t, y):  # a crank that does not turn fully: past its range the tables end
        return min(y[0] - lo, hi - y[0])

    left.terminal = True
    events = ([runaway] if math.isfinite(limit) else []) + ([turned] if machine.turns is not None else []) + \
        ([left] if hi is not None else [])

    held = []  # the time the brake held the crank at rest, if it did

    def solve(how: str):
        def one(t0, y0, more=(), t1=T):
            return solve_ivp(budget, (t0, t1), y0, method=how, rtol=rtol, atol=rtol * scale * 1e-3,
                             dense_output=True, max_step=max_step, events=(events + list(more)) or None)

        def piece(t0, t1, y0, extra):
            if red.friction is None or not red.friction.switches.size:
                return one(t0, y0, extra, t1)
            return _across_switches(lambda a, y, more=(): one(a, y, list(extra) + list(more), t1), y0,
                                    len(events) + len(extra), red.friction, t1, t0)

        with np.errstate(over="ignore", invalid="ignore"):
            if machine.schedule is not None or machine.brake is not None:
                model.switching = Switching.of(machine)
                parts, _, at = integrate(piece, model, model.y0(phi0), len(events), T,
                                         machine.brake.from_angle if machine.brake else None)
                held[:] = [at]
                return _Joined(parts, len(events))
            return piece(0.0, T, model.y0(phi0), ())

    try:
        try:
            sol = solve(method)
        except (ValueError, np.linalg.LinAlgError):
            # Radau's Newton matrix can turn non-finite on a state that has settled exactly (a DC
            # motor at twice the bundled voltage: a finite, steady ω = 12 rad/s, and scipy's
            # lu_factor refused the iteration matrix at t = 4.8 s): LSODA, which switches between
            # stiff and non-stiff steps itself, takes the run over from the start.
            if method != "Radau":
                raise
            budget = _Budget(model.rhs, T, progress, phi0, stall=stall)
            sol, method = solve("LSODA"), "LSODA"
    except (ValueError, np.linalg.LinAlgError) as exc:  # the solver's own check of its Jacobian or states
        raise SimulationError(f"the machine's state left float64's range near t = {budget.t:.6g} s ({exc}); check "
                              "the [machine.motor] parameters and the inertias") from None
    if sol.status == 1 and math.isfinite(limit) and sol.t_events[0].size:  # the runaway event
        t_run, w_run = float(sol.t_events[0][0]), float(sol.y_events[0][0][1])
        raise SimulationError(f"the crank's speed reached {w_run:.4g} rad/s at t = {t_run:.6g} s, {RUNAWAY:g} times the "
                              f"motor's top speed ({motor_top:.4g} rad/s at the crank){' turning backwards' if w_run < 0 else ''}: "
                              "the loads drive the machine, not its motor; check [machine.process_load] and the "
                              "mechanism's loads against the motor")
    if sol.status == 1 and hi is not None and sol.t_events[-1].size:  # left the drive's range
        t_out, at = float(sol.t_events[-1][0]), float(sol.y_events[-1][0][0])
        raise SimulationError(f"the crank left its range [{math.degrees(lo):.6g}°, {math.degrees(hi):.6g}°] "
                              f"(drive.range) at t = {t_out:.6g} s, φ = {math.degrees(at):.6g}°, moving at "
                              f"{float(sol.y_events[-1][0][1]):.6g} rad/s: the machine's motion is known only where "
                              "the mechanism assembles; widen drive.range if it assembles further, give a shorter "
                              "duration, or change the start state or the loads")
    if not sol.success or not np.isfinite(sol.y).all():
        raise SimulationError(f"the machine's integration stopped at t = {sol.t[-1]:.6g} s: {sol.message}")
    T = float(sol.t[-1])  # the duration, or when the crank completed its turns
    t = np.linspace(0.0, T, samples)
    y = sol.sol(t)
    eps = model.rhs(t, y)[1]
    w_rotor = y[3] if model.shaft else y[1]
    mm, cur = model.motor(w_rotor, y, t)
    twist = (y[2] - y[0]) if model.shaft else None
    ts = model.shaft_torque(y) if model.shaft else None
    steady = steady_cycle(sol, phi0, rtol)
    startup = None if steady is None else startup_time(sol, steady, T)
    top, top_at = peak(sol, lambda s, ts: motor_torque_at(machine, red, s, ts), T)
    stops = stopping(sol, model.switching, held[0], T) if held else None
    return MachineRun(t, y[0], y[1], np.asarray(eps, dtype=float), np.asarray(mm, dtype=float) * np.ones_like(t),
                      None if cur is None else np.asarray(cur, dtype=float) * np.ones_like(t), twist, ts, steady,
                      startup, sol.sol, model.rhs, top, top_at, method, energy_balance(model, sol.sol, sol.t, t), rtol,
                      stops)


def _across_switches(one, y0: np.ndarray, n: int, friction, T: float, t0: float = 0.0):
    """Integrate (``one(t0, y0, extra events)``: solve_ivp from t0) in pieces that end where the
    crank reaches a friction switch (``PairFriction.switches``, either way), each restarting
    there: the friction's jump is then a piece's end, not inside a step the solver would have to
    shrink around (ten turns of models/machine_friction.toml: the 10th turn's time agreed with a
    100× tighter run to 2.2e-8 stepped over, 6.2e-9 in pieces; the energy balance's worst
    residual 2.1e-8, 6.8e-9). From the time ``t0`` to T. Returns the pieces joined (``_Joined``)."""
    parts = []
    while True:
        ahead, behind = friction.neighbours(float(y0[0]))

        def up(t, y, a=ahead):
            return y[0] - a

        def down(t, y, b=behind):
            return y[0] - b

        up.terminal = down.terminal = True
        sol = one(t0, y0, (up, down))
        parts.append(sol)
        switched = sol.status == 1 and (sol.t_events[n].size or sol.t_events[n + 1].size)
        if not switched or any(sol.t_events[k].size for k in range(n)) or sol.t[-1] >= T:
            return _Joined(parts, n)
        t0, y0 = float(sol.t[-1]), sol.y[:, -1].copy()


class _Joined:
    """solve_ivp's result over the pieces of ``_across_switches``: steps ``t``, states ``y``, the
    dense output ``sol`` (each time from its piece), and the last piece's status and first ``n``
    events."""

    def __init__(self, parts, n: int):
        self.t = np.concatenate([parts[0].t] + [p.t[1:] for p in parts[1:]])
        self.y = np.concatenate([parts[0].y] + [p.y[:, 1:] for p in parts[1:]], axis=1)
        self.bounds = np.array([p.t[-1] for p in parts[:-1]])
        self.pieces = [p.sol for p in parts]
        last = parts[-1]
        self.status, self.success, self.message = last.status, last.success, last.message
        none = last.t_events is None  # solve_ivp without events
        self.t_events, self.y_events = ([], []) if none else (last.t_events[:n], last.y_events[:n])

    def sol(self, t):
        t = np.asarray(t, dtype=float)
        k = np.searchsorted(self.bounds, t, side="right")
        if t.ndim == 0:
            return self.pieces[int(k)](t)
        out = np.empty((self.y.shape[0], t.size))
        for i in np.unique(k):
            out[:, k == i] = self.pieces[int(i)](t[k == i])
        return out


def speed_range(solution, a: float, b: float, *, periodic: bool, n: int = 64 * CYCLE_POINTS) -> tuple[float, float]:
    """ω_min and ω_max [rad/s] of the dense output ``solution`` (t → state) over times [a, b]
    (a cycle, if ``periodic``): n samples, each extreme refined between them (``linkgen.extrema``)."""
    from linkgen.extrema import peak, samples

    t = samples(a, b, n, periodic)
    w = solution(t)[1]
    period = (b - a) if periodic else None
    speed = lambda tt: solution(tt)[1]  # noqa: E731
    return peak(speed, t, w, kind="min", period=period)[1], peak(speed, t, w, period=period)[1]


__all__ = ["MachineRun", "RTOL", "STEADY_TOL", "SteadyCycle", "choose_method", "motor_torque_at", "run_machine",
           "speed_range", "steady_cycle"]
