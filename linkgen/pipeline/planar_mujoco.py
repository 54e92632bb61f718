"""The planar family's MuJoCo and picture stages: mjcf, simulate, validate (with the report's
figures), draw, animate, render. The planar sub-kinds are told apart here and nowhere else: a
linkage whose crank carries a cam is checked by its contact (``crosscheck.cam``), a class III or
higher linkage (no Assur groups) is posed numerically, and a ``[machine]`` table joins its
comparison (``crosscheck.machine``) to the file's result."""

from __future__ import annotations

import math

import numpy as np

from linkgen.model.arguments import input_kind
from linkgen.model.turn import full_turn
from linkgen.families.planar.description import Mechanism


def _source(mech):
    """The assembled mechanism, or the numerically posed one where the Assur groups do not cover
    it (MuJoCo needs no groups); and the StructureError that said so, or None."""
    from linkgen.errors import StructureError
    from linkgen.families.planar.assembly import assemble
    from linkgen.mujoco.posed import posed

    if not isinstance(mech, Mechanism):  # already assembled (or posed)
        return mech, None
    try:
        return assemble(mech), None
    except StructureError as exc:
        return posed(mech), exc


def _mechanism(desc):
    return getattr(desc, "mechanism", desc)


def mjcf(desc, settings=None, practical: bool = False, robot=None) -> str:
    """The MJCF text (``linkgen build``) of any structure class; ``settings`` (default derived
    from the mechanism), or with ``practical`` MuJoCo's usual settings keeping the derived rotor
    inertia that holds the crank speed; with ``robot`` (``mujoco.robot.RobotOptions``) the
    robot-ready model (``mujoco.robot``) instead."""
    from linkgen.errors import ArgumentError, StructureError
    from linkgen.families.planar.assembly import assemble
    from linkgen.mujoco.mjcf import write_mjcf

    source = desc
    if isinstance(desc, Mechanism):
        try:
            source = assemble(desc)
        except StructureError:  # class III and higher: MuJoCo needs no Assur groups
            pass
    if robot is not None:
        from linkgen.mujoco.robot_planar import planar_robot_mjcf

        if practical or settings is not None:
            raise ArgumentError("robot: the robot-ready model states MuJoCo's own settings; leave settings and "
                                "practical out")
        return planar_robot_mjcf(source, robot)
    if practical:
        from dataclasses import replace

        from linkgen.crosscheck.practical import USER
        from linkgen.mujoco.mjcf import settings_for

        settings = replace(USER, armature=settings_for(_mechanism(desc)).armature)
    return write_mjcf(source, settings)


def coupling(desc, settings=None, practical: bool = False):
    """The loop-free MJCF (``linkgen build --loops coupling``) and its ``Coupling`` (the fits and
    their errors): ``settings`` (default derived from the mechanism), or with ``practical``
    MuJoCo's usual settings. Raises CouplingError where a quartic coupling misses its bound."""
    from linkgen.mujoco.coupling import couple
    from linkgen.mujoco.coupling_mjcf import write_coupled
    from linkgen.mujoco.mjcf import settings_for

    from dataclasses import replace

    from linkgen.families.planar.assembly import Assembly

    source, _ = _source(desc)
    if not isinstance(source, Assembly):  # class III and higher: the numeric poses of the description
        source = _mechanism(desc)
    c = couple(source)
    if practical:
        from linkgen.crosscheck.practical import USER

        settings = USER
    elif settings is None:
        settings = settings_for(_mechanism(desc))
    xml = write_coupled(source, c, settings)
    if isinstance(source, Assembly):  # the torque needs the closed form's forces
        import mujoco

        from linkgen.mujoco.coupling_torque import lag, torque_error
        from linkgen.mujoco.log import no_log_file

        with no_log_file():
            model = mujoco.MjModel.from_xml_string(xml)
        c = replace(c, torque=torque_error(source, c, model), timeconst=settings.timeconst,
                    lags=lag(c, settings.timeconst, source.mechanism.drive.omega))
        xml = write_coupled(source, c, settings)
    return xml, c


def simulate(desc, *, revolutions=None, omega=None, epsilon=None, settings=None, samples=None, nthread=None,
             progress=None, max_steps=None, settle=None, notice=None):
    """A MuJoCo run over the drive range (``mujoco.simulate.simulate``; an option left None takes
    its default there); ``notice(text)`` hears that the closed form does not cover the mechanism
    and the run starts from the numeric pose."""
    from linkgen.mujoco.simulate import simulate as run

    options = {k: v for k, v in (("revolutions", revolutions), ("omega", omega), ("epsilon", epsilon),
                                 ("settings", settings), ("samples", samples), ("nthread", nthread),
                                 ("progress", progress), ("max_steps", max_steps), ("settle", settle))
               if v is not None}
    source, why = _source(desc)
    if why is not None and notice is not None:
        notice(f"the closed form does not cover this mechanism ({why}); MuJoCo runs it from the numeric pose, "
               f"with settings from the crank speed")
    return run(source, **options)


