"""The interactive page's data (``draw.page.PageData``) of a stand-alone cam and of a spatial
four-bar. A cam: its profile turning, the follower, the follower's point B with its velocity and
acceleration (and the cam's point B₁ under it), the follower's displacement, velocity and pressure
angle as curves; the "crank pin" is the end of the cam's angle mark on its base circle. A spatial
four-bar: the projection on the plane of the two principal directions of its points' paths over
a turn (the plane it shows its motion in best), the moving points' velocities and accelerations
projected alike, the output's angle or travel and the balancing torque as curves (a prismatic
input: over its range of strokes s [m], with the balancing force [N])."""

from __future__ import annotations

import math

import numpy as np

from linkgen.draw.page import PageData, arrow_segments
from linkgen.draw.page_planar import balancing_label
from linkgen.draw.plan import title_of
from linkgen.draw.teaching import LONGEST, summary_lines
from linkgen.errors import LinkgenError

PROFILE_POINTS = 181
CIRCLE = np.linspace(0.0, 2 * math.pi, 37)


def _scale(vectors: np.ndarray, size: float) -> float:
    longest = float(np.max(np.linalg.norm(vectors, axis=-1))) if vectors.size else 0.0
    if longest <= 0.0:
        return 1.0
    raw = longest / (LONGEST * size)
    k = math.floor(math.log10(raw))
    return next(m * 10.0 ** k for m in (1.0, 2.0, 5.0, 10.0) if m * 10.0 ** k >= raw)


def cam_page(cm, frames: int = 72) -> PageData:
    """The page's data of the cam mechanism ``cm`` at ``frames`` cam angles over a turn."""
    from linkgen.families.cam.kinetics import state
    from linkgen.families.cam.summary import cam_summary

    f, w = cm.follower, cm.omega
    th = np.linspace(0.0, 2 * math.pi, frames, endpoint=False)
    c, c1, c2, u = f.centre(th)
    profile = f.profile(np.linspace(0.0, 2 * math.pi, PROFILE_POINTS))
    size = 2.2 * float(np.max(np.linalg.norm(f.pitch_curve(np.linspace(0, 2 * math.pi, 361))[0], axis=1)))
    nan = np.full((1, 2), np.nan)
    lines = []
    for i, t in enumerate(th):
        cs, sn = math.cos(t), math.sin(t)
        turned = profile @ np.array([[cs, sn], [-sn, cs]])
        mark = np.array([[0.0, 0.0], [f.base_radius * cs, f.base_radius * sn]])
        roller = c[i] + max(f.roller_radius, 0.006 * size) * np.column_stack([np.cos(CIRCLE), np.sin(CIRCLE)])
        if f.kind == "translating":
            stem = np.array([c[i], c[i] + 0.35 * size * np.array([0.0, 1.0])])
        else:
            stem = np.array([c[i], [f.pivot_distance, 0.0]])
        if f.flat:
            roller = np.array([[c[i, 0] - 0.22 * size, c[i, 1]], [c[i, 0] + 0.22 * size, c[i, 1]]])
            stem = np.array([[f.offset, c[i, 1]], [f.offset, c[i, 1] + 0.35 * size]])
        lines.append(np.concatenate([turned, nan, mark, nan, roller, nan, stem, nan]))
    width = max(len(x) for x in lines)
    lines = np.stack([np.vstack([x, np.full((width - len(x), 2), np.nan)]) for x in lines])
    pin = f.base_radius * np.column_stack([np.cos(th), np.sin(th)])
    v, a, v1 = c1 * w, c2 * w * w, w * np.column_stack([-c[:, 1], c[:, 0]])
    mu_v, mu_a = _scale(np.concatenate([v, v1]), size), _scale(a, size)
    st = state(cm, th)
    points = {"O": np.zeros((frames, 2)), "B": c}
    if f.kind == "oscillating":
        points["O1"] = np.tile([f.pivot_distance, 0.0], (frames, 1))
    base = f.base_radius * np.column_stack([np.cos(CIRCLE), np.sin(CIRCLE)])
    unit = "m" if f.kind == "translating" else "rad"
    from linkgen.draw.cam import default_cam_angle

    start = int(np.argmin(np.abs(th - default_cam_angle(cm))))
    return PageData(title=title_of(cm), phi=th, start=start, lines=lines, points=points, pin=pin,
                    vectors={"velocity": arrow_segments(np.stack([c, c], 1), np.stack([v, v1], 1), mu_v),
                             "acceleration": arrow_segments(c[:, None], a[:, None], mu_a)},
                    vector_scales={"velocity": f"v_B, v_B1: 1 m of drawing = {mu_v:g} m/s",
                                   "acceleration": f"a_B: 1 m of drawing = {mu_a:g} m/s²"},
                    curves={f"follower displacement [{unit}]": st.displacement,
                            f"follower velocity [{unit}/s]": st.velocity,
                            "pressure angle [°]": np.degrees(st.pressure_angle)},
                    summary=tuple(summary_lines(cam_summary(cm, w))), fixed=base)


