"""The pairs' friction at a state (φ, ω, ε) of a machine without building the kinetostatics: the
frictionless reactions are affine in the loads, so at each crank angle those of the pairs with
friction are

    R(φ) = A₀(φ) + ω²·A₂(φ) + ε·A_ε(φ) + ω·A_c(φ) + Σ_k f_k·G_k(φ),

A₀ from the given loads at rest (gravity, forces, torques, springs), A₂ and A_ε from the inertia
loads per unit ω² and ε, A_c from the dampers per unit ω, and G_k the reactions one unit of pair
k's friction f_k (its couple [N·m] or force along the guide [N], ``planar.friction``) makes. These
columns, with each pair's relative rate per unit crank rate, are cubic splines over one turn
(as ``tables.SmoothTable``: a stroke-switched force's jumps exact) through the closed form's values
(``reactions.solve_reactions``) on a grid that is refined until the splines meet the closed form
at every cell's middle within TABLE_TOL (``FrictionTable.error`` is what they reached).

At a state the friction then is the fixed point f_k = −sgn(ω·rel_k)·μ_k·ρ_k(R), ρ = r·|R| at a
revolute and max(|N|, 2|M|/L) at a prismatic pair, of K unknowns (``kinetostatics``' own law);
with the machine's equation J·ε = free + s·Σ f_k·rel_k (−Σ f_k·rel_k is M_f, ``machine.friction``)
it is solved jointly with ε by Newton's method on the K + 1 unknowns, the Jacobian exact (ρ is
piecewise linear or a norm of affine functions). Superposition needs reactions linear in the loads:
a mechanism with gears (whose tooth force has |F_t|·tan α) has no table (``build`` returns None)."""

from __future__ import annotations

import math

import numpy as np

from linkgen.families.planar.assembly import Assembly
from linkgen.machine.tables import jump_grid, switch_angles

# The splines must meet the closed form at every cell's middle within this fraction of each
# column block's peak. A quintic between 4096 angles a turn errs by ~(h/2)⁶·|f⁽⁶⁾|/720 there, ~1e-15 of
# machine_friction's reactions (measured 3.3e-15); next to a stroke-switched force's jump the grid's
# values are taken tables.SIDE = 1e-10 rad to either side of the switch, which moves them by
# 1e-10·|f′| (measured 2.5e-11 of the peak on a press, at any grid). 1e-10 of the reactions moves
# the friction moment by 1e-10 of itself, a few 1e-12 of the machine's torques.
TABLE_TOL = 1e-10
# The first grid (cells over one turn) and the finest one tried; a mechanism whose reactions need
# more (near a singular pose) is solved by the closed form at each state instead (slower, exact).
# Not the accuracy alone sets the splines: a cubic's third derivative jumps at every grid angle, and
# an ODE solver of order 8 crossing them loses accuracy — ten turns of machine_friction at rtol
# 1e-10 ended 3.5e-8 (relative) from a 100× tighter run with cubics on 2048 cells (error 8.5e-13),
# 7.1e-9 on 16384; quintics (C⁴) on 4096 cells: 6.5e-9, ~13 MB for 4 pairs.
FIRST_CELLS, MAX_CELLS = 4096, 32768
# The splines' degree (``_Spline``).
DEGREE = 5
# Newton's iteration stops once its step moves each friction by at most this fraction of itself.
# Its convergence is quadratic: the friction's law is piecewise linear (a block) or a norm |R| of
# affine reactions (a pin), whose curvature leaves, after a step δ (relative), an error of at most
# (c·δ)², c = μ·r·|∂R/∂f| < 1 the contraction of the closed form's own iteration (checked: the
# Jacobian's determinant > 0). A step ≤ 1e-6 thus leaves ≤ 1e-12, the closed form's FRICTION_TOL.
NEWTON_TOL = 1e-6
MAX_NEWTON = 30


