"""The energy balance of a machine run, checked at every output sample.

Along the motion the kinetic energy changes by the work done on the machine:

    T(t) − T(0) + ΔV_shaft = W_loads + W_dampers + W_drive + W_shaft_damper + W_friction,

T = ½·(J(φ) + J_add)·ω² (with an elastic shaft ½·(J(φ) + J_f)·ω² + ½·J_rotor·u²·ω_r²),
W_loads = ∫ M₀(φ) dφ the work of every load that depends on the crank angle only (gravity,
springs, forces, torques, the process load: minus their potential where they have one), exact
over the same table M₀ the equation reads (``SmoothTable.integral``) — or, where the equation
reads the closed form itself (``[machine] tables = false``), ∫ M₀(φ)·ω dt by the quadrature
below —, W_dampers = ∫ C(φ)·ω² dt
(≤ 0), W_drive = ∫ u·η·M_motor·ω_r dt, and with a shaft ΔV_shaft = ½·c·dz(θ − φ)² − its start
value and W_shaft_damper = −∫ b·(ω_r − ω)² dt; with friction in the pairs W_friction =
−∫ s·M_f·ω dt ≤ 0, the friction's reduced moment at each quadrature point's state and its
acceleration (``machine.friction``: the same solve the equation makes); with a brake its work
W_brake = ∫ M_brake·ω dt ≤ 0, and the drive's power is zero while the schedule has the motor off
(``machine.schedule``). The time integrals are Gauss–Legendre quadratures
of the solver's dense output between its own steps and the samples (GAUSS points each, exact to
degree 2·GAUSS − 1, beyond the dense output's own order 7), so the residual measures the
integration, not the quadrature.

The residual is judged relative to the run's energy scale, the largest magnitude of any of the
terms above (or of T) along the run, against ENERGY_TOL; a run over it is flagged (``ok``
False) and ``linkgen dynamics`` says so and exits with status 1.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# Gauss–Legendre points per interval of the work integrals.
GAUSS = 6
# The residual's bound, relative to the run's energy scale. The solver holds each step's local
# error to RTOL = 1e-10 of the state; over the N ≤ 1e5 steps of a long run these add up to
# at most N·RTOL = 1e-5 if all of one sign, RTOL·√N ≈ 3e-8 if independent. Measured on the
# bundled machines (docs/machine.md): 8e-13 to 1.3e-9 (the largest on the released four-bar,
# then 7e-10 on a press whose stroke force switches inside a solver step). 1e-7 leaves a
# factor 75 over the worst measured while still catching a wrong term: leaving the dampers'
# work out of slider_crank_torque's balance gives 1.0 (tests/test_machine_state.py).
ENERGY_TOL = 1e-7


@dataclass(frozen=True)
class EnergyBalance:
    """At the run's output samples (n,) [J]: the kinetic energy T, the work since t = 0 of the
    position-dependent loads, of the dampers, of the drive, and with a shaft its stored energy's
    change and its damper's work (else None); the residual ΔT + ΔV_shaft − ΣW; ``scale`` [J] the
    run's energy scale and ``tolerance`` the residual's bound relative to it."""

    kinetic: np.ndarray
    loads: np.ndarray
    dampers: np.ndarray
    drive: np.ndarray
    shaft_energy: np.ndarray | None
    shaft_damper: np.ndarray | None
    residual: np.ndarray
    scale: float
    tolerance: float = ENERGY_TOL
    friction: np.ndarray | None = None  # the friction's work since t = 0 [J] (≤ 0); None without friction
    brake: np.ndarray | None = None  # the brake's work since t = 0 [J] (≤ 0); None without a brake

    @property
    def worst(self) -> float:
        """The largest |residual| relative to the energy scale."""
        return float(np.abs(self.residual).max() / self.scale) if self.scale > 0 else 0.0

    @property
    def ok(self) -> bool:
        return self.worst <= self.tolerance

    def to_json(self) -> dict:
        return {"worst_residual_relative": self.worst, "worst_residual_J": float(np.abs(self.residual).max()),
                "energy_scale_J": self.scale, "tolerance": self.tolerance, "ok": self.ok,
                "final": {"kinetic_J": float(self.kinetic[-1]), "loads_work_J": float(self.loads[-1]),
                          "dampers_work_J": float(self.dampers[-1]), "drive_work_J": float(self.drive[-1])}
                | ({} if self.friction is None else {"friction_work_J": float(self.friction[-1])})
                | ({} if self.brake is None else {"brake_work_J": float(self.brake[-1])})}


def _powers(model, y: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Rows: the drive's, the dampers', the shaft damper's, the friction's, the brake's and (where
    the equation reads the closed form, not the tables) the φ-dependent loads' power [W] at states
    y (n, k), times t (k,)."""
    phi, w = y[0], y[1]
    w_rotor = y[3] if model.shaft else w
    mm, _ = model.motor(w_rotor, y, t)
    drive = model.u * model.eta * np.asarray(mm, dtype=float) * w_rotor
    red = model.red
    damp = red.damping(phi) * w * w
    shaft = -model.shaft.damping * (w_rotor - w) ** 2 if model.shaft else np.zeros_like(w)
    friction = -model.friction_moment(y, t) * w if red.friction is not None else np.zeros_like(w)
    loads = red.load_moment(phi) * w if red.exact else np.zeros_like(w)
    return np.vstack([drive, damp, shaft, friction, model.brake(t, w) * w, loads])