def validate(desc, *, practical: bool = True, nthread: int | None = None, max_steps: int | None = None, progress=None,
             source=None, machine_progress=None):
    """MuJoCo against the closed form: a ``CrossCheck`` (``crosscheck.run.crosscheck``), a
    ``CamLinkageCheck`` for a crank carrying a cam, or with ``source`` (the description's file)
    holding a ``[machine]`` table a ``MachineCheck`` joining the machine's comparison
    (``machine_progress`` its progress). StructureError for a class III or higher linkage."""
    from linkgen.errors import StructureError
    from linkgen.families.planar.assembly import assemble
    from linkgen.mujoco.options import MAX_STEPS

    try:
        asm = assemble(desc) if isinstance(desc, Mechanism) else desc
    except StructureError as exc:
        raise StructureError(f"the closed form does not cover this mechanism ({exc}); `linkgen build` and "
                             f"`linkgen simulate` still work for it") from None
    if asm.mechanism.cams:  # contact in MuJoCo, the cam's tolerances
        from linkgen.crosscheck.cam import check_cam_linkage

        return check_cam_linkage(asm, progress, max_steps)
    from linkgen.crosscheck.run import crosscheck

    check = crosscheck(asm, practical=practical, nthread=nthread, progress=progress,
                       max_steps=MAX_STEPS if max_steps is None else max_steps)
    if source is None:
        return check
    from linkgen.crosscheck.machine import MachineCheck, compare_machine

    machine = compare_machine(source, progress=machine_progress, asm=asm)
    return check if machine is None else MachineCheck(check, machine)


def figures(desc, check, out) -> dict:
    """The report's figures of a validated linkage into the folder ``out`` (its skeleton and
    position plan, and the comparison's plots) and the design summary beside them: the entries
    the report adds to the file's result (``figures``: file names, ``summary``)."""
    from linkgen.families.planar.assembly import assemble
    from linkgen.report.report import plot_mechanism, plot_model

    asm = assemble(desc) if isinstance(desc, Mechanism) else desc
    if asm.mechanism.cams:
        return {"figures": plot_mechanism(asm, out)}
    if getattr(check, "comparison", None) is None:
        return {}
    from linkgen.families.planar.summary import summarize

    return {"figures": plot_mechanism(asm, out) + plot_model(check.comparison, out),
            "summary": summarize(asm).to_dict()}


def report(entry: dict):
    """The report's (row, section) writers of a linkage's validate entry: a cam on the crank's,
    or a linkage comparison's (``report.sections``)."""
    from linkgen.report import sections

    return sections.CAM_LINKAGE if "cam_linkage" in entry else sections.LINKAGE


def _in_range(mech, phi: np.ndarray, option: str) -> None:
    from linkgen.errors import ArgumentError

    d = mech.drive
    if full_turn(mech):
        return
    bad = phi[(phi < d.start - 1e-12) | (phi > d.stop + 1e-12)]
    if bad.size and mech.slide_drive:
        raise ArgumentError(f"{option}: {float(bad[0]):.6g} m is outside the drive's stroke {d.start:.6g}..{d.stop:.6g} m "
                            f"(drive.start, drive.stop)")
    if bad.size:
        raise ArgumentError(f"{option}: {math.degrees(float(bad[0])):.6g}° is outside the drive's range "
                            f"{math.degrees(d.start):.6g}°..{math.degrees(d.stop):.6g}° (drive.start, drive.stop)")