class FrictionTable:
    """The columns of the module docstring over one turn (``build``); ``pairs`` the friction
    entries in order, ``error`` the worst relative gap of the splines at the cells' middles."""

    def __init__(self, asm: Assembly, table: "_Spline", error: float, cells: int):
        mech = asm.mechanism
        self.pairs = list(mech.frictions)
        self.table, self.error, self.cells = table, error, cells
        k = len(self.pairs)
        self.k, self.c = k, 2 * k
        self.revolute = np.array([fr.pin_radius is not None for fr in self.pairs])
        self.mu_r = np.array([fr.coefficient * (fr.pin_radius if fr.pin_radius is not None else 1.0)
                              for fr in self.pairs])
        self.two_over_l = np.array([2.0 / fr.block_length if fr.block_length else 0.0 for fr in self.pairs])
        from linkgen.families.planar.friction import STILL_TOL, asm_size

        self.still = np.where(self.revolute, STILL_TOL, STILL_TOL * max(asm_size(asm), np.finfo(float).tiny))
        # the same as lists, for a single state's solve in floats (``friction_one``)
        self.revolute_list, self.mu_r_list = self.revolute.tolist(), self.mu_r.tolist()
        self.two_over_l_list, self.still_list = self.two_over_l.tolist(), self.still.tolist()

    def columns(self, phi: np.ndarray):
        """(A (n, C, 4), G (n, C, K), rel (n, K)) at crank angles φ (n,)."""
        v = np.atleast_2d(self.table.at(phi))
        n, c, k = v.shape[0], self.c, self.k
        a = v[:, :4 * c].reshape(n, 4, c).transpose(0, 2, 1)
        g = v[:, 4 * c:4 * c + c * k].reshape(n, k, c).transpose(0, 2, 1)
        return a, g, v[:, 4 * c + c * k:]

    def solve(self, phi, omega, epsilon=None, free=None, inertia=None, s=None, guess=None):
        """Each pair's Coulomb friction f (n, K) at crank angles φ, speeds ω (each (n,)) and
        either the given accelerations ``epsilon`` (n,) or the ε (n,) that solves the machine's
        equation inertia·ε = free + s·Σ f_k·rel_k (``free``, ``inertia``, ``s`` (n,)), from the
        friction ``guess`` (n, K) or the frictionless reactions' one. Returns (f, ε, rel (n, K), ok
        (n,)): ok where Newton converged to a fixed point the closed form's own iteration reaches
        (the friction's Jacobian I + coef·∂ρ/∂R·G has a positive determinant) and, solving for ε,
        where the effective inertia J − s·Σ rel_k·∂f_k/∂ε is > 0; the caller solves the other
        states by the closed form (``machine.friction``), which names why they lock.

        With ε unknown it is eliminated first: ε = (free + s·rel·f)/J makes R = P + Q·f with
        P = base + A_ε·free/J and Q = G + A_ε ⊗ s·rel/J, and the effective inertia is
        J·det(I + coef·∂ρ·Q)/det(I + coef·∂ρ·G) (the joint system's two Schur complements).
        A single state is solved in floats (``friction_one``: the same iteration)."""
        out = (self._one(phi, omega, epsilon, free, inertia, s, guess) if np.size(phi) == 1 else
               self._many(phi, omega, epsilon, free, inertia, s, guess))
        if not self.table.periodic:  # a drive's partial range: the closed form beyond its ends
            x = np.reshape(np.asarray(phi, dtype=float), -1)
            out[3][:] &= (x >= self.table.start) & (x <= self.table.start + self.table.period)
        return out

    def _many(self, phi, omega, epsilon, free, inertia, s, guess):
        a, g, rel = self.columns(phi)
        n, k = rel.shape[0], self.k
        w = np.broadcast_to(np.asarray(omega, dtype=float), (n,))
        coef = np.where(np.abs(rel) > self.still, np.sign(w[:, None] * rel), 0.0) * self.mu_r  # f = −coef·ρ(R)
        de = a[:, :, 2]
        base = a[:, :, 0] + (w * w)[:, None] * a[:, :, 1] + w[:, None] * a[:, :, 3]
        joint = epsilon is None
        if joint:
            free, inertia, s = (np.broadcast_to(np.asarray(v, dtype=float), (n,)) for v in (free, inertia, s))
            base = base + (free / inertia)[:, None] * de
            q = g + de[:, :, None] * (s / inertia)[:, None, None] * rel[:, None, :]
        else:
            base = base + np.asarray(epsilon, dtype=float).reshape(-1, 1) * de
            q = g
        qx, qy = q[:, 0::2, :], q[:, 1::2, :]
        f = -coef * self._rho(base)[0] if guess is None else np.array(np.broadcast_to(guess, (n, k)), dtype=float)
        eye = np.eye(k)
        ok = np.zeros(n, dtype=bool)
        for _ in range(MAX_NEWTON):
            rho, dx, dy = self._rho(base + np.matmul(q, f[:, :, None])[:, :, 0])
            jac = coef[:, :, None] * (dx[:, :, None] * qx + dy[:, :, None] * qy) + eye
            with np.errstate(all="ignore"):
                step = np.linalg.solve(jac, (f + coef * rho)[:, :, None])[:, :, 0]
            f = f - step
            if not np.isfinite(step).all():
                break
            if (np.abs(step) <= NEWTON_TOL * np.abs(f)).all() or not np.any(step):
                ok[:] = True
                break
        eps = (free + s * np.einsum("nk,nk->n", rel, f)) / inertia if joint else np.broadcast_to(epsilon, (n,))
        if ok.all():
            with np.errstate(all="ignore"):
                ok = np.linalg.det(jac) > 0
                if joint:  # the friction's own fixed point (Q → G) must be one the closed form reaches too
                    gx, gy = g[:, 0::2, :], g[:, 1::2, :]
                    ok &= np.linalg.det(coef[:, :, None] * (dx[:, :, None] * gx + dy[:, :, None] * gy) + eye) > 0
        return f, eps, rel, ok

    def _one(self, phi, omega, epsilon, free, inertia, s, guess):
        from linkgen.machine.friction_one import solve_one

        v = self.table.at(np.reshape(np.asarray(phi, dtype=float), (1,)))[0].tolist()
        one = (lambda x: None if x is None else float(np.reshape(x, -1)[0]))
        f, eps, rel, ok = solve_one(self, v, one(omega), one(epsilon), one(free), one(inertia), one(s),
                                    None if guess is None else np.reshape(guess, -1).tolist(), NEWTON_TOL, MAX_NEWTON)
        return np.array([f]), np.array([eps]), np.array([rel]), np.array([ok])

    def _rho(self, r: np.ndarray):
        """ρ_k (n, K) and its derivatives by each pair's two components (n, K) each, for the pairs'
        reaction components R (n, C): a revolute's (Rx, Ry), a prismatic pair's (N, M)."""
        x, y = r[:, 0::2], r[:, 1::2]
        norm = np.hypot(x, y)
        safe = np.where(norm > 0, norm, 1.0)
        lever = self.two_over_l * np.abs(y)
        by_n = np.abs(x) >= lever
        rho = np.where(self.revolute, norm, np.where(by_n, np.abs(x), lever))
        dx = np.where(self.revolute, x / safe, np.where(by_n, np.sign(x), 0.0))
        dy = np.where(self.revolute, y / safe, np.where(by_n, 0.0, self.two_over_l * np.sign(y)))
        return rho, dx, dy


