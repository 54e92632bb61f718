"""Closed-form kinetostatics: joint reactions and the balancing torque, group by group.

The method of Buynachev, Bazhenov, Troitsky (2019), §1 and §6: with d'Alembert's inertia loads (−m·a_S at the centre of
mass, −I·ε about it) every link is in equilibrium, and each class-II Assur group is
statically determinate on its own — 6 equations (3 per link) in the 6 unknowns of its
three pairs. The groups are solved from the last attached back to the first, each one's
outer reactions becoming given loads on the links it hangs from; the crank's 3 equations
then give the drive pair's reaction and the balancing torque. Everything is vectorised
over crank angles (each group's six equations in closed form, ``equilibrium``), in the kinematics' blocks, and the
result is checked against the power balance on every call (BALANCE_TOL).

Sign conventions (the same for every family: docs/format.md, "Conventions"; each pair's two
links are in ``Forces.on`` and ``Forces.by``):
    * Revolute pair ``J`` between links (first, second) in the description's order
      (``Mechanism.revolutes``: the order of the ``[links.NAME]`` tables): ``reactions[J]`` is
      the force [N] the *second* link exerts on the *first*, world frame, shape (n, 2).
    * Prismatic pair: ``normal_force`` [N] is the guide's force on the slider along the
      guide line's left normal; ``moment`` [N·m] is the couple the guide exerts on the
      slider (about +z) when the normal force is placed at the slider's ``point``. Along the
      line the pair carries only its Coulomb friction, if it has any (``Forces.friction``).
    * Friction (``[[friction]]``, ``planar.friction``): the reactions depend on it and it on
      them; solved by fixed-point iteration from the frictionless solution (FRICTION_TOL), the
      power balance then adding the friction's losses; FrictionError where it has no solution.
    * ``balancing_torque`` [N·m]: the torque the drive applies to the crank, about +z.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from linkgen.families.planar.assembly import Assembly, assemble
from linkgen.families.planar.blocks import in_blocks
from linkgen.errors import BalanceError, FrictionError, angle_ranges
from linkgen.families.planar.friction import FrictionLoads, friction_loads
from linkgen.families.planar.kinematics import BlockFailed, Kinematics, checked_angles, checked_mode, raise_failure, solve_block
from linkgen.families.planar.motion import rate
from linkgen.families.planar.loads import applied_loads, mass_table
from linkgen.families.planar.reactions import solve_reactions


@dataclass(frozen=True)
class Forces:
    """Reactions and torques over crank angles ``phi`` (n,) at crank speed ``omega`` and
    acceleration ``epsilon`` (each (n,)). See the module docstring for the sign conventions.

    Attributes:
        balancing_torque: (n,) [N·m] from the group-by-group solution.
        power_balance_torque: (n,) [N·m] the same from virtual work (Σ F·v′ + M·θ′ = 0), plus
            the friction's lost power over ω from the pairs' relative rates: an independent check.
        reactions: revolute name → (n, 2) [N].
        normal_force, moment: prismatic name → (n,) [N], [N·m].
        reduced: the reduced dynamics at these angles.
        tooth: gear pair name → the tooth force on its planet (n, 2) [N]: the tangential part
            from the planet's moment balance about its centre, the radial part |F_t|·tan α
            pushing the gears apart (along the line of action at the pressure angle α).
        contact: cam pair name → the contact force N (n,) [N] the cam presses on its follower's
            roller with, along the pitch curve's outward normal through the roller's centre
            (``planar.cam_pair``); N < 0 where the follower would leave the cam.
        singular: (n,) True at angles marked singular (``on_singular="mark"``); there every
            force and torque is 0.
        on, by: pair name → the link its reaction acts on and the link that exerts it: a
            revolute's first and second link in the description's order, a prismatic pair's
            slider and guide.
        friction: pair name → (n,) its Coulomb friction (``planar.friction``): the couple on a
            revolute's first link [N·m], the force on a slider along its guide's direction [N].
        friction_power: (n,) [W] the power the friction takes out (≥ 0; zeros without friction).
    """

    def __repr__(self) -> str:
        return f"Forces({self.phi.shape[0]} angles, {len(self.reactions)} reactions, {len(self.normal_force)} prismatic pairs)"


    phi: np.ndarray
    omega: np.ndarray
    epsilon: np.ndarray
    balancing_torque: np.ndarray
    power_balance_torque: np.ndarray
    reactions: dict[str, np.ndarray]
    normal_force: dict[str, np.ndarray]
    moment: dict[str, np.ndarray]
    reduced: "ReducedDynamics"
    singular: np.ndarray
    tooth: dict = field(default_factory=dict)
    contact: dict = field(default_factory=dict)
    on: dict = field(default_factory=dict)
    by: dict = field(default_factory=dict)
    friction: dict = field(default_factory=dict)
    friction_power: np.ndarray | None = None


@dataclass(frozen=True)
class ReducedDynamics:
    """The mechanism reduced to the crank, over φ (each (n,)).

    inertia J(φ) = Σ m·|v_S′|² + I·θ′² [kg·m²]; inertia_derivative dJ/dφ [kg·m²/rad];
    moment: reduced moment of the given loads (gravity, forces, torques, springs, dampers at the
    crank speed ω) Σ F·v′ + M·θ′ [N·m]; damping: its part per unit ω, the reduced damping
    ∂M/∂ω = −Σ c·(dL/dφ)² − Σ c_t·(dθ/dφ)² [N·m·s/rad] (≤ 0; 0 without dampers), so that the
    moment at another speed ω′ is moment + damping·(ω′ − ω).
    The balancing torque then is T = J·ε + ½·J′·ω² − moment.
    """

    inertia: np.ndarray
    inertia_derivative: np.ndarray
    moment: np.ndarray
    damping: np.ndarray | None = None


def reduced_dynamics(asm: Assembly, kin: Kinematics, loads: dict | None = None, omega=0.0) -> ReducedDynamics:
    """J(φ), dJ/dφ, the reduced moment of the given loads at crank speed ``omega`` and the reduced
    damping at the angles of ``kin`` (``loads``: ``applied_loads(asm, kin, omega=omega)`` if
    already at hand)."""
    loads = applied_loads(asm, kin, omega=omega) if loads is None else loads
    n = kin.phi.shape[0]
    j, dj, m_red = np.zeros(n), np.zeros(n), np.zeros(n)
    for name, mp in mass_table(asm).items():
        s, th = loads[name].com, kin.links[name].angle
        j += mp.mass * np.einsum("ij,ij->i", s.d1, s.d1) + mp.inertia * th.d1**2
        dj += 2.0 * (mp.mass * np.einsum("ij,ij->i", s.d1, s.d2) + mp.inertia * th.d1 * th.d2)
        m_red += np.einsum("ij,ij->i", loads[name].force, s.d1) + loads[name].moment * th.d1
    return ReducedDynamics(j, dj, m_red, reduced_damping(asm, kin))


def reduced_damping(asm: Assembly, kin: Kinematics) -> np.ndarray:
    """∂M/∂ω (n,) [N·m·s/rad]: −Σ c·(dL/dφ)² over the dampers between points, −Σ c·(dθ/dφ)² over
    the torsional ones (``planar.springs``)."""
    from linkgen.families.planar.spring_loads import spring_lengths, torsion_deflection

    mech = asm.mechanism
    out = np.zeros(kin.phi.shape[0])
    for s in mech.springs:
        if s.damping:
            out -= s.damping * spring_lengths(kin, s)[1] ** 2
    for t in mech.torsion_springs:
        if t.damping:
            out -= t.damping * torsion_deflection(kin, t)[1] ** 2
    return out


# The balancing torque by two routes must agree to this fraction of the torque scale S (per
# angle: Σ|F·S′| + |M·θ′| over the links' total loads, plus |R|·span of every reaction on the
# crank, the sizes of the terms each route adds up). Each route rounds at ~eps·S per operation;
# the group route also goes through one LU solve of a 6×6 system per group, whose forward error
# is ~κ·eps with κ ≲ (ratio of the group's lengths ≲ 1e2)/|D| and |D| ≥ SINGULAR_TOL = 1e-4
# (linkgen.groups): ≲ 2e-10 per group, a few groups chained. 1e-8 leaves a margin of ~10 over
# that and still catches any wrong or missing term, which shows at the size of S itself.
# Measured on the bundled models: ≤ 1.5e-15 of the peak torque.
BALANCE_TOL = 1e-8


def forces(mech_or_asm, phi, omega, epsilon=0.0, threads: int | None = None, *,
           on_singular: str = "raise") -> Forces:
    """Kinetostatics at crank angles ``phi`` [rad] (n,), crank speed ω [rad/s] and
    acceleration ε [rad/s²] (scalars or (n,)), in the cache-sized blocks of the kinematics
    (``linkgen.blocks``: the memory besides the results does not grow with n). Every call
    compares the group-by-group balancing torque with the power balance (BALANCE_TOL).
    ``on_singular="mark"``: return normally with ``Forces.singular`` True at singular angles,
    where every force is set to 0.

    Raises:
        ArgumentError: ω or ε not finite, or neither scalar nor (n,); a bad ``on_singular``.
        AssemblyError / SingularityError / MagnitudeError: as ``solve``.
        BalanceError: the two balancing torques disagree (names the angles).
    """
    mark = checked_mode(on_singular)
    asm = mech_or_asm if isinstance(mech_or_asm, Assembly) else assemble(mech_or_asm)
    phi = checked_angles(phi)
    n = phi.shape[0]
    w, e = rate("omega", omega, n, "rad/s"), rate("epsilon", epsilon, n, "rad/s²")

    def block(rows: slice):
        (poses, points, sliders, near, marked), ok = solve_block(asm, phi[rows], mark)
        if not ok:
            raise BlockFailed
        kin = Kinematics(asm, phi[rows], poses, points, sliders, near, marked)
        wr, er = (w if np.ndim(w) == 0 else w[rows]), (e if np.ndim(e) == 0 else e[rows])
        return _block_forces(asm, kin, np.broadcast_to(wr, kin.phi.shape), np.broadcast_to(er, kin.phi.shape), mark)

    try:
        tree, infos = in_blocks(block, n, threads)
    except BlockFailed:
        raise_failure(asm, phi, mark)
        raise
    locked = [r for info in infos for r in info[2]]
    if locked:
        raise FrictionError(locked)
    bad = [r for info in infos for r in info[0]]
    if bad:
        raise BalanceError(bad, max(info[1] for info in infos), BALANCE_TOL)
    torque, power, reactions, normal, moment, (j, dj, m_red, c_red), marked, tooth, contact, friction, loss = tree
    mech = asm.mechanism
    on = {r.name: r.links[0] for r in mech.revolutes} | {p.name: p.slider for p in mech.prismatics}
    by = {r.name: r.links[1] for r in mech.revolutes} | {p.name: p.guide for p in mech.prismatics}
    return Forces(phi, np.array(np.broadcast_to(w, (n,))), np.array(np.broadcast_to(e, (n,))), torque, power,
                  reactions, normal, moment, ReducedDynamics(j, dj, m_red, c_red), marked, tooth, contact, on, by,
                  friction, loss * np.abs(np.broadcast_to(w, (n,))))


@np.errstate(invalid="ignore", divide="ignore", over="ignore")  # found and named by angle below
def _block_forces(asm: Assembly, kin: Kinematics, w: np.ndarray, e: np.ndarray, mark: bool = False):
    """One block's forces: (tree, (balance failures as angle ranges, worst relative deviation,
    angle ranges where the friction has no solution))."""
    mech = asm.mechanism
    n = kin.phi.shape[0]
    marked = kin.singular
    given = applied_loads(asm, kin, omega=w)
    masses = mass_table(asm)
    # Total load on each link (given + d'Alembert), force (n,2) and moment about its centre of mass.
    load: dict[str, list[np.ndarray]] = {}
    for name, mp in masses.items():
        s, th = given[name].com, kin.links[name].angle
        acc = s.d2 * (w * w)[:, None] + s.d1 * e[:, None]
        alpha = th.d2 * w * w + th.d1 * e
        load[name] = [given[name].force - mp.mass * acc, given[name].moment - mp.inertia * alpha]
    # Virtual work with the crank turned by δφ: T + Σ (F·S′ + M·θ′) = 0; the terms' sizes give the scale.
    power, scale = np.zeros(n), np.zeros(n)
    for name in masses:
        f_term = np.einsum("ij,ij->i", load[name][0], given[name].com.d1)
        m_term = load[name][1] * kin.links[name].angle.d1
        power += f_term + m_term
        scale += np.hypot(*load[name][0].T) * np.hypot(*given[name].com.d1.T) + np.abs(m_term)
    com = {name: given[name].com.p for name in masses}
    locked: list = []
    sol = solve_reactions(asm, kin, load, com, marked)
    friction, loss = {}, np.zeros(n)
    if mech.frictions:
        sol, applied, marked, locked = _with_friction(asm, kin, w, load, com, marked, sol, mark)
        friction, loss = applied.pair, applied.loss
        # The losses, from the pairs' relative rates (``friction``), add sgn(ω)·loss to the torque.
        power = power - np.sign(w) * loss
        scale = scale + loss
    torque, reactions, normal, moment, tooth, contact, sol_scale = sol
    scale = scale + sol_scale
    power = -power
    red = reduced_dynamics(asm, kin, given)
    if marked.any():
        for arr in (power, red.inertia, red.inertia_derivative, red.moment, red.damping, loss):
            arr[marked] = 0.0
    bad, worst = balance_failures(kin.phi, torque, power, scale, marked)
    tree = (torque, power, reactions, normal, moment, (red.inertia, red.inertia_derivative, red.moment, red.damping),
            marked, tooth, contact, friction, loss)
    return tree, (bad, worst, locked)


# The friction iteration (``_with_friction``) stops at an angle when no pair's friction changes by
# more than this fraction of its value from one pass to the next. Each pass is the frictionless
# solution's arithmetic (rounding ~1e-15 relative, times the groups' condition ≲ 1e2 as for
# BALANCE_TOL), so 1e-12 is reachable, and it leaves the reactions within ~1e-12 of the fixed point
# times 1/(1 − contraction), the contraction being ~μ·r/arm or μ·tan(pressure angle) (< 1 where it
# converges in MAX_FRICTION_PASSES).
FRICTION_TOL = 1e-12
# Passes: a contraction of 0.93 reaches FRICTION_TOL in ~380; more than this is a mechanism so close
# to self-locking that its torques are not worth reporting.
MAX_FRICTION_PASSES = 400
# An angle whose total friction grows past this multiple of the first pass's diverges (self-locks).
FRICTION_GROWTH = 1e6


def _with_friction(asm: Assembly, kin: Kinematics, w: np.ndarray, load: dict, com: dict, marked: np.ndarray, sol,
                   mark: bool):
    """Fixed-point iteration on the reactions from the frictionless solution ``sol``: each pass
    applies a friction as given loads, solves again and takes the friction of the new reactions,
    until that is the one applied (FRICTION_TOL). The next pass applies the new friction, or where
    the residual (new − applied) did not shrink, a step λ of the way to it, λ halved each time
    (under-relaxation: a pass whose friction overshoots, as where the friction's share of a pair's
    reaction turns against it, then converges; a mechanism that self-locks still does not).
    Returns (the last solution, the friction loads it was solved with, the angles marked
    singular (with the self-locked ones if ``mark``: ``on_singular="mark"``), angle ranges where
    it finds no solution (raise))."""
    n = kin.phi.shape[0]
    tiny = np.finfo(float).tiny
    applied = friction_loads(asm, kin, w, com, *sol[1:4])
    first = sum(np.abs(v) for v in applied.pair.values()) + tiny
    done = np.zeros(n, dtype=bool)
    failed = np.zeros(n, dtype=bool)
    step, last = np.ones(n), np.full(n, np.inf)
    for _ in range(MAX_FRICTION_PASSES):
        sol = solve_reactions(asm, kin, load, com, marked | failed, applied.link)
        new = friction_loads(asm, kin, w, com, *sol[1:4])
        change = np.zeros(n, dtype=bool)
        residual = np.zeros(n)
        for k, v in new.pair.items():
            gap = np.abs(v - applied.pair[k])
            change |= ~(gap <= FRICTION_TOL * np.maximum(np.abs(v), np.abs(applied.pair[k])))
            residual += gap
        done = ~change | marked
        failed |= ~(sum(np.abs(v) for v in new.pair.values()) <= FRICTION_GROWTH * first)
        if np.all(done | failed):
            break
        step = np.where(residual >= last, 0.5 * step, step)
        last = residual
        applied = _zeroed(_toward(applied, new, step), failed)
    failed |= ~done & ~marked
    if mark and failed.any():
        marked = marked | failed
        sol = solve_reactions(asm, kin, load, com, marked, _zeroed(applied, failed).link)
    return sol, _zeroed(applied, failed), marked, [] if mark else angle_ranges(kin.phi, failed)


def _toward(a: FrictionLoads, b: FrictionLoads, step: np.ndarray) -> FrictionLoads:
    """a + step·(b − a) per angle: every part of the friction loads is linear in the pairs' values,
    whose signs the kinematics fix, so a step between two of them is itself one."""
    if np.all(step == 1.0):
        return b
    s2 = step[:, None]
    return FrictionLoads({k: [a.link[k][0] + s2 * (f - a.link[k][0]), a.link[k][1] + step * (m - a.link[k][1])]
                          for k, (f, m) in b.link.items()},
                         {k: a.pair[k] + step * (v - a.pair[k]) for k, v in b.pair.items()},
                         a.loss + step * (b.loss - a.loss))


def _zeroed(fl: FrictionLoads, rows: np.ndarray) -> FrictionLoads:
    """``fl`` with no friction at ``rows`` (angles that diverged: kept finite for the next pass)."""
    if not rows.any():
        return fl
    keep = ~rows
    return FrictionLoads({k: [f * keep[:, None], m * keep] for k, (f, m) in fl.link.items()},
                         {k: v * keep for k, v in fl.pair.items()}, fl.loss * keep)


def balance_failures(phi: np.ndarray, torque: np.ndarray, power: np.ndarray, scale: np.ndarray,
                     skip: np.ndarray) -> tuple[list[tuple[float, float]], float]:
    """Where the two balancing torques [N·m] (n,) differ by more than BALANCE_TOL of the torque
    scale (n,) [N·m], outside ``skip``: (angle ranges, worst relative deviation)."""
    rel = np.abs(torque - power) / np.maximum(scale, np.finfo(float).tiny)
    bad = ~(rel <= BALANCE_TOL) & ~skip
    return (angle_ranges(phi, bad), float(rel[bad].max())) if bad.any() else ([], 0.0)


__all__ = ["BALANCE_TOL", "Forces", "ReducedDynamics", "balance_failures", "forces", "reduced_dynamics"]
