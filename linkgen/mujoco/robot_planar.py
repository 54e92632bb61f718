"""The robot build of a planar linkage: what its closed form gives the robot MJCF
(``robot.RobotDrive``): the driven joint, the peak balancing torque over the drive range, the
largest reduced inertia, the revolutes to sense and the loads MJCF cannot carry."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from linkgen.model.turn import full_turn
from linkgen.errors import LinkgenError
from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.description import GROUND, Mechanism
from linkgen.mujoco.robot import PEAK_SAMPLES, RobotDrive, RobotOptions, robot_model
from linkgen.mujoco.robot_sensors import ReactionSite
from linkgen.mujoco.robot_xml import MOUNT


def _body(link: str) -> str:
    from linkgen.mujoco.tree import body_name

    return MOUNT if link == GROUND else body_name(link)


def _peak(asm: Assembly | None, mech) -> tuple[float | None, float | None, float]:
    """The closed form's peak |balancing torque| [N·m] and largest reduced inertia J [kg·m²]
    over the drive range at the description's ω, ε (ω² growing by 2·ε·Δφ), and the largest ω;
    (None, None, ω) where there is no closed form (class III and higher) or it fails."""
    from linkgen.families.planar.kinetostatics import forces

    d = mech.drive
    phi = np.linspace(d.start, d.stop, PEAK_SAMPLES)
    w = np.sqrt(np.maximum(d.omega**2 + 2 * d.epsilon * (phi - d.start), 0.0)) * (1.0 if d.omega >= 0 else -1.0)
    w_max = float(np.max(np.abs(w)))
    if asm is None:
        return None, None, w_max
    try:
        f = forces(asm, phi, w, d.epsilon, on_singular="mark")
    except LinkgenError:
        return None, None, w_max
    ok = ~f.singular
    if not ok.any():
        return None, None, w_max
    return float(np.max(np.abs(f.balancing_torque[ok]))), float(np.max(f.reduced.inertia[ok])), w_max


def _inertia_scale(mech: Mechanism) -> float:
    """An upper scale of the reduced inertia where the closed form gives none: every moving link's
    mass at the mechanism's size from the crank's pivot, plus its own inertia [kg·m²]."""
    from linkgen.families.planar.geometry import effective_mass_properties, link_shapes
    from linkgen.families.planar.pose import mechanism_size

    shapes, size = link_shapes(mech), mechanism_size(mech)
    return sum(mp.mass * size**2 + mp.inertia
               for mp in (effective_mass_properties(mech, shapes, n) for n in mech.moving_links))


def _loads(mech: Mechanism) -> tuple[str, ...]:
    """How to apply each of the description's loads, "{P}" standing for the names' prefix."""
    from linkgen.mujoco.tree import body_name, site_name

    out = []
    for f in mech.forces:
        during = (f" while φ is in {math.degrees(f.stroke[0]):.6g}°..{math.degrees(f.stroke[1]):.6g}°"
                  if f.stroke is not None else "")
        out.append(f"[[force]] F = ({f.force[0]:g}, {f.force[1]:g}, 0) N on link {f.link} at point {f.point}{during}: "
                   f"each step mujoco.mj_applyFT(model, data, R·F, [0, 0, 0], data.site('{{P}}"
                   f"{site_name(mech, f.link, f.point)}').xpos, model.body('{{P}}{body_name(f.link)}').id, "
                   "data.qfrc_applied), R = data.body('{P}mount').xmat (3×3)")
    for t in mech.torques:
        out.append(f"[[torque]] M = {t.torque:g} N·m on link {t.link} about the plane's normal: each step "
                   f"mujoco.mj_applyFT(model, data, [0, 0, 0], M·R[:, 2], data.body('{{P}}{body_name(t.link)}').xipos, "
                   f"model.body('{{P}}{body_name(t.link)}').id, data.qfrc_applied)")
    for fr in mech.frictions:  # load-dependent: a value per state, from linkgen's kinetostatics (mujoco.friction)
        what = (f"a couple μ·r·|R| (μ = {fr.coefficient:g}, r = {fr.pin_radius:g} m) between links "
                f"{' and '.join(mech.revolute(fr.pair).links)}" if fr.pin_radius is not None
                else f"a force μ·max(|N|, 2|M|/L) (μ = {fr.coefficient:g}, L = {fr.block_length:g} m) along the guide "
                     f"between the slider and its guide")
        out.append(f"[[friction]] in pair {fr.pair}: {what}, against their relative motion; its value at each state "
                   f"is linkgen.forces(...).friction['{fr.pair}'] at the crank's angle and speed")
    return tuple(out)


def planar_drive(source: Mechanism | Assembly) -> RobotDrive:
    """What the robot build needs of a planar linkage (assembled, or a class III and higher one)."""
    from linkgen.families.planar.geometry import link_shapes, sketch_input
    from linkgen.mujoco.tree import site_name, spanning_tree

    mech = source.mechanism if isinstance(source, Assembly) else source
    shapes = link_shapes(mech)
    peak, inertia, w_max = _peak(source if isinstance(source, Assembly) else None, mech)
    info = spanning_tree(mech)
    sites = []
    for parent, child, pair in info.tree:
        if pair.kind == "R":
            rev = mech.revolute(pair.name)
            sites.append(ReactionSite(pair.name, _body(rev.links[0]), _body(rev.links[1]),
                                      site=site_name(mech, child, rev.point)))
    for pair in info.closures:
        rev = mech.revolute(pair.name)
        local = shapes[rev.links[1]].local[rev.point]
        sites.append(ReactionSite(pair.name, _body(rev.links[0]), _body(rev.links[1]),
                                  anchor=(float(local[0]), float(local[1]), 0.0)))
    d = mech.drive
    full = full_turn(mech)
    notes = (("each cam pair's contact keeps the stiff contact of linkgen's validation model (its solref is "
              "below two timesteps at 2 ms, so MuJoCo's safety limit sets it to 4 ms)",) if mech.cams else ())
    return RobotDrive("planar", d.joint, float(sketch_input(mech, shapes)), None if full else (d.start, d.stop),
                      peak, w_max, inertia if inertia is not None else _inertia_scale(mech), tuple(sites),
                      (float(mech.gravity[0]), float(mech.gravity[1]), 0.0), _loads(mech), notes)


def planar_robot_mjcf(source: Mechanism | Assembly, options: RobotOptions) -> str:
    """The robot MJCF text of a planar linkage (``robot``)."""
    from linkgen.mujoco.mjcf import _source, write_mjcf
    from linkgen.mujoco.options import PLACEHOLDER
    from linkgen.mujoco.scene import motion_extent

    mech = source.mechanism if isinstance(source, Assembly) else source
    if mech.slide_drive:
        from linkgen.errors import UnsupportedError

        raise UnsupportedError(f"--robot: {mech.name!r} is driven by the prismatic pair {mech.drive.joint!r} (a linear "
                               f"actuator); the robot model is written for a driven crank only. linkgen build without "
                               f"--robot writes its MJCF with the drive on the slide joint")
    src = _source(source)
    xml = write_mjcf(source, PLACEHOLDER)  # the validation model; its settings are replaced
    felt = _felt(source) if options.plane == "xy" else source
    drive = replace(planar_drive(felt), gravity=(float(mech.gravity[0]), float(mech.gravity[1]), 0.0))
    return robot_model(xml, drive, options, mech.name, scene=(motion_extent(src), src.size), source=felt)


def _felt(source: Mechanism | Assembly) -> Mechanism | Assembly:
    """The linkage as it moves with its plane flat (``--plane xy``): gravity along the plane's
    normal, none in the plane; the closed form of the limits and of the accuracy is taken so."""
    from linkgen.families.planar.assembly import assemble

    mech = source.mechanism if isinstance(source, Assembly) else source
    flat = replace(mech, gravity=(0.0, 0.0))
    return assemble(flat) if isinstance(source, Assembly) else flat


__all__ = ["planar_drive", "planar_robot_mjcf"]