class _Spline:
    """Columns (m, p) through quintic splines over one turn (periodic where nothing jumps, else
    not-a-knot from each jump to the next, a piece too short for a quintic cubic): C⁴ between the
    jumps, so that an ODE solver of order 8 sees no kink in the friction (a cubic's third
    derivative jumps at every grid angle)."""

    def __init__(self, x: np.ndarray, v: np.ndarray, periodic: bool):
        from scipy.interpolate import CubicSpline, PPoly, make_interp_spline

        self.start, self.period, self.periodic = float(x[0]), float(x[-1] - x[0]), periodic
        pieces = np.split(np.arange(x.size), np.flatnonzero(np.diff(x) == 0.0) + 1)
        polys = []
        for k in pieces:
            if k.size > DEGREE:
                bc = "periodic" if len(pieces) == 1 and periodic else None
                b = make_interp_spline(x[k], v[k], k=DEGREE, bc_type=bc)
                # the piece's polynomials from the spline's derivatives at each interval's left end
                c = np.stack([b(x[k][:-1], nu=DEGREE - m) / math.factorial(DEGREE - m) for m in range(DEGREE + 1)])
            else:
                c = CubicSpline(x[k], v[k], bc_type="not-a-knot" if k.size > 2 else "natural").c
                c = np.concatenate([np.zeros((DEGREE + 1 - c.shape[0],) + c.shape[1:]), c])
            polys.append((c, x[k]))
        self.poly = PPoly(np.concatenate([c for c, _ in polys], axis=1),
                          np.concatenate([polys[0][1]] + [xs[1:] for _, xs in polys[1:]]))

    def at(self, phi):
        """The columns at crank angles φ [rad] (any turn; right-continuous at a jump)."""
        x = np.asarray(phi, dtype=float)
        if self.periodic:
            x = x - np.floor((x - self.start) / self.period) * self.period
        return self.poly(x)


