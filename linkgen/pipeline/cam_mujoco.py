"""The stand-alone cam family's MuJoCo and picture stages: mjcf, validate (with the report's
figures), draw, animate, render."""

from __future__ import annotations

import math

import numpy as np


def mjcf(desc, settings=None, practical: bool = False, robot=None) -> str:
    """The MJCF text (``linkgen build``): the cam's own contact settings, derived from its motion
    (no robot-ready model: a cam's contact needs its own settings)."""
    from linkgen.errors import ArgumentError
    from linkgen.mujoco.cam import cam_mjcf

    if robot is not None:
        raise ArgumentError("robot: a stand-alone cam has no robot-ready model (its contact needs the step and "
                            "contact settings of its own MJCF); it is for planar linkages and spatial four-bars")

    if practical:
        raise ArgumentError("--practical is for linkages; a cam's MJCF carries its own contact settings")
    if settings is not None:
        raise ArgumentError("settings: a stand-alone cam's MJCF carries its own contact settings, derived from its "
                            "motion; leave settings out (None)")
    return cam_mjcf(desc)


def validate(desc, *, practical: bool = True, nthread: int | None = None, max_steps: int | None = None, progress=None,
             source=None, machine_progress=None):
    """One turn in MuJoCo against the closed form, diagnosed: a ``crosscheck.cam.CamCheck``
    (``practical``, ``nthread``, ``source`` and ``machine_progress`` are planar linkages' options:
    they do not apply here)."""
    from linkgen.crosscheck.cam import check_cam

    return check_cam(desc, progress=progress, max_steps=max_steps)


def figures(desc, check, out) -> dict:
    """The report's figures of a validated cam into the folder ``out``: its drawing, the
    follower's motion and the contact, closed form against MuJoCo."""
    from linkgen.report.figures_cam import plot_cam

    return {"figures": plot_cam(desc, check.run, out)}


def report(entry: dict):
    """The report's (row, section) writers of a cam's validate entry (``report.sections``)."""
    from linkgen.report import sections

    return sections.CAM


def draw(desc, angles, out, *, vectors=None, parts: bool = False, free_body=None, plan=None):
    """The cam and its follower at one cam angle (``angles`` a number [rad], None: 0) with
    ``vectors`` ("velocity", "acceleration", "forces") of the follower's point B, or the ``plan``
    of B (``families.cam.plans``), or a position plan by inversion (an array), written to ``out``;
    returns (what was drawn, the drawn data or None)."""
    from linkgen.draw.cam import cam_figure, default_cam_angle, cam_plan_figure
    from linkgen.errors import ArgumentError

    if free_body is not None:
        raise ArgumentError(f"--free-body: {desc.name} is a cam and its follower, with no Assur groups; "
                            f"--vectors forces draws the contact force")
    if angles is not None and np.ndim(angles) > 0:
        cam_plan_figure(desc, np.asarray(angles, dtype=float), out)
        return f"{desc.name}, position plan by inversion of {len(angles)} cam angles", None
    theta = default_cam_angle(desc) if angles is None else float(angles)
    at = f"φ = {math.degrees(theta):.6g}°"
    if plan is not None:
        from linkgen.draw.polygons import vector_plan_figure
        from linkgen.families.cam.plans import cam_plan

        _, data = vector_plan_figure(desc, cam_plan(desc, theta, plan), out)
        return f"{desc.name}, {plan} plan of the follower's point B at {at} (closes to {data.closure():.1e})", data
    arrows = None
    if vectors is not None:
        from linkgen.draw.family_vectors import cam_arrows

        arrows = cam_arrows(desc, theta, vectors, parts)
    cam_figure(desc, theta, out, arrows=arrows)
    return f"{desc.name}, cam and follower at {at}" + (f", {vectors}" if vectors else ""), arrows


def page(desc, out, frames: int = 72, mujoco: bool = False, progress=None) -> str:
    """The interactive page (``draw.page``) of the cam and its follower, written to ``out``."""
    from linkgen.errors import ArgumentError

    if mujoco:
        raise ArgumentError(f"--mujoco: {desc.name} is a cam; the page shows MuJoCo's curves for planar linkages "
                            f"(validate writes its MuJoCo comparison into the report)")
    from linkgen.draw.page import write_page
    from linkgen.draw.page_families import cam_page

    data = cam_page(desc, frames)
    write_page(data, out)
    return f"{desc.name}, {len(data.phi)} cam angles, vectors {', '.join(data.vectors)}, curves {', '.join(data.curves)}"


def animate(desc, frames: int, progress=None, mujoco: bool = False, notice=None) -> tuple[list, str]:
    """The frames of the cam turning once (the drawing of ``draw``), and how they were made."""
    from linkgen.draw.frames import cam_frames, turn_angles

    if mujoco:
        from linkgen.errors import ArgumentError

        raise ArgumentError("--mujoco puts MuJoCo's run beside planar linkages; for this model `linkgen render` "
                            "gives MuJoCo's frames and `linkgen validate` its run")
    return cam_frames(desc, turn_angles(frames), progress), " over one turn"


def render(desc, angle, width: int, height: int) -> tuple[np.ndarray, str]:
    """A MuJoCo offscreen frame of the cam model at cam angle ``angle`` [rad] (None: 0), the
    follower where the closed form puts it, and what it shows."""
    from linkgen.draw.frames import cam_render

    theta = 0.0 if angle is None else float(angle)
    return cam_render(desc, theta, width, height)[0], f"MuJoCo frame of {desc.name} at φ = {math.degrees(theta):.6g}°"


STAGES = {"mjcf": mjcf, "validate": validate, "figures": figures, "report": report, "draw": draw, "page": page, "animate": animate, "render": render}

__all__ = ["STAGES"]
