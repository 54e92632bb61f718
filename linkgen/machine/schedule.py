"""The motor switched on and off and the brake (``[machine.schedule]``, ``[machine.brake]``,
``linkgen.model.schedule``) in the machine's equation:

    (J(φ) + J_add)·ω̇ + ½·J′(φ)·ω² = M(φ, ω) + k(t)·u·η·M_motor + M_brake,

k(t) = 1 while the motor runs (motor_on ≤ t < motor_off), else 0 (a DC motor's circuit is opened:
its current drops to 0 and stays there until it is switched on again); M_brake = 0 before the
brake is applied at t_b, then −T·s (constant, s = sgn ω(t_b)) or −c·ω (viscous). The switch times
and the brake's engagement are where the integration stops and restarts (``integrate``), each
piece integrated with its own k and brake (``Model.phase``), so that no solver step straddles a
jump; the brake applied from an angle is an event on the crank angle. The run ends when the crank
comes to rest (ω = 0, an event) with the brake applied: the brake holds it from then (a constant
brake's torque is the most it can hold; the run does not go on to ask whether the loads overcome
it). Without a brake, the run-down ends at the first ω = 0 after motor_off and the run goes on.
``stopping`` gives the run-down time (motor_off → rest) and the braking angle (brake → rest).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np
from scipy.optimize import brentq

from linkgen.errors import SimulationError
from linkgen.model.machine import Machine


@dataclass(frozen=True)
class Switching:
    """The motor's on/off times [s], the brake's law (kind None: no brake) and the time it is
    applied ``brake_at`` [s] (inf: not yet known or never) with the sign ``sign`` of ω then."""

    on: float = 0.0
    off: float = math.inf
    brake_kind: str | None = None
    brake_value: float = 0.0
    brake_at: float = math.inf
    sign: float = 0.0

    @classmethod
    def of(cls, machine: Machine) -> "Switching":
        s, b = machine.schedule, machine.brake
        at = math.inf if b is None or b.from_time is None else b.from_time
        return cls(s.motor_on if s else 0.0, s.motor_off if s else math.inf, b.kind if b else None,
                   b.value if b else 0.0, at)

    def motor(self, t):
        """k(t): 1 where the motor runs, else 0 (right-continuous at the switches)."""
        t = np.asarray(t, dtype=float)
        return np.where((t >= self.on) & (t < self.off), 1.0, 0.0)

    def brake(self, braking, w):
        """The brake's moment on the crank [N·m] where ``braking`` (bool or array), at speed w."""
        if self.brake_kind is None:
            return np.zeros_like(np.asarray(w, dtype=float))
        law = -self.brake_value * (self.sign if self.brake_kind == "constant" else np.asarray(w, dtype=float))
        return np.where(braking, law, 0.0)

    def braking(self, t):
        return np.asarray(t, dtype=float) >= self.brake_at

    def times(self, end: float) -> list[float]:
        """The switch times strictly inside (0, end)."""
        return sorted({x for x in (self.on, self.off, self.brake_at) if 0.0 < x < end})


@dataclass(frozen=True)
class Stopping:
    """When the motor ran and the brake was applied, and when the crank came to rest: ``rest_at``
    [s] (the first ω = 0 after motor_off, or with the brake; None if it never did), ``held``
    (the run ended there, the brake holding the crank), the run-down time motor_off → rest [s],
    the braking angle |φ(rest) − φ(brake)| [rad] and time brake → rest [s]."""

    motor_on: float
    motor_off: float | None
    brake_at: float | None
    brake_angle: float | None
    rest_at: float | None
    held: bool
    run_down_time: float | None
    braking_angle: float | None
    braking_time: float | None

    def to_json(self) -> dict:
        return {"motor_on": self.motor_on, "motor_off": self.motor_off, "brake_applied_at": self.brake_at,
                "brake_applied_angle": self.brake_angle, "rest_at": self.rest_at, "held_by_brake": self.held,
                "run_down_time": self.run_down_time, "braking_angle": self.braking_angle,
                "braking_time": self.braking_time,
                "at_rest": "the run ends when the crank comes to rest with the brake applied: the brake holds it"
                           if self.held else None}


