"""A planar linkage's interactive page (``draw.page``): the links over the drive's range at the
drive's ω and ε, the points' velocities and accelerations and the pairs' reactions as arrows,
each output's position and the balancing torque as curves (a prismatic drive: over its strokes
s [m] at its ṡ and s̈, with the balancing force [N])."""

from __future__ import annotations

import math

import numpy as np

from linkgen.draw.page import PageData, arrow_segments
from linkgen.errors import LinkgenError
from linkgen.draw.plan import title_of
from linkgen.draw.teaching import LONGEST, summary_lines
from linkgen.families.planar.description import GROUND
from linkgen.families.planar.plate import convex_hull


def page_angles(mech, frames: int) -> np.ndarray:
    """``frames`` crank angles [rad] (a prismatic drive: strokes [m]) over the drive's range (a full
    turn without its repeated end)."""
    d = mech.drive
    full = not mech.slide_drive and d.stop - d.start >= 2 * math.pi - 1e-12
    return np.linspace(d.start, d.stop, frames, endpoint=not full)


def balancing_label(stroke: bool) -> str:
    """The balancing load's curve: a force [N] on a prismatic drive, else a torque [N·m]."""
    return "balancing force [N]" if stroke else "balancing torque [N·m]"


def _round_scale(longest: float, size: float) -> float:
    if longest <= 0.0 or not math.isfinite(longest):
        return 1.0
    raw = longest / (LONGEST * size)
    k = math.floor(math.log10(raw))
    return next(m * 10.0 ** k for m in (1.0, 2.0, 5.0, 10.0) if m * 10.0 ** k >= raw)


def _lines(pos, i: int) -> np.ndarray:
    rows = []
    for link in pos.mechanism.links:
        if link.name == GROUND:
            continue
        xy = np.array([pos.points[p][i] for p in link.points])
        if len(xy) >= 3:
            hull = convex_hull(xy)
            rows += [*hull, hull[0], (np.nan, np.nan)]
        elif len(xy) == 2:
            rows += [xy[0], xy[1], (np.nan, np.nan)]
    for pair in pos.guides:  # the slider's block as a short stroke along its guide
        base, u = pos.guide_line(pair, i)
        c = pos.local_to_world(pos.guides[pair].slider, pos.guides[pair].point, i)
        half = 0.04 * pos.size() * u
        rows += [c - half, c + half, (np.nan, np.nan)]
    return np.array(rows, dtype=float)


def planar_page(asm, frames: int = 72) -> PageData:
    """The page's data of the assembled linkage ``asm`` at ``frames`` crank angles."""
    from linkgen.families.planar.kinematics import solve_motion
    from linkgen.families.planar.positions import positions
    from linkgen.families.planar.summary import summarize

    mech = asm.mechanism
    phi = page_angles(mech, frames)
    pos = positions(mech, phi)
    size = positions(mech, page_angles(mech, 361)).size()
    mo = solve_motion(asm, phi, mech.drive.omega, mech.drive.epsilon, on_singular="mark")
    fixed_pts = set(mech.link(GROUND).points)
    moving = [p for p in mech.points if p not in fixed_pts]
    at = np.stack([mo.points[p][0] for p in moving], axis=1)
    vectors, scales = {}, {}
    for what, col, unit in (("velocity", 1, "m/s"), ("acceleration", 2, "m/s²")):
        vec = np.stack([mo.points[p][col] for p in moving], axis=1)
        mu = _round_scale(float(np.max(np.linalg.norm(vec, axis=-1))), size)
        vectors[what], scales[what] = arrow_segments(at, vec, mu), f"1 m of drawing = {mu:g} {unit}"
    curves, notes = {}, []
    summary = summarize(asm)
    for name, o in summary.outputs.items():
        if mech.slide_drive and name.split(" ")[0] == mech.drive.joint:
            continue  # the driven pair's own stroke is the input itself, the curves' axis
        if o.kind == "slider" and name.split(" ")[0] in mo.sliders:
            curves[f"{name} displacement [m]"] = mo.sliders[name.split(" ")[0]][0]
        elif name.split(" ")[0] in mo.links:
            curves[f"{name} angle [°]"] = np.degrees(np.unwrap(mo.links[name.split(" ")[0]][0]))
        if len(curves) >= 2:
            break
    try:
        from linkgen.families.planar.kinetostatics import forces

        f = forces(asm, phi, mech.drive.omega, mech.drive.epsilon, on_singular="mark")
        curves[balancing_label(mech.slide_drive)] = f.balancing_torque
        rev = [r for r in mech.revolutes if r.name in f.reactions]
        if rev:
            r_at = np.stack([mo.points[r.point][0] for r in rev], axis=1)
            r_vec = np.stack([f.reactions[r.name] for r in rev], axis=1)
            mu = _round_scale(float(np.max(np.linalg.norm(r_vec, axis=-1))), size)
            vectors["forces"], scales["forces"] = arrow_segments(r_at, r_vec, mu), f"reactions, 1 m = {mu:g} N"
    except LinkgenError as exc:  # a dead centre inside the range: the page says why it has no forces
        notes.append(f"no forces: {str(exc).splitlines()[0][:120]}")
    crank = mech.link(mech.crank).points
    pin = pos.points[crank[1] if len(crank) > 1 else crank[0]]
    if mech.slide_drive:  # the driven slider's point
        pin = pos.points[next(p.point for p in mech.prismatics if p.name == mech.drive.joint)]
    ground = [pos.points[p][0] for p in fixed_pts]
    fixed = np.array([q for g in ground for q in (g, (np.nan, np.nan))], dtype=float) if ground else None
    from linkgen.draw.defaults import default_angle

    first = mech.drive.start if mech.slide_drive else default_angle(mech)  # the pose ``draw`` shows by default
    start = int(np.argmin(np.abs(phi - first)))
    return PageData(title=title_of(mech), phi=phi, start=start, lines=np.stack([_lines(pos, i) for i in range(len(phi))]),
                    points={p: pos.points[p] for p in mech.points}, pin=pin, vectors=vectors, vector_scales=scales,
                    curves=curves, summary=tuple(summary_lines(summary) + notes), fixed=fixed,
                    stroke=mech.slide_drive)


def mujoco_curves(data: PageData, samples) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """MuJoCo's values of the page's curves from a run's ``samples`` (``mujoco.sample.Samples``):
    label → (φ (m,) [rad] or s (m,) [m], values (m,)), an angle on the closed form's turn (whole
    turns apart)."""
    phi = np.asarray(samples.crank[0], dtype=float)
    out = {}
    for label, ours in data.curves.items():
        name = label.split(" ")[0]
        if label.endswith("displacement [m]") and name in samples.sliders:
            out[label] = (phi, np.asarray(samples.sliders[name][0], dtype=float))
        elif label.endswith("angle [°]") and name in samples.links:
            theirs = np.degrees(np.unwrap(np.asarray(samples.links[name][0], dtype=float)))
            near = np.interp(phi[0], data.phi, ours)
            out[label] = (phi, theirs - 360.0 * np.round((theirs[0] - near) / 360.0))
        elif label in (balancing_label(False), balancing_label(True)):
            out[label] = (phi, np.asarray(samples.drive_torque, dtype=float))
    return out


__all__ = ["balancing_label", "mujoco_curves", "page_angles", "planar_page"]
