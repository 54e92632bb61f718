"""The motor's schedule and the brake (``[machine.schedule]``, ``[machine.brake]``) in MuJoCo's
machine, which has no element for either: each step applies the motor's torque times the share
of the step it runs (k̄ = |[t, t + h) ∩ [on, off)|/h, so a switch inside a step gives the step the
exact impulse of a constant torque), and the brake's moment on the crank likewise for the share
of the step after it is applied — −T·s (s = sgn ω when applied) or −c·ω at the braked part's
middle. A brake applied from a crank angle is applied where the step's predicted sweep reaches
it (linear in the sweep). The run ends (its samples do) where the closed form's run comes to
rest; MuJoCo keeps the brake's sign to the last sample, as the closed form's last piece does.
"""

from __future__ import annotations

import math

from linkgen.machine.schedule import Switching
from linkgen.model.machine import Machine


def _overlap(a: float, b: float, lo: float, hi: float) -> float:
    return max(0.0, min(b, hi) - max(a, lo))


class StepSwitching:
    """The schedule and the brake step by step (see the module docstring)."""

    def __init__(self, machine: Machine):
        self.sw = Switching.of(machine)
        self.from_angle = machine.brake.from_angle if machine.brake is not None else None
        self.motor_share, self.brake_share = 1.0, 0.0

    def motor_at(self, t: float) -> float:
        """k(t): 1 where the motor runs at time t, else 0."""
        return float(self.sw.motor(t))

    def step(self, t: float, h: float, phi: float, sweep: float, omega: float) -> None:
        """Before the step [t, t + h) from crank angle ``phi`` [rad] sweeping ``sweep`` [rad] at
        speed ``omega``: the motor's and the brake's shares of it."""
        sw = self.sw
        self.motor_share = _overlap(t, t + h, sw.on, sw.off) / h
        if sw.brake_kind is None:
            return
        if math.isinf(sw.brake_at) and self.from_angle is not None:
            a, b = phi, phi + sweep
            if a == self.from_angle or (min(a, b) < self.from_angle <= max(a, b)):
                share = (self.from_angle - a) / sweep if sweep != 0 else 0.0
                self.sw = sw = Switching(sw.on, sw.off, sw.brake_kind, sw.brake_value, t + h * share)
        self.brake_share = _overlap(t, t + h, sw.brake_at, math.inf) / h
        if self.brake_share > 0 and sw.sign == 0.0:
            self.sw = Switching(sw.on, sw.off, sw.brake_kind, sw.brake_value, sw.brake_at, math.copysign(1.0, omega)
                                if omega != 0 else 0.0)

    def brake_torque(self, omega_braked: float) -> float:
        """The brake's mean moment on the crank over the step [N·m], ω at the braked part's middle."""
        sw = self.sw
        if sw.brake_kind is None or self.brake_share == 0.0:
            return 0.0
        law = sw.sign if sw.brake_kind == "constant" else omega_braked
        return -sw.brake_value * law * self.brake_share

    def brake_now(self, t: float, omega: float) -> float:
        """The brake's moment on the crank [N·m] at the instant t (a sample's forces)."""
        sw = self.sw
        if sw.brake_kind is None or t < sw.brake_at:
            return 0.0
        return -sw.brake_value * (sw.sign if sw.brake_kind == "constant" else omega)


__all__ = ["StepSwitching"]
