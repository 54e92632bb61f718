"""Coulomb friction in the pairs (``[[friction]]``) in the machine's equation.

The friction's reduced moment M_f = P_f/ω = sgn(ω)·loss(φ, ω, ε), P_f ≥ 0 the power it takes out
(the closed form's friction kinetostatics, ``kinetostatics.forces``: Σ μ·r·|R|·|θ̇_a − θ̇_b| +
Σ μ·(|N₁| + |N₂|)·|ṡ|), depends on the reactions and so on the crank's acceleration ε through the
inertia loads. The machine's equation

    (J(φ) + J_add)·ε + ½·J′(φ)·ω² = M_drive + M(φ, ω) − s(ω)·M_f(φ, ω, ε)

is solved for ε at each state (``acceleration``) jointly with the pairs' friction by Newton's
method over the mechanism's table of the frictionless reactions' affine parts
(``machine.friction_table``: no kinetostatics per state; ~0.1 ms), from the last state's friction.
Where it has no table or does not converge (``FrictionTable.solve``'s ok), the closed form's
kinetostatics answers: Newton's iteration on ε with a secant slope (vectorised over states: every
iteration is one call of the kinetostatics at ε and ε + δ over all of them), starting from the last
state's friction moment (a single state) or from none. M_f is nearly affine in ε (its slope is the
friction's share of the inertia loads, ~μ·r/arm of J), so that iteration converges in 2–3 calls
to EPSILON_TOL. ``friction_values`` gives the pairs' friction at a given ε the same two ways
(MuJoCo's steps, the linkage check).

Near ω = 0 (a start from rest, a reversal) the Coulomb law is regularised: s(ω) =
tanh(|ω|/STICK_SPEED), so that the friction moment s·sgn(ω)·loss = tanh(ω/STICK_SPEED)·loss is a
smooth function of ω through zero (a ramp with a kink would break the ODE solver's and the
energy quadrature's orders at each reversal). A crank that the drive and the loads cannot move
against the friction then creeps at a speed of order STICK_SPEED instead of sticking exactly (a
stated velocity scale, not static friction); from 19·STICK_SPEED on, tanh is 1 to float64's
precision and the law is Coulomb's exactly.

Where the friction has no solution at a state (the mechanism self-locks, ``FrictionError``), or
the equation's effective inertia ∂(torque)/∂ε turns ≤ 0 (friction that grows with ε faster than
the inertia: the crank cannot be accelerated either way), ``LockedError`` names the state."""

from __future__ import annotations

import math

import numpy as np

from linkgen.errors import FrictionError, SimulationError
from linkgen.families.planar.assembly import Assembly

# The regularisation's speed [rad/s]: the friction is s = tanh(|ω|/STICK_SPEED) of Coulomb's.
# 1e-3 rad/s is 1e-4 of the bundled machines' speeds (~10–30 rad/s): a crank held by friction
# creeps by at most ~0.06°/s, and a run that never comes within it of rest is pure Coulomb.
STICK_SPEED = 1e-3
# The iteration on ε stops when the equation's residual is at most this fraction of J times the
# acceleration scale (|free|/J + |M_f|/J): the kinetostatics' own friction fixed point is converged
# to FRICTION_TOL = 1e-12 of the friction, so the residual is known to ~1e-12 of |M_f|; 1e-11
# leaves a factor 10 over that noise and is 1e-1 of the ODE solver's RTOL = 1e-10.
EPSILON_TOL = 1e-11
# The secant's step δ on ε, as a fraction of the acceleration scale: the slope ∂g/∂ε = J + s·∂M_f/∂ε
# then carries a noise of ~1e-12·|M_f|/δ ≈ 1e-8 of J, far below what a Newton step needs.
SLOPE_STEP = 1e-4
# Iterations before giving up (a well-posed state converges in 2–4).
MAX_ITERATIONS = 30


class LockedError(SimulationError):
    """The friction locks the machine at a state of its run."""