def build(asm: Assembly) -> FrictionTable | None:
    """The table of ``asm``'s friction pairs (None: gears, a grid of MAX_CELLS not enough, or a
    turn the closed form does not cover everywhere, e.g. through a singular pose),
    built once per assembly (the ODE and MuJoCo's run of a comparison share it)."""
    from linkgen.errors import LinkgenError

    cached = getattr(asm, "_friction_table", False)
    if cached is not False:
        return cached
    try:
        table = _build(asm)
    except LinkgenError:  # singular or not assembled somewhere on the turn: each state by the closed form
        table = None
    object.__setattr__(asm, "_friction_table", table)
    return table


def _build(asm: Assembly) -> FrictionTable | None:
    mech = asm.mechanism
    if mech.gears or not mech.frictions:
        return None
    d = mech.drive
    full = d.stop - d.start >= 2 * math.pi - 1e-9
    span = 2 * math.pi if full else d.stop - d.start
    switches = switch_angles(mech, d.start)
    cells = FIRST_CELLS
    while cells <= MAX_CELLS:
        grid, where = jump_grid(d.start, cells, switches, span)
        table = _Spline(grid, _values(asm, where), full)
        wide = np.diff(grid) > 0
        middle = 0.5 * (grid[:-1] + grid[1:])[wide]
        error = _gap(asm, table.at(middle), _values(asm, middle))
        if error <= TABLE_TOL:
            return FrictionTable(asm, table, error, cells)
        cells *= 2
    return None


def _gap(asm: Assembly, spline: np.ndarray, exact: np.ndarray) -> float:
    """The worst gap between the splines and the closed form, relative to each block's peak."""
    k = len(asm.mechanism.frictions)
    c = 2 * k
    edges = [0, c, 2 * c, 3 * c, 4 * c] + [4 * c + c * (j + 1) for j in range(k)] + [4 * c + c * k + k]
    worst = 0.0
    for lo, hi in zip(edges[:-1], edges[1:]):
        peak = float(np.abs(exact[:, lo:hi]).max())
        if peak > 0:
            worst = max(worst, float(np.abs(spline[:, lo:hi] - exact[:, lo:hi]).max()) / peak)
    return worst


def _values(asm: Assembly, phi: np.ndarray) -> np.ndarray:
    """The columns (n, 4C + C·K + K) at crank angles φ (n,) from the closed form."""
    from linkgen.families.planar.friction import pair_loads, relative_rate
    from linkgen.families.planar.kinematics import solve
    from linkgen.families.planar.loads import applied_loads, mass_table
    from linkgen.families.planar.reactions import solve_reactions

    mech = asm.mechanism
    kin = solve(asm, phi)
    n = phi.shape[0]
    masses = mass_table(asm)
    rest, moving = applied_loads(asm, kin, omega=0.0), applied_loads(asm, kin, omega=1.0)
    com = {name: rest[name].com.p for name in masses}
    zero = {name: [np.zeros((n, 2)), np.zeros(n)] for name in masses}

    def inertia(order: str):
        return {name: [-mp.mass * getattr(rest[name].com, order), -mp.inertia * getattr(kin.links[name].angle, order)]
                for name, mp in masses.items()}

    cases = [{name: [rest[name].force, rest[name].moment] for name in masses}, inertia("d2"), inertia("d1"),
             {name: [moving[name].force - rest[name].force, moving[name].moment - rest[name].moment] for name in masses}]
    for fr in mech.frictions:
        case = dict(zero)
        case.update(pair_loads(asm, kin, com, fr, np.ones(n)))
        cases.append(case)
    out = []
    for case in cases:
        _, reactions, normal, moment, *_ = solve_reactions(asm, kin, case, com, kin.singular)
        for fr in mech.frictions:
            if fr.pin_radius is not None:
                out += [reactions[fr.pair][:, 0], reactions[fr.pair][:, 1]]
            else:
                out += [normal[fr.pair], moment[fr.pair]]
    out += [relative_rate(asm, kin, fr)[0] for fr in mech.frictions]
    return np.stack([np.broadcast_to(v, (n,)) for v in out], axis=1)


__all__ = ["FrictionTable", "MAX_CELLS", "NEWTON_TOL", "TABLE_TOL", "build"]
