"""The four-bar kernel: positions, transfer functions, kinetostatics and reduced inertia of
V four-bar variants at N crank angles at once, as (V, N) arrays — the planar closed form's own
formulas (``families.planar.primitives.circle_circle`` for the RRR group, Newton–Euler with
d'Alembert loads for the reactions, the assembly mode chosen from the sketch as
``families.planar.assembly.assemble`` does) written for variants × angles, then reduced by
``metrics``. Rows it does not vouch for (``fourbar_params.ORDINARY``) or whose values are not
finite are handed back for the general route (``general``).

Joints: the reaction R_A on the coupler from the crank, R_B on the coupler from the rocker,
R_C on the rocker from the ground and R_O on the crank from the ground; only their magnitudes
are reported, so the sign convention is the table's, not a choice."""

from __future__ import annotations

import math

import numpy as np

from linkgen.families.planar.assembly import SKETCH_TIE

from linkgen.errors import AssemblyError, SingularityError, angle_ranges
from linkgen.studies.fourbar_params import FourBar, Params
from linkgen.studies.metrics import reduce

# Bytes of one (variants, angles) temporary: below glibc's 128 KiB mmap threshold, so that the ~40
# temporaries of a block come from the heap. The threshold stops adapting when MALLOC_TRIM_THRESHOLD_
# is set — dask's nanny sets it for its workers — and each larger temporary is then mapped and
# unmapped anew: measured 7× the CPU time (41 s instead of 6 s for 10^5 variants × 360 angles).
TEMP_BYTES = 96 * 1024


def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


