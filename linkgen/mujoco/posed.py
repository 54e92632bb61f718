"""Mechanisms the closed form does not cover (groups of class III and higher) as the MuJoCo
side needs them: the description, link shapes, guides and the numeric reference pose
(``linkgen.families.planar.pose``), standing in for an Assembly where no Assur groups are needed."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.description import Mechanism
from linkgen.errors import SimulationError
from linkgen.families.planar.geometry import GuideShape, LinkShape, guide_shapes, link_shapes, sketch_input
from linkgen.families.planar.kinematics import solve
from linkgen.families.planar.pose import LinkStates, reference_pose


@dataclass(frozen=True)
class Posed:
    """A mechanism with its shapes, guides, sketch crank angle [rad] and reference pose."""

    mechanism: Mechanism
    shapes: dict[str, LinkShape]
    guides: dict[str, GuideShape]
    sketch_phi: float
    reference: LinkStates


def posed(mech: Mechanism) -> Posed:
    """The numeric stand-in for ``assemble(mech)`` (raises as ``pose.state`` does)."""
    shapes = link_shapes(mech)
    return Posed(mech, shapes, guide_shapes(mech, shapes), sketch_input(mech, shapes), reference_pose(mech))


def slider_reference(source: Assembly | Posed) -> dict[str, float]:
    """Each prismatic pair's displacement [m] along its guide (from the guide's base point) at
    the reference pose, which MuJoCo's slide joints count from."""
    if isinstance(source, Assembly):
        ref = solve(source, np.array([source.sketch_phi]))
        return {n: float(s.v[0]) for n, s in ref.sliders.items()}
    ref = source.reference
    out = {}
    for name, g in source.guides.items():
        base = ref.point(g.guide, g.base)[0]
        th = float(ref.angle[g.guide][0]) + g.alpha
        out[name] = float((ref.point(g.slider, g.point)[0] - base) @ np.array([math.cos(th), math.sin(th)]))
    return out


def torque_schedule(source: Posed, model, n: int) -> np.ndarray:
    """``xfrc_applied`` rows (n, 6·nbody) for a Posed mechanism's link torques (constant);
    point forces would need the closed form's positions to be scheduled, so they are refused."""
    from linkgen.families.planar.description import GROUND
    from linkgen.mujoco.tree import body_name

    mech = source.mechanism
    if any(f.link != GROUND for f in mech.forces):
        raise SimulationError("point forces on a mechanism the closed form does not cover are not simulated yet "
                              "(gravity and link torques are)")
    out = np.zeros((n, model.nbody, 6))
    for t in mech.torques:
        if t.link != GROUND:
            out[:, model.body(body_name(t.link)).id, 5] += t.torque
    return out.reshape(n, -1)


__all__ = ["Posed", "posed", "slider_reference", "torque_schedule"]
