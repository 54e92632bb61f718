"""The loop closures in MuJoCo terms: their Jacobian, their forces from the closed form, and
the mechanism's length scale."""

from __future__ import annotations

import mujoco
import numpy as np

from linkgen.families.planar.assembly import Assembly
from linkgen.mujoco.tree import link_name, site_name, spanning_tree


def mechanism_size(asm: Assembly) -> float:
    """The sketch's diagonal [m]: the mechanism's natural length scale."""
    xy = np.array(list(asm.mechanism.points.values()))
    return float(np.hypot(*(xy.max(axis=0) - xy.min(axis=0))))


def acceleration_scale(size: float, omega: float, epsilon: float, gravity: float) -> float:
    """The accelerations' natural scale [m/s²]: size·(ω² + |ε|) + |g|. Gravity belongs in it:
    at a slow crank the loop forces, and so MuJoCo's resolution of accelerations, are set by g."""
    return size * (omega * omega + abs(epsilon)) + abs(gravity)


def closure_jacobian(asm: Assembly, model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """In-plane rows (x, y per loop-closing revolute) of J = J_body1 − J_body2 at each
    closure's point, shape (2·closures, nv). Needs ``mj_kinematics`` and ``mj_comPos``."""
    rows = []
    jp1, jp2 = np.zeros((3, model.nv)), np.zeros((3, model.nv))
    for pair in spanning_tree(asm).closures:
        eq = model.equality(pair.name).id
        b1, b2 = model.eq_obj1id[eq], model.eq_obj2id[eq]
        point = data.site(site_name(asm, link_name(model.body(b1).name), asm.mechanism.revolute(pair.name).point)).xpos
        mujoco.mj_jac(model, data, jp1, None, point, b1)
        jp2[:] = 0.0
        if b2 > 0:
            mujoco.mj_jac(model, data, jp2, None, point, b2)
        rows += [jp1[0] - jp2[0], jp1[1] - jp2[1]]
    return np.array(rows).reshape(-1, model.nv)


def closure_forces(asm: Assembly, model: mujoco.MjModel, reactions: dict[str, np.ndarray], k: int) -> np.ndarray:
    """The closed-form loop forces at sample k as forces on each connect's body1, (2·closures,)
    [N], in the row order of ``closure_jacobian``. ``reactions[J]`` is the force of J's
    second link on its first (linkgen.kinetostatics)."""
    out = []
    for pair in spanning_tree(asm).closures:
        eq = model.equality(pair.name).id
        first = asm.mechanism.revolute(pair.name).links[0]
        sign = 1.0 if link_name(model.body(model.eq_obj1id[eq]).name) == first else -1.0
        out += list(sign * reactions[pair.name][k])
    return np.array(out, dtype=float)


def closure_diag(asm: Assembly, model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """MuJoCo's approximate inverse inertia (``efc_diagA``) of each loop-closing revolute's
    x and y rows, shape (closures, 2) [1/kg]. Needs ``mj_forward``."""
    out = []
    for pair in spanning_tree(asm).closures:
        eq = model.equality(pair.name).id
        rows = np.flatnonzero((data.efc_type == mujoco.mjtConstraint.mjCNSTR_EQUALITY) & (data.efc_id == eq))
        out.append(data.efc_diagA[rows[:2]])
    return np.array(out, dtype=float).reshape(-1, 2)
