"""The robot build of a spatial four-bar (``robot``): its own frame (z up already, so no
``plane``), the peak balancing torque of its closed form, and the loop-closing connect's reaction
sensed (the tree's ball and hinge pairs are not: their reactions are the closed form's)."""

from __future__ import annotations

import math

import numpy as np

from linkgen.errors import LinkgenError
from linkgen.mujoco.robot import PEAK_SAMPLES, RobotDrive, RobotOptions, robot_model
from linkgen.mujoco.robot_sensors import ReactionSite
from linkgen.mujoco.robot_xml import MOUNT


def spatial_robot_mjcf(mech, options: RobotOptions) -> str:
    """The robot MJCF text of a spatial four-bar: its own frame (z up already; no ``plane``), the
    loop-closing connect's reaction sensed."""
    from linkgen.errors import ArgumentError
    from linkgen.families.spatial.forces import forces
    from linkgen.families.spatial.kinematics import assembled_chain
    from linkgen.mujoco.options import PLACEHOLDER
    from linkgen.mujoco.spatial_mjcf import write_spatial_mjcf

    if options.plane is not None:
        raise ArgumentError(f"--plane {options.plane}: a spatial four-bar is written in its own frame, z up (its "
                            "description's); --plane places a planar linkage's plane")
    chain = assembled_chain(mech)
    phi = chain.phi_s + np.linspace(0.0, 2 * math.pi, PEAK_SAMPLES)
    notes = ()
    try:
        f = forces(mech, phi)
        peak = float(np.max(np.abs(f.balancing_torque)))
        if f.indeterminate:
            notes = (f"the closed form's reaction at {chain.pair_b} is statically indeterminate (by {f.indeterminate}, "
                     "a loop of four hinges): reaction:" + chain.pair_b + " reads MuJoCo's own split of it, which "
                     "depends on its constraint settings",)
    except LinkgenError:
        peak = None
    pair = mech.joint(chain.pair_b)
    origin = {chain.crank: chain.a0, chain.coupler: chain.A,
              chain.output: chain.B if chain.output_slides else chain.b0}
    second = pair.links[1]
    anchor = tuple(float(x) for x in (chain.B - origin.get(second, np.zeros(3))))
    body = {n: (MOUNT if n not in origin else n) for n in pair.links}
    sites = (ReactionSite(chain.pair_b, body[pair.links[0]], body[second], anchor=anchor),)
    if chain.kind == "RCCC":  # no connect to sense: the loop closes by welding the output's two halves
        sites = ()
        notes += (f"the RCCC's loop closes by a weld between the output's two halves (on {chain.pair_out} and on "
                  f"{chain.pair_b}); no reaction is sensed",)
    size = chain.size
    inertia = sum(l.mass for l in mech.links) * size**2  # an upper scale: no reduced inertia in this family
    loads = tuple(f"[[force]] ({', '.join(f'{x:g}' for x in f.force)}) N on link {f.link} at point {f.point}"
                  + (" over its stroke" if f.stroke is not None else "") + ": each step mujoco.mj_applyFT(model, data, "
                  f"R·F, [0, 0, 0], the point's position, model.body('{{P}}{f.link}').id, data.qfrc_applied), "
                  "R = data.body('{P}mount').xmat (3×3)" for f in mech.forces)
    loads += tuple(f"[[torque]] M = ({', '.join(f'{x:g}' for x in t.torque)}) N·m on link {t.link}: each step "
                   f"mujoco.mj_applyFT(model, data, [0, 0, 0], R·M, data.body('{{P}}{t.link}').xipos, "
                   f"model.body('{{P}}{t.link}').id, data.qfrc_applied)" for t in mech.torques)
    drive = RobotDrive("spatial", chain.drive, float(chain.phi_s), None, peak, abs(mech.drive.omega), inertia, sites,
                       tuple(float(x) for x in mech.gravity), loads, notes)
    return robot_model(write_spatial_mjcf(mech, PLACEHOLDER, chain), drive, options, mech.name, source=mech)


__all__ = ["spatial_robot_mjcf"]