class PairFriction:
    """The closed form's friction moment of one mechanism (``Reduced.friction``)."""

    def __init__(self, asm: Assembly, exact: bool = False):
        from linkgen.families.planar.friction_switches import friction_switches

        self.asm = asm
        d = asm.mechanism.drive
        # crank angles in [start, start + 2π) where a pair's friction changes direction: M_f jumps
        # there (for a crank that turns fully; the integration restarts at each, ``machine.machine``)
        full = d.stop - d.start >= 2 * math.pi - 1e-9
        self.switches = np.array(friction_switches(asm, d.start, d.start + 2 * math.pi) if full else [])
        self.switches = np.unique(np.mod(self.switches - d.start, 2 * math.pi)) + d.start
        self.calls = 0
        self.last = None  # the last single state's s·M_f [N·m]: the next one's starting guess
        self.last_pairs = None  # the last single state's pair frictions (table route): the same
        self.last_values = None  # the same for ``values``
        self.exact = exact  # every state by the closed form's kinetostatics, not the table (the reference)

    def neighbours(self, phi: float, margin: float = 1e-9) -> tuple[float, float]:
        """The nearest switch angles [rad] ahead of φ and behind it, each more than ``margin``
        [rad] away (±inf without switches)."""
        if not self.switches.size:
            return math.inf, -math.inf
        two = 2 * math.pi
        ahead = self.switches + two * np.ceil((phi + margin - self.switches) / two)
        behind = self.switches + two * np.floor((phi - margin - self.switches) / two)
        return float(ahead.min()), float(behind.max())

    @property
    def table(self):
        """The mechanism's ``friction_table.FrictionTable`` (built on first use, once per assembly;
        None where it has none: then every state goes through the closed form's kinetostatics)."""
        from linkgen.machine.friction_table import build

        return None if self.exact else build(self.asm)

    def moment(self, phi, omega, epsilon) -> np.ndarray:
        """M_f = sgn(ω)·loss [N·m] at the states (φ, ω, ε) (each (k,)), unscaled (Coulomb), by the
        closed form's kinetostatics (the reference the table's route is checked against)."""
        from linkgen.families.planar.kinetostatics import forces

        self.calls += 1
        phi = np.atleast_1d(np.asarray(phi, dtype=float))
        w = np.broadcast_to(np.asarray(omega, dtype=float), phi.shape)
        f = forces(self.asm, phi, w, np.broadcast_to(np.asarray(epsilon, dtype=float), phi.shape), threads=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(w != 0, f.friction_power / np.where(w != 0, np.abs(w), 1.0), 0.0) * np.sign(w)

    def values(self, phi, omega, epsilon) -> tuple[dict[str, np.ndarray], np.ndarray]:
        """``friction_values`` at the states (φ, ω, ε) (each (k,)), a single state's from the last
        one's friction (MuJoCo's last step)."""
        pairs, mf, f = friction_values(self.asm, phi, omega, epsilon, self.last_values, self.exact)
        if np.size(mf) == 1:
            self.last_values = f
        return pairs, mf


def friction_values(asm: Assembly, phi, omega, epsilon, guess=None, exact: bool = False):
    """Each pair's Coulomb friction (``Forces.friction``: name → (k,)) and M_f (k,) [N·m] at the
    states (φ, ω, ε) (each (k,)), and the friction (k, K) (or None): by the mechanism's table
    (``friction_table``, from ``guess`` (k, K)) where it has one and converges, else by the closed
    form's kinetostatics (which raises FrictionError where the pairs self-lock; every state with
    ``exact``)."""
    from linkgen.families.planar.kinetostatics import forces
    from linkgen.machine.friction_table import build

    phi = np.atleast_1d(np.asarray(phi, dtype=float))
    w = np.broadcast_to(np.asarray(omega, dtype=float), phi.shape)
    e = np.broadcast_to(np.asarray(epsilon, dtype=float), phi.shape)
    names = [fr.pair for fr in asm.mechanism.frictions]
    table = None if exact else build(asm)
    ok = np.zeros(phi.shape, dtype=bool)
    if table is not None:
        f, _, rel, ok = table.solve(phi, w, epsilon=e, guess=guess if guess is not None and phi.size == 1 else None)
        mf = -np.einsum("nk,nk->n", f, rel)
    else:
        f, mf = np.zeros((phi.size, len(names))), np.zeros(phi.size)
    if not ok.all():
        bad = ~ok
        exact = forces(asm, phi[bad], w[bad], e[bad], threads=1)
        f[bad] = np.stack([exact.friction[name] for name in names], axis=1)
        with np.errstate(invalid="ignore", divide="ignore"):
            mf[bad] = np.where(w[bad] != 0, exact.friction_power / np.where(w[bad] != 0, np.abs(w[bad]), 1.0),
                               0.0) * np.sign(w[bad])
    return {name: f[:, k] for k, name in enumerate(names)}, mf, (f if ok.all() else None)


def scale(omega) -> np.ndarray:
    """s(ω) = tanh(|ω|/STICK_SPEED): the share of Coulomb's friction at crank speed ω."""
    return np.tanh(np.abs(np.asarray(omega, dtype=float)) / STICK_SPEED)


def acceleration(friction: PairFriction, phi, omega, free, inertia, t=None):
    """ε (k,) [rad/s²] with (inertia)·ε = free − s(ω)·M_f(φ, ω, ε), ``free`` the frictionless
    right-hand side M_drive + M − ½·J′·ω² [N·m] and ``inertia`` J + J_add [kg·m²] (each (k,));
    also M_f·s (the friction's reduced moment [N·m], for the energy balance). ``t`` (k,) [s]
    names the state in a LockedError."""
    phi = np.atleast_1d(np.asarray(phi, dtype=float))
    w = np.broadcast_to(np.asarray(omega, dtype=float), phi.shape)
    free = np.broadcast_to(np.asarray(free, dtype=float), phi.shape)
    inertia = np.broadcast_to(np.asarray(inertia, dtype=float), phi.shape)
    s = scale(w)
    moving = s > 0
    eps = free / inertia
    mf = np.zeros(phi.shape)
    if not moving.any():
        return eps, mf
    idx = np.flatnonzero(moving)
    if friction.table is not None:  # Newton on (ε, the pairs' friction) over the table (``friction_table``)
        guess = friction.last_pairs if idx.size == 1 else None
        f, e, rel, ok = friction.table.solve(phi[idx], w[idx], free=free[idx], inertia=inertia[idx], s=s[idx],
                                             guess=guess)
        eps[idx], mf[idx] = e, -s[idx] * np.einsum("nk,nk->n", f, rel)
        if idx.size == 1:
            friction.last_pairs = f if ok[0] else None
        idx = idx[~ok]  # the rest (locking, or no table) by the closed form's kinetostatics, below
        if not idx.size:
            return eps, mf
    tt = None if t is None else np.broadcast_to(np.asarray(t, dtype=float), phi.shape)[idx]

    def residual(e):  # g(ε) = J·ε − free + s·M_f(ε) [N·m] at the states twice: ε (k,) and ε + δ (k,)
        two = np.concatenate([idx, idx])
        try:
            m = s[two] * friction.moment(phi[two], w[two], e)
        except FrictionError as exc:
            raise _locked(phi[idx], w[idx], tt, f"the friction has no solution ({exc})") from None
        return inertia[two] * e - free[two] + m, m

    sub_free, sub_j = free[idx], inertia[idx]
    guess = friction.last if friction.last is not None and idx.size == 1 else 0.0
    e0 = (sub_free - guess) / sub_j  # the last state's friction moment: a warm start
    size = np.abs(sub_free) / sub_j + np.abs(guess) / sub_j + np.finfo(float).tiny
    for _ in range(MAX_ITERATIONS):
        # one call of the kinetostatics at ε and ε + δ: the residual and its slope (a secant)
        delta = SLOPE_STEP * size
        g, m = residual(np.concatenate([e0, e0 + delta]))
        g0, g1, m0 = g[:idx.size], g[idx.size:], m[:idx.size]
        size = np.maximum(size, np.abs(m0) / sub_j)
        slope = (g1 - g0) / delta
        if np.all(np.abs(g0) <= EPSILON_TOL * sub_j * size):  # its last Newton step, on the same line
            e0, m0 = e0 - g0 / slope, m0 - (m[idx.size:] - m0) / delta * g0 / slope
            break
        if not np.all(slope > 0):
            bad = ~(slope > 0)
            raise _locked(phi[idx][bad], w[idx][bad], None if tt is None else tt[bad], "the friction grows with the "
                          "crank's acceleration faster than the inertia resists it (the equation's effective inertia "
                          "is ≤ 0)")
        e0 = e0 - g0 / slope
        size = np.maximum(size, np.abs(e0))
    else:
        raise _locked(phi[idx], w[idx], tt, f"the friction's iteration on the acceleration did not converge in "
                                            f"{MAX_ITERATIONS} steps")
    if idx.size == 1:
        friction.last = float(m0[0])
    eps[idx], mf[idx] = e0, m0
    return eps, mf


def _locked(phi, w, t, why: str) -> LockedError:
    """The error at the first of the states (φ, ω, t) (each (k,); t None: not named)."""
    when = "" if t is None else f"t = {float(np.atleast_1d(t)[0]):.6g} s, "
    return LockedError(f"the friction locks the machine at {when}φ = {math.degrees(float(np.atleast_1d(phi)[0])):.4f}°, "
                       f"ω = {float(np.atleast_1d(w)[0]):.6g} rad/s: {why}; lower the [[friction]] coefficients or "
                       "pin radii, or change the drive")


__all__ = ["EPSILON_TOL", "LockedError", "MAX_ITERATIONS", "PairFriction", "STICK_SPEED", "acceleration",
           "friction_values", "scale"]
