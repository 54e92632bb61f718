"""Coulomb friction in the pairs (``[[friction]]``, ``families.planar.friction``) in MuJoCo runs.

MuJoCo's own ``frictionloss`` is a fixed limit, independent of the pair's load: it cannot carry a
friction μ·r·|R| that grows with the reaction. linkgen applies the friction itself each step, as it
applies the description's forces and torques, through ``xfrc_applied``: a revolute's friction
couple on its two links' bodies, a slider's friction force along its guide at the slider's point
(and its opposite on the guide). The friction is the closed form's (``kinetostatics.forces``) at
MuJoCo's crank angle and speed, not one computed from MuJoCo's own reactions of the step: those
follow from the constraint solve the applied forces enter, so a friction read from them lags a
step behind its own effect (an algebraic loop through the soft loop constraints); the validation
then checks the fixed point by recomputing the friction from MuJoCo's reactions
(``friction_from_reactions``) against the one applied. The MJCF file does not carry the friction
(its header says so); a user's own run applies it as linkgen does.
"""

from __future__ import annotations

import mujoco
import numpy as np

from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.description import GROUND
from linkgen.families.planar.friction_switches import SWITCH_BISECTIONS, SWITCH_GRID, friction_switches  # noqa: F401 (re-exported)
from linkgen.mujoco.tree import body_name, site_name

HEADER_NOTE = ("Friction in the pairs ([[friction]]) is not in this file: MuJoCo's frictionloss does not grow with "
               "a pair's load, so linkgen applies the closed form's friction couples and forces each step through "
               "xfrc_applied (docs/format.md, [[friction]]). ")


def friction_at(asm: Assembly, phi, omega, epsilon, mark: str = "raise") -> dict[str, np.ndarray]:
    """Each pair's friction (couple on a revolute's first link [N·m], force on a slider along its
    guide [N]) from the closed form at crank angles ``phi`` (n,), speed and acceleration
    (``mark="mark"``: zero where the closed form is singular or finds no solution); "raise" through
    the mechanism's friction table (``machine.friction.friction_values``: the same fixed point to
    ~1e-13, without building the kinetostatics each step)."""
    from linkgen.families.planar.kinetostatics import forces

    if mark == "raise":
        from linkgen.machine.friction import friction_values

        return friction_values(asm, phi, omega, epsilon)[0]
    return forces(asm, np.atleast_1d(np.asarray(phi, dtype=float)), omega, epsilon, on_singular=mark).friction


def add_friction(asm: Assembly, model: mujoco.MjModel, data: mujoco.MjData, friction: dict[str, float]) -> None:
    """Add the pairs' friction (``friction_at`` at one angle) to ``xfrc_applied`` at MuJoCo's
    current positions (``mj_kinematics`` done)."""
    mech = asm.mechanism
    for fr in mech.frictions:
        value = float(friction[fr.pair])
        if fr.pin_radius is not None:
            for link, sign in zip(mech.revolute(fr.pair).links, (1.0, -1.0)):
                if link != GROUND:
                    data.xfrc_applied[model.body(body_name(link)).id, 5] += sign * value
            continue
        g = asm.guides[fr.pair]
        u = np.array([*data.joint(fr.pair).xaxis[:2], 0.0])
        at = data.site(site_name(asm, g.slider, mech.prismatic(fr.pair).point)).xpos
        for link, sign in ((g.slider, 1.0), (g.guide, -1.0)):
            if link != GROUND:  # at the body's centre of mass, with its moment about it
                b, f = model.body(body_name(link)).id, sign * value * u
                data.xfrc_applied[b, :3] += f
                data.xfrc_applied[b, 3:] += np.cross(at - data.xipos[b], f)


def friction_schedule(asm: Assembly, model: mujoco.MjModel, phi: np.ndarray, omega, epsilon) -> np.ndarray:
    """``xfrc_applied`` rows (n, nbody, 6) of the friction at the closed form's positions over φ
    (n,): the open-loop input of a run's steps, as ``forces.load_schedule``."""
    from linkgen.families.planar.kinematics import solve
    from linkgen.families.planar.loads import mass_table

    mech = asm.mechanism
    n = phi.shape[0]
    out = np.zeros((n, model.nbody, 6))
    # a run's lead-in starts before the range: zero friction where the closed form has none there
    friction = friction_at(asm, phi, omega, epsilon, "mark")
    kin = solve(asm, phi, on_singular="mark")
    com = {name: kin.point(name, np.asarray(mp.com, dtype=float)).p for name, mp in mass_table(asm).items()}
    for fr in mech.frictions:
        value = friction[fr.pair]
        if fr.pin_radius is not None:
            for link, sign in zip(mech.revolute(fr.pair).links, (1.0, -1.0)):
                if link != GROUND:
                    out[:, model.body(body_name(link)).id, 5] += sign * value
            continue
        g = asm.guides[fr.pair]
        u = kin.links[g.guide].direction(g.alpha).p
        at = kin.links[g.slider].point(g.point).p
        for link, sign in ((g.slider, 1.0), (g.guide, -1.0)):
            if link == GROUND:
                continue
            b, f, arm = model.body(body_name(link)).id, sign * value[:, None] * u, at - com[link]
            out[:, b, 0:2] += f
            out[:, b, 5] += arm[:, 0] * f[:, 1] - arm[:, 1] * f[:, 0]
    return out


def friction_from_reactions(asm: Assembly, phi: np.ndarray, omega, reactions: dict, normal: dict,
                            moment: dict) -> dict[str, np.ndarray]:
    """Each pair's friction by the friction law (``families.planar.friction``) from the given
    reactions (e.g. MuJoCo's), at the closed form's relative rates at φ (n,)."""
    from linkgen.families.planar.friction import friction_loads
    from linkgen.families.planar.kinematics import solve
    from linkgen.families.planar.loads import mass_table

    kin = solve(asm, phi)
    com = {name: kin.point(name, np.asarray(mp.com, dtype=float)).p for name, mp in mass_table(asm).items()}
    w = np.broadcast_to(np.asarray(omega, dtype=float), phi.shape)
    return friction_loads(asm, kin, w, com, reactions, normal, moment).pair


__all__ = ["HEADER_NOTE", "add_friction", "friction_at", "friction_from_reactions", "friction_schedule",
           "friction_switches"]