def draw(desc, angles, out, *, vectors=None, parts: bool = False, free_body=None, plan=None):
    """The skeleton at one crank angle (``angles`` a number [rad], None: the range's start) with
    its link names and lengths and the design summary, and ``vectors`` ("velocity",
    "acceleration", "forces"; ``parts``: an acceleration's tangential and normal parts;
    ``free_body``: a group's forces alone), or the ``plan`` ("velocity", "acceleration") at that
    angle, or a position plan (``angles`` an array), written to ``out``. Returns (what was drawn,
    the drawn data: ``Arrows``, ``VectorPlan`` or None)."""
    from linkgen.draw.plan import plan_figure

    mech = _mechanism(desc)
    if angles is not None and np.ndim(angles) > 0:
        _in_range(mech, np.asarray(angles, dtype=float), "--angles")
        plan_figure(mech, np.asarray(angles, dtype=float), out)
        return f"{mech.name}, position plan of {len(angles)} positions", None
    from linkgen.errors import ArgumentError, StructureError
    from linkgen.families.planar.assembly import assemble

    from linkgen.draw.defaults import default_angle

    if angles is None:  # a crank off its dead centres; a stroke's start
        phi = mech.drive.start if mech.slide_drive else default_angle(mech)
    else:
        phi = float(input_kind(angles, mech.slide_drive, "--angle"))
    _in_range(mech, np.array([phi]), "--angle")
    at = _at(mech, phi)
    try:
        asm = assemble(mech)
    except StructureError as exc:  # class III and higher: the skeleton from the numeric pose only
        if plan is not None or vectors is not None or free_body is not None:
            raise ArgumentError(f"{mech.name}: plans and vectors come from the Assur groups' closed form ({exc})") from None
        from linkgen.draw.plan import skeleton_figure

        skeleton_figure(mech, phi, out)
        return f"{mech.name}, skeleton at {at}", None
    if plan is not None:
        from linkgen.draw.polygons import vector_plan_figure
        from linkgen.families.planar.vector_plan import vector_plan

        _, data = vector_plan_figure(mech, vector_plan(asm, phi, plan), out)
        return f"{mech.name}, {plan} plan at {at} (closes to {data.closure():.1e} of its size)", data
    from linkgen.draw.teaching import teaching_figure
    from linkgen.draw.vectors import check_vectors, force_arrows, motion_arrows
    from linkgen.families.planar.summary import summarize

    arrows = None
    if free_body is not None and vectors not in (None, "forces"):
        raise ArgumentError(f"--free-body draws forces; it cannot be combined with --vectors {vectors}")
    if vectors is not None or free_body is not None:
        what = check_vectors(vectors or "forces")
        arrows = (force_arrows(asm, phi, free_body) if what == "forces" else motion_arrows(asm, phi, what, parts))
    _, _, mu = teaching_figure(asm, phi, out, arrows=arrows, summary=summarize(asm))
    extra = f", {arrows.what} at {mu:g} {arrows.unit} per m of drawing" if arrows is not None and mu else ""
    if arrows is not None and arrows.arrows and not mu:
        extra = f", {arrows.what}: every one zero here"
    return f"{mech.name}, skeleton at {at}{extra}", arrows




def page(desc, out, frames: int = 72, mujoco: bool = False, progress=None) -> str:
    """The interactive page (``draw.page``) of the linkage, written to ``out``; with ``mujoco``
    MuJoCo's run over the drive range beside the closed form's curves (``progress`` as
    ``simulate``'s). Returns what it shows."""
    from dataclasses import replace

    from linkgen.draw.page import write_page
    from linkgen.draw.page_planar import mujoco_curves, planar_page
    from linkgen.errors import ArgumentError, StructureError
    from linkgen.families.planar.assembly import assemble

    mech = _mechanism(desc)
    try:
        asm = assemble(mech)
    except StructureError as exc:
        raise ArgumentError(f"{mech.name}: the page's vectors come from the Assur groups' closed form ({exc})") from None
    data = planar_page(asm, frames)
    if mujoco:
        from linkgen.mujoco.simulate import simulate as run

        data = replace(data, mujoco=mujoco_curves(data, run(asm, progress=progress).samples))
    write_page(data, out)
    return (f"{mech.name}, {data.inputs_text}, vectors {', '.join(data.vectors)}, curves {', '.join(data.curves)}"
            + (f", MuJoCo's run beside {', '.join(data.mujoco)}" if mujoco else ""))


def animate(desc, frames: int, progress=None, mujoco: bool = False, notice=None) -> tuple[list, str]:
    """The frames of the mechanism moving over its drive range with its point paths, and how
    they were made; with ``mujoco``, MuJoCo's rendered run beside the drawing at the crank
    angles it reached (``notice(text)`` hears that the run starts)."""
    from linkgen.draw.animate import drawn_frames, frame_angles, mujoco_run_frames

    mech = _mechanism(desc)
    phi = frame_angles(mech, frames)
    shots = None
    if mujoco:
        if notice is not None:
            notice(f"running {mech.name} in MuJoCo over its drive range …")
        phi, shots = mujoco_run_frames(mech, frames)
    return drawn_frames(mech, phi, shots, progress=progress), (", closed form beside MuJoCo's run" if mujoco else "")


def render(desc, angle, width: int, height: int) -> tuple[np.ndarray, str]:
    """A MuJoCo offscreen frame (h, w, 3) of the generated model at crank angle ``angle`` [rad]
    (None: the range's start), and what it shows."""
    from linkgen.draw.render import render_mechanism

    mech = _mechanism(desc)
    phi = mech.drive.start if angle is None else float(input_kind(angle, mech.slide_drive, "--angle"))
    _in_range(mech, np.array([phi]), "--angle")
    _, frames = render_mechanism(mech, phi, width, height)
    return frames[0], f"MuJoCo frame of {mech.name} at {_at(mech, phi)}"


def _at(mech, phi: float) -> str:
    """``φ = 30°``, or a prismatic drive's ``s = 0.3 m``."""
    return f"s = {phi:.6g} m" if mech.slide_drive else f"φ = {math.degrees(phi):.6g}°"


STAGES = {"mjcf": mjcf, "coupling": coupling, "simulate": simulate, "validate": validate, "figures": figures, "report": report, "draw": draw, "page": page,
          "animate": animate, "render": render}

__all__ = ["STAGES"]