def _branch(fb: FourBar, p: Params, size: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each variant's assembly mode m = ±1 (V,) from its sketch, and whether the sketch pose
    assembles at all (V,): the mode whose points land nearest the sketch and whose links lie at
    their sketch angles (``assemble``'s rule, ties to m = +1)."""
    o, a, b, c = fb.points
    ox, oy = p.points[o]
    ang = np.arctan2(p.points[a][1] - oy, p.points[a][0] - ox)
    la = p.length[fb.crank]
    ax, ay = ox + la * np.cos(ang), oy + la * np.sin(ang)
    errs = []
    for m in (1.0, -1.0):
        (bx, by), fail = _dyad(ax, ay, *p.points[c], p.length[fb.coupler], p.length[fb.rocker], m)
        err = np.zeros_like(ax)
        at = {a: (ax, ay), b: (bx, by), c: p.points[c]}
        for link in fb.group_links:
            for q in fb.ends[link]:
                err = err + np.hypot(at[q][0] - p.points[q][0], at[q][1] - p.points[q][1]) / size
            first, second = fb.ends[link]
            turn = np.arctan2(at[second][1] - at[first][1], at[second][0] - at[first][0])
            sketch = np.arctan2(p.points[second][1] - p.points[first][1], p.points[second][0] - p.points[first][0])
            err = err + np.abs(np.remainder(turn - sketch + math.pi, 2 * math.pi) - math.pi)
        errs.append(np.where(fail, np.inf, err))
    return (np.where(errs[1] < errs[0] - SKETCH_TIE, -1.0, 1.0),  # assemble's tie rule: m = +1
            np.isfinite(errs[0]) | np.isfinite(errs[1]))


def _dyad(ax, ay, cx, cy, ra, rc, m):
    """B with |B − A| = ra, |B − C| = rc, m = +1 left of A→C (``circle_circle``), and the mask
    where it does not exist."""
    dx, dy = cx - ax, cy - ay
    dd = dx * dx + dy * dy
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / np.sqrt(dd)
        along = (dd + (ra * ra - rc * rc)) * (0.5 * inv)
        h2 = ra * ra - along * along
        fail = (h2 < 0.0) | (dd == 0.0)
        h = np.sqrt(np.where(fail, 0.0, h2))
        ka, kh = along * inv, (m * inv) * h
    return (ax + ka * dx - kh * dy, ay + ka * dy + kh * dx), fail


def _block(fb: FourBar, p: Params, rows: slice, m: np.ndarray, phi: np.ndarray, cos: np.ndarray, sin: np.ndarray):
    """The arrays ``metrics.reduce`` takes for the variants ``rows``, and the masks (V, N) where
    the group does not assemble and where it is singular."""
    from linkgen.families.planar.groups import SINGULAR_TOL

    o, a, b, c = fb.points
    col = lambda v: v[rows][:, None]  # noqa: E731 - (V,) → (V, 1)
    ox, oy, cx, cy = col(p.points[o][0]), col(p.points[o][1]), col(p.points[c][0]), col(p.points[c][1])
    la, lb, lc = col(p.length[fb.crank]), col(p.length[fb.coupler]), col(p.length[fb.rocker])
    w, e = col(p.omega), col(p.epsilon)
    ux, uy = la * cos, la * sin  # A − O
    ax, ay = ox + ux, oy + uy
    (bx, by), fail = _dyad(ax, ay, cx, cy, lb, lc, col(m))
    r2x, r2y, r3x, r3y = bx - ax, by - ay, bx - cx, by - cy  # B − A, B − C
    det = _cross(r2x, r2y, r3x, r3y)
    d = np.abs(det / (lb * lc))
    singular = ~fail & (d < SINGULAR_TOL)
    with np.errstate(divide="ignore", invalid="ignore"):
        inv = 1.0 / det
        # First transfer functions (per unit crank angle): A′ = k × (A − O).
        a1x, a1y = -uy, ux
        w2 = -(a1x * r3x + a1y * r3y) * inv
        w3 = -(a1x * r2x + a1y * r2y) * inv
        # Second: A″ = −(A − O); q = A″ − w2²·r2 + w3²·r3, then the same 2×2 system.
        qx, qy = -ux - w2 * w2 * r2x + w3 * w3 * r3x, -uy - w2 * w2 * r2y + w3 * w3 * r3y
        e2 = -(qx * r3x + qy * r3y) * inv
        e3 = -(qx * r2x + qy * r2y) * inv
    # Each joint's position and its first and second transfer functions (the pivots' are 0).
    at = {o: (ox, oy, 0.0, 0.0, 0.0, 0.0), a: (ax, ay, a1x, a1y, -ux, -uy),
          b: (bx, by, a1x - w2 * r2y, a1y + w2 * r2x, -ux - e2 * r2y - w2 * w2 * r2x, -uy + e2 * r2x - w2 * w2 * r2y),
          c: (cx, cy, 0.0, 0.0, 0.0, 0.0)}
    rates = {fb.crank: (1.0, 0.0), fb.coupler: (w2, e2), fb.rocker: (w3, e3)}
    loads, inertia, com = {}, 0.0, {}
    for name in (fb.crank, fb.coupler, fb.rocker):
        first, second = fb.ends[name]
        x0, y0, x1, y1, x2, y2 = at[first]
        length = {fb.crank: la, fb.coupler: lb, fb.rocker: lc}[name]
        cx_, cy_ = (at[second][0] - x0) / length, (at[second][1] - y0) / length  # the link's x axis
        sx, sy = col(p.com[name][0]), col(p.com[name][1])
        gx, gy = cx_ * sx - cy_ * sy, cy_ * sx + cx_ * sy  # G − first point
        t1, t2 = rates[name]
        g1x, g1y = x1 - t1 * gy, y1 + t1 * gx
        g2x, g2y = x2 - t2 * gy - t1 * t1 * gx, y2 + t2 * gx - t1 * t1 * gy
        mass, moment = col(p.mass[name]), col(p.inertia[name])
        accx, accy = g2x * w * w + g1x * e, g2y * w * w + g1y * e
        alpha = t2 * w * w + t1 * e
        loads[name] = (mass * (col(p.gravity[0]) - accx), mass * (col(p.gravity[1]) - accy), -moment * alpha)
        com[name] = (x0 + gx, y0 + gy)
        inertia = inertia + mass * (g1x * g1x + g1y * g1y) + moment * (t1 * t1)
    f1x, f1y, m1 = loads[fb.crank]
    f2x, f2y, m2 = loads[fb.coupler]
    f3x, f3y, m3 = loads[fb.rocker]
    # Moments about B: coupler (A − B) × R_A = k2, rocker (C − B) × R_C = k3, R_A + R_C = S.
    k2 = -_cross(com[fb.coupler][0] - bx, com[fb.coupler][1] - by, f2x, f2y) - m2
    k3 = -_cross(com[fb.rocker][0] - bx, com[fb.rocker][1] - by, f3x, f3y) - m3
    sx_, sy_ = -f2x - f3x, -f2y - f3y
    u1x, u1y, u2x, u2y = -r2x, -r2y, -r3x, -r3y
    k3 = _cross(u2x, u2y, sx_, sy_) - k3
    with np.errstate(divide="ignore", invalid="ignore"):
        inv_u = 1.0 / _cross(u1x, u1y, u2x, u2y)
        rax, ray = (k2 * u2x - u1x * k3) * inv_u, (k2 * u2y - u1y * k3) * inv_u
    torque = _cross(ux, uy, rax, ray) - _cross(com[fb.crank][0] - ox, com[fb.crank][1] - oy, f1x, f1y) - m1
    joints = {o: np.hypot(rax - f1x, ray - f1y), a: np.hypot(rax, ray), b: np.hypot(rax + f2x, ray + f2y),
              c: np.hypot(sx_ - rax, sy_ - ray)}
    theta = np.arctan2(at[fb.ends[fb.rocker][1]][1] - at[fb.ends[fb.rocker][0]][1],
                       at[fb.ends[fb.rocker][1]][0] - at[fb.ends[fb.rocker][0]][0])
    return ({"outputs": {fb.rocker: theta}, "least_d": d, "torque": torque, "inertia": inertia, "joints": joints},
            fail, singular)


def solve(fb: FourBar, mech, p: Params, phi: np.ndarray, full: bool) -> tuple[dict, list, np.ndarray]:
    """Metric columns (V,) of the variants ``p`` on the crank angles ``phi``, their failures as
    a list of (row, error class name, message), and the rows left to the general route (V,)."""
    from linkgen.families.planar.groups import fail_reason
    from linkgen.families.planar.kinematics import singular_reason
    from linkgen.families.planar.structure import analyze

    group = analyze(mech).groups[0]
    rows = p.omega.shape[0]
    xs = np.stack([xy[0] for xy in p.points.values()])
    ys = np.stack([xy[1] for xy in p.points.values()])
    size = np.hypot(xs.max(axis=0) - xs.min(axis=0), ys.max(axis=0) - ys.min(axis=0))
    m, assembles = _branch(fb, p, size)
    cos, sin = np.cos(phi), np.sin(phi)
    cols = {k: np.full(rows, np.nan) for k in fb.layout.columns}
    failures: list = []
    general = ~p.ordinary
    sketch_phi = np.arctan2(p.points[fb.points[1]][1] - p.points[fb.points[0]][1],
                            p.points[fb.points[1]][0] - p.points[fb.points[0]][0])
    joint_of = {j: mech.revolute(j).point for j in fb.layout.joints}
    block = max(1, TEMP_BYTES // (8 * phi.shape[0]))
    for start in range(0, rows, block):
        sl = slice(start, min(start + block, rows))
        with np.errstate(all="ignore"):  # failed and singular samples are masked and reported
            got, fail, singular = _block(fb, p, sl, m, phi, cos, sin)
        reactions = {j: got["joints"][joint_of[j]] for j in fb.layout.joints}
        with np.errstate(all="ignore"):
            out = reduce(fb.layout, phi, full, got["outputs"], got["least_d"], got["torque"], reactions, got["inertia"])
        finite = np.all(np.isfinite(got["torque"]) & np.isfinite(got["inertia"]), axis=1)
        rows_here = np.arange(sl.start, sl.stop)
        bad = fail.any(axis=1) | singular.any(axis=1) | ~assembles[sl]
        good = ~general[sl] & ~bad & finite
        for k in cols:
            cols[k][rows_here[good]] = out[k][good]
        general[rows_here[~general[sl] & ~bad & ~finite]] = True
        for i in np.flatnonzero(~general[sl] & bad):
            r = start + i
            if not assembles[r]:
                err = AssemblyError(group.label, [(float(sketch_phi[r]),) * 2], "the sketch pose cannot be assembled")
            elif fail[i].any():
                err = AssemblyError(group.label, angle_ranges(phi, fail[i]), fail_reason(group))
            else:
                err = SingularityError(group.label, angle_ranges(phi, singular[i]), singular_reason(group))
            failures.append((int(r), type(err).__name__, Exception.__str__(err)))
    return cols, failures, general


__all__ = ["TEMP_BYTES", "solve"]
