"""The description's ``[[force]]``/``[[torque]]`` loads applied to MuJoCo's spatial model as body
wrenches (``xfrc_applied``) at MuJoCo's own positions and crank angle, the way the planar side
applies them (``linkgen.mujoco.forces``): the same stroke test, the same force-at-a-point rule.
MJCF has no element for a load that switches with the crank angle, so the written file carries
gravity only and says so; linkgen sets the wrenches at every read-out and, while stepping, at
every stage of every step (``loads_while_stepping``, MuJoCo's control callback): a wrench held
over an RK4 step turns with the body it was computed for no more, and its error would spin a
coupler on two ball joints about its own line, whose inertia is tiny."""

from __future__ import annotations

from contextlib import contextmanager
from typing import Iterator

import mujoco
import numpy as np

from linkgen.model.names import GROUND
from linkgen.mujoco.forces import add_force
from linkgen.model.strokes import stroke_active
from linkgen.families.spatial.description import SpatialMechanism


def has_loads(mech: SpatialMechanism) -> bool:
    """True when some force or torque acts on a moving link."""
    return any(f.link != GROUND for f in mech.forces) or any(t.link != GROUND for t in mech.torques)


def site_of(model: mujoco.MjModel, link: str, point: str) -> int:
    """The id of ``link``'s site at ``point`` (its bare name, or "POINT:LINK" for a later copy)."""
    copy = mujoco.mj_name2id(model, mujoco.mjtObj.mjOBJ_SITE, f"{point}:{link}")
    return copy if copy >= 0 else model.site(point).id


def _plan(mech: SpatialMechanism, model: mujoco.MjModel) -> tuple[list, list]:
    """(force, body id, site id, vector) per force and (body id, vector) per torque on a moving link."""
    forces = [(f, model.body(f.link).id, site_of(model, f.link, f.point), np.asarray(f.force, dtype=float))
              for f in mech.forces if f.link != GROUND]
    torques = [(model.body(t.link).id, np.asarray(t.torque, dtype=float)) for t in mech.torques if t.link != GROUND]
    return forces, torques


def apply_loads(mech: SpatialMechanism, model: mujoco.MjModel, data: mujoco.MjData, phi: float,
                plan: tuple | None = None) -> None:
    """Set ``xfrc_applied`` from the loads at crank angle φ [rad] (the stroke test) at MuJoCo's
    current positions: ``mj_kinematics`` and ``mj_comPos`` must have run for this state."""
    forces, torques = _plan(mech, model) if plan is None else plan
    data.xfrc_applied[:] = 0.0
    at = np.array([phi])
    for f, body, site, vec in forces:
        if stroke_active(f, at)[0]:
            add_force(data, body, data.site_xpos[site], vec)
    for body, vec in torques:
        data.xfrc_applied[body, 3:] += vec


def loads_at_state(mech: SpatialMechanism, model: mujoco.MjModel, data: mujoco.MjData, phi: float) -> None:
    """Positions of the current qpos, then the loads at crank angle φ [rad] on them."""
    mujoco.mj_kinematics(model, data)
    mujoco.mj_comPos(model, data)
    apply_loads(mech, model, data, phi)


@contextmanager
def loads_while_stepping(mech: SpatialMechanism, model: mujoco.MjModel, data: mujoco.MjData,
                         crank_qpos: int, phi_offset: float) -> Iterator[None]:
    """While inside, every ``mj_step`` of ``data`` sets the loads at each integrator stage from
    that stage's positions and crank angle (qpos[crank_qpos] + ``phi_offset``) [rad]. MuJoCo's
    control callback is process-wide: the previous one is restored on leaving, and other data
    are passed on to it untouched."""
    previous = mujoco.get_mjcb_control()
    plan = _plan(mech, model)

    def stage(m, d):
        if d is data:  # positions and mj_comPos are done when MuJoCo calls the control callback
            apply_loads(mech, m, d, float(d.qpos[crank_qpos]) + phi_offset, plan)
        elif previous is not None:
            previous(m, d)

    if not has_loads(mech):
        yield
        return
    mujoco.set_mjcb_control(stage)
    try:
        yield
    finally:
        mujoco.set_mjcb_control(previous)


__all__ = ["apply_loads", "has_loads", "loads_while_stepping", "loads_at_state", "site_of"]
