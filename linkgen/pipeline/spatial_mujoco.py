"""The spatial four-bar family's MuJoCo and picture stages: mjcf, validate (with the report's
figures), draw, animate, render."""

from __future__ import annotations

import math

import numpy as np

# Positions in the report's position plan of a spatial four-bar (every 30° of the crank's turn).
PLAN_STEP_DEG = 30.0
# Positions in the plan of a chain driven by a slider, over its range (both ends).
PLAN_POSITIONS = 9


def mjcf(desc, settings=None, practical: bool = False, robot=None) -> str:
    """The MJCF text (``linkgen build``) with ``settings`` (default: derived from the chain at
    the drive's speed, as ``validate`` runs it); with ``robot`` (``mujoco.robot.RobotOptions``)
    the robot-ready model (``mujoco.robot``)."""
    from linkgen.crosscheck.spatial import derived_settings
    from linkgen.errors import ArgumentError
    from linkgen.mujoco.spatial_mjcf import write_spatial_mjcf

    if practical:
        raise ArgumentError("--practical is for planar linkages")
    if robot is not None:
        from linkgen.mujoco.robot_spatial import spatial_robot_mjcf

        if settings is not None:
            raise ArgumentError("robot: the robot-ready model states MuJoCo's own settings; leave settings out")
        return spatial_robot_mjcf(desc, robot)
    return write_spatial_mjcf(desc, derived_settings(desc)[0] if settings is None else settings)


def validate(desc, *, practical: bool = True, nthread: int | None = None, max_steps: int | None = None, progress=None,
             source=None, machine_progress=None):
    """MuJoCo against the closed form: a ``crosscheck.spatial.SpatialCheck`` (``practical``,
    ``nthread``, ``source`` and ``machine_progress`` are planar linkages' options: they do not
    apply here)."""
    from linkgen.crosscheck.spatial import check_spatial

    return check_spatial(desc, progress=progress, max_steps=max_steps)


def figures(desc, check, out) -> dict:
    """The report's figures of a validated chain into the folder ``out``: its drawing, a
    position plan and the comparison's plots."""
    from linkgen.draw.spatial import draw_spatial, plot_spatial_check
    from linkgen.families.spatial.kinematics import assembled_chain

    names = [f"{check.model}_drawing.png", f"{check.model}_plan.png"]
    if desc.drive.slides:  # a slider input: its range's start, and a plan over the range
        lo, hi = desc.drive.range
        draw_spatial(desc, np.array([lo]), out / names[0])
        draw_spatial(desc, np.linspace(lo, hi, PLAN_POSITIONS), out / names[1])
    else:
        # the sketch's own pose, as ``linkgen draw`` shows it: φ = 0 can be a folded pose (Bennett's
        # four joints in line there, stacked in the side view)
        draw_spatial(desc, np.array([assembled_chain(desc).phi_s]), out / names[0])
        draw_spatial(desc, np.radians(np.arange(0.0, 360.0, PLAN_STEP_DEG)), out / names[1])
    return {"figures": names + plot_spatial_check(check, out, desc)}


def report(entry: dict):
    """The report's (row, section) writers of a spatial four-bar's validate entry (``report.sections``)."""
    from linkgen.report import sections

    return sections.SPATIAL


def draw(desc, angles, out, *, vectors=None, parts: bool = False, free_body=None, plan=None):
    """The chain at one crank angle (``angles`` a number [rad], None: the sketch's own pose) with
    ``vectors`` (3-D, in every view), or its ``plan`` (the 3-D plan's projections,
    ``families.spatial.plans``), or a position plan (an array), written to ``out``; returns (what
    was drawn, the drawn data or None)."""
    from linkgen.draw.spatial import draw_spatial
    from linkgen.errors import ArgumentError

    if free_body is not None:
        raise ArgumentError(f"--free-body: {desc.name} is a spatial four-bar, solved whole rather than by Assur "
                            f"groups; --vectors forces draws every pair's reaction")
    if angles is None:
        from linkgen.families.spatial.kinematics import assembled_chain

        angles = np.array([assembled_chain(desc).phi_s])
    angles = np.atleast_1d(np.asarray(angles, dtype=float))
    at = (f"s = {float(angles[0]):.6g} m" if desc.drive.slides else f"φ = {math.degrees(float(angles[0])):.6g}°")
    if plan is not None and len(angles) == 1:
        from linkgen.draw.polygons import spatial_plan_figure
        from linkgen.families.spatial.plans import spatial_plan

        _, data = spatial_plan_figure(desc, spatial_plan(desc, float(angles[0]), plan), out)
        return f"{desc.name}, {plan} plan at {at} (3-D, closes to {data.closure():.1e}; its projections)", data
    arrows = None
    if vectors is not None and len(angles) == 1:
        from linkgen.draw.family_vectors import spatial_arrows

        arrows = spatial_arrows(desc, float(angles[0]), vectors, parts)
    draw_spatial(desc, angles, out, arrows=arrows)
    return f"{desc.name}, " + (f"position plan of {len(angles)} positions" if len(angles) > 1
                               else f"skeleton at {at}" + (f", {vectors}" if vectors else "")), arrows


def page(desc, out, frames: int = 72, mujoco: bool = False, progress=None) -> str:
    """The interactive page (``draw.page``) of the chain (its top view), written to ``out``."""
    from linkgen.errors import ArgumentError

    if mujoco:
        raise ArgumentError(f"--mujoco: {desc.name} is a spatial four-bar; the page shows MuJoCo's curves for planar linkages "
                            f"(validate writes its MuJoCo comparison into the report)")
    from linkgen.draw.page import write_page
    from linkgen.draw.page_families import spatial_page

    data = spatial_page(desc, frames)
    write_page(data, out)
    return f"{desc.name}, {data.inputs_text}, vectors {', '.join(data.vectors)}, curves {', '.join(data.curves)}"


def animate(desc, frames: int, progress=None, mujoco: bool = False, notice=None) -> tuple[list, str]:
    """The frames of the chain over one turn of its crank (the drawing of ``draw``), and how
    they were made."""
    from linkgen.draw.frames import spatial_frames, turn_angles

    if mujoco:
        from linkgen.errors import ArgumentError

        raise ArgumentError("--mujoco puts MuJoCo's run beside planar linkages; for this model `linkgen render` "
                            "gives MuJoCo's frames and `linkgen validate` its run")
    if desc.drive.slides:
        return spatial_frames(desc, np.linspace(*desc.drive.range, frames), progress), " over the input's range"
    return spatial_frames(desc, turn_angles(frames), progress), " over one turn"


def render(desc, angle, width: int, height: int) -> tuple[np.ndarray, str]:
    """A MuJoCo offscreen frame of the spatial model at crank angle ``angle`` [rad] (None: 0),
    posed from the closed form, and what it shows."""
    from linkgen.draw.frames import spatial_render

    if desc.drive.slides:
        s = desc.drive.range[0] if angle is None else float(angle)
        return spatial_render(desc, s, width, height)[0], f"MuJoCo frame of {desc.name} at s = {s:.6g} m"
    phi = 0.0 if angle is None else float(angle)
    return spatial_render(desc, phi, width, height)[0], f"MuJoCo frame of {desc.name} at φ = {math.degrees(phi):.6g}°"


STAGES = {"mjcf": mjcf, "validate": validate, "figures": figures, "report": report, "draw": draw, "page": page, "animate": animate, "render": render}

__all__ = ["PLAN_STEP_DEG", "STAGES"]
