"""Loads on the links over crank angles: gravity, external forces and torques, mass properties.

Both the closed form (kinetostatics) and the MuJoCo side read the description's loads
through ``stroke_active`` and ``mass_table`` so that they apply the same inputs.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.description import GROUND, MassProperties, PointForce
from linkgen.families.planar.geometry import effective_mass_properties
from linkgen.families.planar.cam_pair import spring_load
from linkgen.families.planar.kinematics import Kinematics
from linkgen.families.planar.primitives import Vec
from linkgen.families.planar.spring_loads import spring_tension, torsion_torque
from linkgen.families.planar.springs import carrier
from linkgen.model.strokes import stroke_active


def mass_table(asm: Assembly) -> dict[str, MassProperties]:
    """Mass properties of every moving link (the description's or the stated defaults),
    the same ones the MJCF writer puts into the model."""
    return {n: effective_mass_properties(asm.mechanism, asm.shapes, n) for n in asm.mechanism.moving_links}


@dataclass(frozen=True)
class LinkLoad:
    """The given (non-inertial) load on a link over φ: resultant force (n, 2) [N] and
    moment about the link's centre of mass (n,) [N·m]; ``com`` is the centre of mass (Vec)."""

    com: Vec
    force: np.ndarray
    moment: np.ndarray


def applied_loads(asm: Assembly, kin: Kinematics, gravity: bool = True, omega=0.0,
                  springs: bool = True) -> dict[str, LinkLoad]:
    """Gravity (unless ``gravity`` is False), external point forces (inside their strokes),
    external torques, cam followers' springs and (unless ``springs`` is False: a MuJoCo model
    has them as passive forces) the springs and dampers (``planar.springs``) per moving link;
    the dampers at crank speed ``omega`` [rad/s] (scalar or (n,))."""
    mech = asm.mechanism
    n = kin.phi.shape[0]
    g = np.asarray(mech.gravity if gravity else (0.0, 0.0), dtype=float)
    out = {}
    for name, mp in mass_table(asm).items():
        com = kin.point(name, np.asarray(mp.com, dtype=float))
        out[name] = LinkLoad(com, np.broadcast_to(mp.mass * g, (n, 2)).copy(), np.zeros(n))
    for f in mech.forces:
        if f.link == GROUND:
            continue
        load = out[f.link]
        on = stroke_active(f, kin.phi)[:, None]
        vec = np.where(on, np.asarray(f.force, dtype=float), 0.0)
        arm = kin.points[f.point].p - load.com.p
        load.force[:] += vec
        load.moment[:] += arm[:, 0] * vec[:, 1] - arm[:, 1] * vec[:, 0]
    for t in mech.torques:
        if t.link != GROUND:
            out[t.link].moment[:] += t.torque
    for cam in mech.cams:  # the follower's spring, against the rise
        load = out[cam.follower]
        force, torque = spring_load(kin, cam)
        arm = kin.points[cam.roller].p - load.com.p
        load.force[:] += force
        load.moment[:] += torque + arm[:, 0] * force[:, 1] - arm[:, 1] * force[:, 0]
    if springs:
        _add_springs(asm, kin, omega, out)
    return out


def _add_springs(asm: Assembly, kin: Kinematics, omega, out: dict[str, LinkLoad]) -> None:
    """Each spring's pair of forces along its line (T·u on its first point, −T·u on its second)
    and each torsion spring's pair of torques."""
    mech = asm.mechanism
    for s in mech.springs:
        tension, u = spring_tension(kin, s, omega)
        for point, sign in zip(s.points, (1.0, -1.0)):
            link = carrier(mech, point)
            if link == GROUND:
                continue
            load = out[link]
            force = sign * tension[:, None] * u
            arm = kin.points[point].p - load.com.p
            load.force[:] += force
            load.moment[:] += arm[:, 0] * force[:, 1] - arm[:, 1] * force[:, 0]
    for t in mech.torsion_springs:
        tau = torsion_torque(kin, t, omega)
        for link, sign in zip(t.links, (-1.0, 1.0)):
            if link != GROUND:
                out[link].moment[:] += sign * tau


__all__ = ["LinkLoad", "applied_loads", "mass_table", "stroke_active"]