def integrate(piece, model, y0: np.ndarray, n: int, end: float, from_angle: float | None):
    """Integrate the machine over [0, end] in pieces between the switch times, the brake's
    engagement and the crank's rest: ``piece(t0, t1, y0, extra events)`` integrates one piece
    (solve_ivp's result, events: the run's n own, then the extra ones). Returns the pieces, the
    switching with the brake's time and sign, and the time the crank came to rest under the
    brake (None if it did not)."""
    sw = model.switching
    parts, t0, y = [], 0.0, np.asarray(y0, dtype=float)
    try:
        while True:
            if math.isinf(sw.brake_at) and from_angle is not None and y[0] == from_angle:
                sw = replace(sw, brake_at=t0)
            braking = sw.brake_kind is not None and t0 >= sw.brake_at
            if braking and sw.sign == 0.0:
                sw = replace(sw, sign=float(np.sign(y[1])))
                if sw.sign == 0.0:  # applied to a crank at rest: held at once
                    if parts:
                        return parts, sw, t0
                    raise SimulationError("the brake ([machine.brake]) is applied at t = 0 to a crank at rest: it holds "
                                          "it there, there is no motion to integrate; apply it later or give a "
                                          "start_speed")
            model.switching = sw
            model.phase = (float(sw.motor(t0)), braking)
            t1 = min([x for x in sw.times(end) if x > t0] + [end])
            extra = []
            if braking:
                def rest(t, yy):
                    return yy[1]

                rest.terminal, rest.direction = True, -sw.sign
                extra.append(rest)
            elif sw.brake_kind is not None and from_angle is not None and math.isinf(sw.brake_at):
                def reach(t, yy):
                    return yy[0] - from_angle

                reach.terminal = True
                extra.append(reach)
            sol = piece(t0, t1, y, extra)
            parts.append(sol)
            t_end, y = float(sol.t[-1]), sol.y[:, -1].copy()
            if sol.status == 1 and any(sol.t_events[k].size for k in range(n)):
                return parts, sw, None
            if extra and sol.status == 1 and sol.t_events[n].size:
                if braking:
                    return parts, sw, t_end
                sw = replace(sw, brake_at=t_end)
            if t_end >= end:
                return parts, sw, None
            if model.current and sw.motor(t_end) == 0.0:  # the circuit opened: no current
                y[-1] = 0.0
            t0 = t_end
    finally:
        model.phase = None
        model.switching = sw


def _first_rest(sol, a: float, b: float) -> float | None:
    """The first time in [a, b] where ω = 0 (a sign change between the solver's steps, refined)."""
    steps = np.asarray(sol.t)
    t = np.unique(np.concatenate([[a], steps[(steps > a) & (steps < b)], [b]]))
    w = sol.sol(t)[1]
    for k in range(t.size - 1):
        if w[k] == 0.0:
            return float(t[k])
        if np.sign(w[k]) != np.sign(w[k + 1]):
            return float(brentq(lambda x: float(sol.sol(np.array([x]))[1][0]), t[k], t[k + 1], xtol=1e-14))
    return float(t[-1]) if w[-1] == 0.0 else None


def stopping(sol, sw: Switching, held_at: float | None, end: float) -> Stopping:
    """The run's ``Stopping`` from its joined solution ``sol`` over [0, end]."""
    off = sw.off if sw.off <= end else None
    brake = sw.brake_at if sw.brake_at <= end else None
    rest = held_at
    if rest is None and off is not None:
        rest = _first_rest(sol, off, end)
    angle = float(sol.sol(np.array([brake]))[0][0]) if brake is not None else None
    run_down = rest - off if rest is not None and off is not None and rest >= off else None
    braking = None
    if rest is not None and brake is not None and rest >= brake:
        braking = abs(float(sol.sol(np.array([rest]))[0][0]) - angle)
    return Stopping(sw.on, off, brake, angle, rest, held_at is not None, run_down, braking,
                    rest - brake if braking is not None else None)


__all__ = ["Stopping", "Switching", "integrate", "stopping"]