def spatial_page(mech, frames: int = 72) -> PageData:
    """The page's data of the spatial four-bar ``mech`` at ``frames`` crank angles over a turn (a
    prismatic input: ``frames`` strokes over its range, both ends)."""
    from linkgen.families.spatial.kinematics import assembled_chain, solve
    from linkgen.families.spatial.summary import summary
    from linkgen.model.names import GROUND

    chain = assembled_chain(mech)
    phi = chain.input_samples(frames)
    mo = solve(mech, phi, chain)
    w, e = float(mech.drive.omega), float(getattr(mech.drive, "epsilon", 0.0))
    xyz = {p: j.d[0] for p, j in mo.points.items()}
    cloud = np.concatenate(list(xyz.values()))
    centre = cloud.mean(axis=0)
    _, _, vt = np.linalg.svd(cloud - centre, full_matrices=False)
    basis = vt[:2]  # the two principal directions of the points' paths

    def flat(x):
        return (np.asarray(x) - centre) @ basis.T

    def flat_vec(x):
        return np.asarray(x) @ basis.T

    nan = np.full((frames, 1, 2), np.nan)
    segs = []
    for link in mech.links:
        if link.name != GROUND and len(link.points) >= 2:
            segs += [np.stack([flat(xyz[p]) for p in link.points], axis=1), nan]
    lines = np.concatenate(segs, axis=1)
    fixed_pts = set(mech.link(GROUND).points)
    moving = [p for p in xyz if p not in fixed_pts]
    at = np.stack([flat(xyz[p]) for p in moving], axis=1)
    v = np.stack([flat_vec(mo.points[p].d[1] * w) for p in moving], axis=1)
    a = np.stack([flat_vec(mo.points[p].d[2] * w * w + mo.points[p].d[1] * e) for p in moving], axis=1)
    size = float(np.max(np.ptp(cloud, axis=0))) * 1.3
    mu_v, mu_a = _scale(v, size), _scale(a, size)
    crank = mech.link(chain.crank).points
    pin = flat(xyz[crank[1] if len(crank) > 1 else crank[0]])
    out_label = f"{chain.output} travel [m]" if chain.output_slides else f"{chain.output} angle [°]"
    out_values = mo.output.d[0] if chain.output_slides else np.degrees(np.unwrap(mo.output.d[0]))
    curves, notes = {out_label: out_values}, []
    try:
        from linkgen.families.spatial.results import forces

        curves[balancing_label(chain.input_slides)] = np.asarray(forces(mech, phi).balancing_torque, dtype=float)
    except LinkgenError as exc:  # a dead centre: the page says why it has no torque
        notes.append(f"no {balancing_label(chain.input_slides).split(' [')[0]}: {str(exc).splitlines()[0][:120]}")
    ground = np.array([q for p in fixed_pts for q in (flat(mech.point(p)), (np.nan, np.nan))], dtype=float)
    e1, e2 = (", ".join(f"{round(float(x), 2) + 0.0:.2f}" for x in b) for b in basis)
    off = phi - chain.phi_s if chain.input_slides else np.angle(np.exp(1j * (phi - chain.phi_s)))
    start = int(np.argmin(np.abs(off)))  # the sketch's pose, as draw shows it
    return PageData(title=title_of(mech) + " (projection on its principal plane)", phi=phi, start=start, lines=lines,
                    points={p: flat(xyz[p]) for p in xyz}, pin=pin,
                    vectors={"velocity": arrow_segments(at, v, mu_v), "acceleration": arrow_segments(at, a, mu_a)},
                    vector_scales={"velocity": f"projected, 1 m = {mu_v:g} m/s",
                                   "acceleration": f"projected, 1 m = {mu_a:g} m/s²"},
                    curves=curves, summary=tuple(summary_lines(summary(mech)) + notes), fixed=ground,
                    axes=(f"along ({e1}) [m]", f"along ({e2}) [m]"), stroke=chain.input_slides)

__all__ = ["cam_page", "spatial_page"]