def _kinetic(model, y: np.ndarray) -> np.ndarray:
    red, m = model.red, model.m
    if model.shaft:
        return 0.5 * (red.j(y[0]) + m.flywheel_inertia) * y[1] ** 2 + 0.5 * m.rotor_inertia * model.u**2 * y[3] ** 2
    return 0.5 * (red.j(y[0]) + m.added_inertia) * y[1] ** 2


def _shaft_energy(model, y: np.ndarray) -> np.ndarray:
    s = model.shaft
    twist, half = y[2] - y[0], 0.5 * s.backlash
    dz = np.where(twist > half, twist - half, np.where(twist < -half, twist + half, 0.0))
    return 0.5 * s.stiffness * dz * dz


def energy_balance(model, dense, steps: np.ndarray, t: np.ndarray) -> EnergyBalance:
    """The balance at sample times ``t`` (n,) [s], increasing from 0, of the run whose dense
    output is ``dense`` (t → states), whose solver stepped at times ``steps`` and whose
    right-hand side is ``model`` (``equation.Model``), judged against ENERGY_TOL."""
    t = np.asarray(t, dtype=float)
    knots = np.union1d(steps[(steps > t[0]) & (steps < t[-1])], t)
    x, wts = np.polynomial.legendre.leggauss(GAUSS)
    a, b = knots[:-1], knots[1:]
    nodes = (0.5 * (b - a)[:, None] * (x[None, :] + 1.0) + a[:, None]).ravel()
    p = _powers(model, dense(nodes), nodes).reshape(6, a.size, GAUSS)
    cells = (p * wts).sum(axis=2) * 0.5 * (b - a)
    cumulative = np.concatenate([np.zeros((6, 1)), np.cumsum(cells, axis=1)], axis=1)
    at = cumulative[:, np.searchsorted(knots, t)]
    y = dense(t)
    if model.red.exact:
        loads = at[5]
    else:
        table = model.red.table("moment_grid")
        loads = table.integral(y[0]) - table.integral(y[0][0])
    kinetic = _kinetic(model, y)
    shaft_energy = _shaft_energy(model, y) if model.shaft else None
    stored = kinetic - kinetic[0] + (shaft_energy - shaft_energy[0] if model.shaft else 0.0)
    residual = stored - (loads + at[0] + at[1] + at[2] + at[3] + at[4])
    friction = model.red.friction is not None
    braked = model.switching.brake_kind is not None
    terms = [kinetic, loads, at[0], at[1]] + ([shaft_energy, at[2]] if model.shaft else []) + ([at[3]] if friction else []) \
        + ([at[4]] if braked else [])
    scale = float(max(np.abs(v).max() for v in terms))
    return EnergyBalance(kinetic, loads, at[1], at[0], shaft_energy, at[2] if model.shaft else None, residual, scale,
                         ENERGY_TOL, at[3] if friction else None, at[4] if braked else None)


__all__ = ["ENERGY_TOL", "EnergyBalance", "GAUSS", "energy_balance"]
