"""A linkage's springs and dampers in MuJoCo (``planar.springs``): MuJoCo's own passive forces.

    * a spring between points: a spatial tendon ``spring:I`` through the two points' sites with
      ``stiffness`` k, ``damping`` c and ``springlength`` L₀ (MuJoCo's passive tendon force
      −k·(L − L₀) − c·L̇, pulling the sites together when positive);
    * a torsion spring at a revolute that is a tree joint between its two links: that hinge's
      ``stiffness``, ``springref`` and ``damping`` (the hinge's qpos is the child's angle against
      the parent's from the sketch, so springref = ±(θ₀ − θ_sketch), + when the spring's second
      link is the child);
    * else (the revolute closes a loop): a fixed tendon ``torsion:I`` over the tree's hinges from
      the first link up to the two links' common ancestor and down to the second (−1 on the way
      up, +1 on the way down: its length is θ_b − θ_a − θ_sketch), springlength θ₀ − θ_sketch.

MuJoCo adds these as generalised forces (``qfrc_passive``). ``mj_rnePostConstraint`` already
counts a spatial tendon's pull on the bodies at its sites in ``cfrc_ext`` (measured on mujoco 4.0:
the tree reactions of models/slider_crank_spring.toml match the closed form's with nothing added,
and are off by the spring's force with it added once more), but a torsion spring's torques act
on joints only, so a tree joint's ``cfrc_int`` (``mujoco.forces``) would count them as the
joint's own: ``spring_wrenches`` puts them, from MuJoCo's state, on the bodies for that reading.
"""

from __future__ import annotations

import mujoco
import numpy as np
from lxml import etree

from linkgen.families.planar.description import GROUND, Mechanism
from linkgen.families.planar.springs import carrier
from linkgen.mujoco.tree import TreeInfo, body_name, site_name, spanning_tree


def spring_name(i: int) -> str:
    return f"spring:{i}"


def torsion_name(i: int) -> str:
    return f"torsion:{i}"


def _fmt(x: float) -> str:
    x = float(x)
    return "0" if x == 0.0 else repr(x)


def _springref(pose, t) -> float:
    """θ₀ − θ_sketch [rad]: the torsion spring's rest against the assembled sketch ``pose`` (the
    writer's {link: (origin, angle)}, where every joint is 0); 0 without a rest angle."""
    a, b = t.links
    return 0.0 if t.rest_angle is None else t.rest_angle - (pose[b][1] - pose[a][1])


def tree_hinge(info: TreeInfo, t) -> tuple[str, float] | None:
    """(the hinge joint's name, +1 if the torsion spring's second link is its child, else −1) when
    the spring's revolute is a tree joint between its two links, else None."""
    a, b = t.links
    for parent, child, pair in info.tree:
        if pair.kind == "R" and pair.name == t.joint and {parent, child} == {a, b}:
            return pair.name, 1.0 if child == b else -1.0
    return None


def hinge_path(info: TreeInfo, a: str, b: str) -> dict[str, float]:
    """The tree's hinges whose angles sum to θ_b − θ_a (from the sketch): joint name → ±1."""
    def up(link):
        chain = [link]
        while chain[-1] != GROUND:
            chain.append(info.parent_of(chain[-1])[0])
        return chain

    ua, ub = up(a), up(b)
    common = next(x for x in ua if x in ub)
    coef: dict[str, float] = {}
    for chain, sign in ((ua, -1.0), (ub, 1.0)):
        for link in chain[:chain.index(common)]:
            pair = info.parent_of(link)[1]
            if pair.kind == "R":
                coef[pair.name] = coef.get(pair.name, 0.0) + sign
    return {k: v for k, v in coef.items() if v}


# A spring tendon's drawn width, as a fraction of the mechanism's size (like the writer's sizes).
TENDON_WIDTH = 0.004


def add_springs(root, mech: Mechanism, pose, size: float) -> None:
    """Add the springs' tendons and the torsion springs' joint springs or tendons to the MJCF
    tree ``root`` (its bodies, joints and sites already written at the assembled sketch ``pose``,
    {link: (origin, angle)}); ``size`` the mechanism's [m]."""
    if not (mech.springs or mech.torsion_springs):
        return
    info = spanning_tree(mech)
    tendon = etree.SubElement(root, "tendon")
    for i, s in enumerate(mech.springs):
        el = etree.SubElement(tendon, "spatial", name=spring_name(i), stiffness=_fmt(s.stiffness),
                              damping=_fmt(s.damping), springlength=_fmt(s.rest_length),
                              width=_fmt(TENDON_WIDTH * size), rgba="0.9 0.75 0.1 1")
        for p in s.points:
            etree.SubElement(el, "site", site=site_name(mech, carrier(mech, p), p))
    for i, t in enumerate(mech.torsion_springs):
        ref = _springref(pose, t)
        hinge = tree_hinge(info, t)
        if hinge is not None:
            name, sign = hinge
            joint = root.find(f".//joint[@name='{name}']")
            joint.set("stiffness", _fmt(t.stiffness))
            joint.set("springref", _fmt(sign * ref))
            joint.set("damping", _fmt(t.damping))
            continue
        el = etree.SubElement(tendon, "fixed", name=torsion_name(i), stiffness=_fmt(t.stiffness),
                              damping=_fmt(t.damping), springlength=_fmt(ref))
        for joint, coef in hinge_path(info, *t.links).items():
            etree.SubElement(el, "joint", joint=joint, coef=_fmt(coef))
    if not len(tendon):
        root.remove(tendon)


def spring_wrenches(mech: Mechanism, model: mujoco.MjModel, data: mujoco.MjData) -> np.ndarray:
    """The torsion springs' torques on the bodies (nbody, 6) as ``xfrc_applied`` rows (zero force,
    the torque about z), from MuJoCo's tendon and joint state
    (``mj_kinematics``, ``mj_comPos``, ``mj_fwdVelocity`` or ``mj_forward`` done)."""
    out = np.zeros((model.nbody, 6))
    info = spanning_tree(mech)

    def push(link: str, torque: float) -> None:
        if link != GROUND:
            out[model.body(body_name(link)).id, 5] += torque

    for i, t in enumerate(mech.torsion_springs):
        hinge = tree_hinge(info, t)
        if hinge is not None:
            j = model.joint(hinge[0])
            q, dof = j.qposadr[0], j.dofadr[0]
            tau = -(model.jnt_stiffness[j.id] * (data.qpos[q] - model.qpos_spring[q])
                    + model.dof_damping[dof] * data.qvel[dof]) * hinge[1]
        else:
            k = model.tendon(torsion_name(i)).id
            tau = -(model.tendon_stiffness[k] * (data.ten_length[k] - model.tendon_lengthspring[k, 0])
                    + model.tendon_damping[k] * data.ten_velocity[k])
        push(t.links[1], tau)
        push(t.links[0], -tau)
    return out


def has_springs(mech: Mechanism) -> bool:
    """Whether ``spring_wrenches`` has anything to add (torsion springs)."""
    return bool(mech.torsion_springs)


__all__ = ["add_springs", "has_springs", "hinge_path", "spring_name", "spring_wrenches", "torsion_name", "tree_hinge"]
