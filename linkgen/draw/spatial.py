"""Pictures of a spatial four-bar — a 3-D view and the top (x–y), front (x–z) and side (y–z) projections to
one scale, at one crank angle or several — and the report's figures of its MuJoCo check. Each glyph is built
in 3-D and drawn through each view's projection; sizes are fractions of the span S."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
from matplotlib.lines import Line2D
from matplotlib.patches import Polygon
from mpl_toolkits.mplot3d.art3d import Poly3DCollection
from scipy.spatial import ConvexHull

from linkgen.mujoco.tolerances import GAP_TOL
from linkgen.draw.plan import DPI, plt_module, save, title_of
from linkgen.draw.skeleton import CRANK, GROUND_GREY, INK, LINK
from linkgen.model.names import GROUND
from linkgen.families.spatial.chain import angle_about
from linkgen.families.spatial.kinematics import assembled_chain, solve
from linkgen.families.spatial.travel import full_turn, slide_displacement, slide_travel

FIGSIZE, CHECK_DPI = (11.0, 10.0), 90  # the drawing [in] at plan.DPI; the check figures' dpi
OTHERS, PATHS = ((0.2, 0.6, 0.35), (0.55, 0.35, 0.75), (0.75, 0.55, 0.1)), ("tab:purple", "tab:olive", "tab:cyan", "tab:pink")
# Fractions of S: ball and pin radius, pin half-length, slider block, support, label gap, hatch stroke,
# and the height of a 9-pt name in a view of FIGSIZE.
BALL, PIN_R, PIN_H, BLOCK, SUPPORT, LABEL, HATCH, CHAR = 0.015, 0.013, 0.04, (0.09, 0.05), (0.05, 0.04), 0.03, 0.014, 0.03
VIEWS = (("top view (x–y)", 0, 1), ("3-D view", None, None), ("front view (x–z)", 0, 2), ("side view (y–z)", 1, 2))
PALE = 0.3  # alpha of a plan's later positions


def _unit(v):
    n = float(np.linalg.norm(v))
    return v / n if n > 1e-12 else v * 0.0


class _View:
    """A 2-D projection or the 3-D view (``basis``: screen right, up) and what names must keep clear of."""

    def __init__(self, ax, basis, is3d, span):
        self.ax, self.basis, self.is3d, self.span, self.segs, self.marks = ax, np.asarray(basis, float), is3d, span, [], []

    def proj(self, p):
        return np.asarray(p, float) @ self.basis.T

    def line(self, p, avoid=False, **kw):
        p, q = np.atleast_2d(p), self.proj(np.atleast_2d(p))
        self.segs += [(a, b) for a, b in zip(q[:-1], q[1:]) if avoid and np.all(np.isfinite([a, b]))]
        return self.ax.plot(*(p.T if self.is3d else q.T), **kw)

    def solid(self, faces, color, alpha, z, avoid=False, shade=False):
        q = self.proj(np.concatenate(faces))
        hull = q[ConvexHull(q, qhull_options="QJ").vertices]  # a convex solid's outline in a projection
        if avoid:
            self.marks += [*hull, *(0.5 * (hull + np.roll(hull, 1, 0))), hull.mean(0)]
        if not self.is3d:
            return self.ax.add_patch(Polygon(hull, facecolor=(*color, alpha), edgecolor=(*INK, alpha), lw=0.9, zorder=z))
        light = _unit(np.array([-0.4, -0.5, 1.0]))
        fc = [(*(np.array(color) * (0.7 + 0.3 * abs(float(_unit(np.cross(f[1] - f[0], f[2] - f[0])) @ light))
                                    if shade else 1.0)), alpha) for f in faces]
        for n in {len(f) for f in faces}:  # one collection per face size (mplot3d pads ragged ones)
            pick = [i for i, f in enumerate(faces) if len(f) == n]
            self.ax.add_collection3d(Poly3DCollection([faces[i] for i in pick], facecolors=[fc[i] for i in pick], zorder=z,
                                                      edgecolors=(*INK, 0.3) if alpha == 1 else "none", linewidths=0.3))

    def text(self, p, offset, s, **kw):
        self.marks += list(self.proj(p) + offset + np.array([(-1, -1), (1, -1), (1, 1), (-1, 1), (0, 0)])
                           * CHAR * self.span * np.array([0.3 * len(s) + 0.2, 0.5]))
        return self.ax.text(*(np.asarray(p) + offset @ self.basis if self.is3d else self.proj(p) + offset), s, **kw)


def _basis3d(azim, elev):
    a, e = math.radians(azim), math.radians(elev)
    return np.array([[-math.sin(a), math.cos(a), 0.0], [-math.sin(e) * math.cos(a), -math.sin(e) * math.sin(a), math.cos(e)]])


def _lathe(c, k, profile, n=16):
    """Faces of a solid of revolution about axis k through c: rings at (radius, height) pairs."""
    e = np.eye(3)[2 if abs(k[2]) < 0.9 else 0]  # a square block's faces square to z (or x): boxes in the projections
    e1, t = _unit(e - k * float(k @ e)), np.linspace(0, 2 * np.pi, n, endpoint=False) + np.pi / n
    rings = [c + h * k + r * (np.outer(np.cos(t), e1) + np.outer(np.sin(t), np.cross(k, e1))) for r, h in profile]
    return [np.array([a[i - 1], a[i], b[i], b[i - 1]]) for a, b in zip(rings, rings[1:]) for i in range(n)] + [rings[0], rings[-1]]


def _hatched(view, p0, p1, side, alpha):
    """A fixed line p0–p1 with hatch strokes towards ``side`` (3-D unit vector)."""
    view.line(np.array([p0, p1]), avoid=alpha == 1, color=INK, lw=1.3, alpha=alpha, zorder=1.8)
    k = max(int(np.linalg.norm(view.proj(p1) - view.proj(p0)) / (0.6 * HATCH * view.span)), 1)
    a, stroke = p0 + np.outer((np.arange(k) + 0.5) / k, p1 - p0), HATCH * view.span * (side - _unit(p1 - p0)) / math.sqrt(2)
    view.line(np.stack([a, a + stroke, a * np.nan], 1).reshape(-1, 3), color=INK, lw=0.6, alpha=alpha, zorder=1.8)  # NaN-broken


def _support(view, p, k, bars):
    """A ground pivot: a hatched support under the pin (or beside it, away from its bars)."""
    s, dirs = view.span, [_unit(view.proj(b - p)) for b in bars]
    d = np.array(next((d for d in ((0, -1), (-1, 0), (1, 0), (0, 1)) if all(np.dot(d, q) < 0.57 for q in dirs)), (0, -1)), float)
    down, across = d @ view.basis, np.array([-d[1], d[0]]) @ view.basis
    reach = PIN_H * abs(float(k @ down)) + PIN_R * math.sqrt(max(0.0, 1 - float(k @ down) ** 2))
    top, (w, h) = p + reach * s * down, (SUPPORT[0] * s, SUPPORT[1] * s)
    view.solid([np.array([top, top + h * down - 0.5 * w * across, top + h * down + 0.5 * w * across])], (1, 1, 1), 1, 1.9, True)
    _hatched(view, top + h * down - 0.8 * w * across, top + h * down + 0.8 * w * across, down, 1.0)


def _place_labels(view, pts):
    """Each name (points seen at one spot share one) where its box is clearest of what is drawn."""
    s, groups = view.span, []
    for name, p in pts.items():
        g = next((g for g in groups if np.linalg.norm(view.proj(p) - view.proj(g[1])) < 0.02 * s), None)
        g[0].append(name) if g else groups.append(([name], p))
    a, b = (np.array([sg[i] for sg in view.segs]).reshape(-1, 2) for i in (0, 1))
    ab, t = b - a, np.linspace(0, 2 * np.pi, 32, endpoint=False)
    for text, p in ((", ".join(names), p) for names, p in groups):
        box = CHAR * s * np.array([0.3 * len(text) + 0.2, 0.5])  # the name's half-width and half-height
        ring = np.stack([np.cos(t), np.sin(t)], 1) / np.abs(np.stack([np.cos(t), np.sin(t)], 1)).max(1, keepdims=True)
        off = np.concatenate([ring * (box + r * LABEL * s) for r in (0.6, 1.0, 1.6, 2.6)])  # boxes this clear of the point
        q = view.proj(p) + off
        w = np.clip(np.einsum("cmk,mk->cm", q[:, None] - a, ab) / np.maximum(np.einsum("mk,mk->m", ab, ab), 1e-30), 0, 1)
        dots = np.array(view.marks + [view.proj(v) for v in pts.values()]).reshape(-1, 2)
        near = np.concatenate([q[:, None] - a - w[..., None] * ab, q[:, None] - dots], 1)
        clear = np.linalg.norm(np.maximum(np.abs(near) - box, 0.0), axis=2).min(1)
        k = int(np.argmax(np.minimum(clear, LABEL * s) - 0.1 * np.linalg.norm(off, axis=1) + 1e-3 * s * off[:, 1]))
        view.text(p, off[k], text, fontsize=9, color=INK, ha="center", va="center", zorder=7)
        if k >= 3 * len(t):  # far out: a leader from the point towards the name
            reach = (1.5 * BALL * s, np.linalg.norm(off[k]) - box.max())
            view.line(p + np.outer(reach, _unit(off[k]) @ view.basis), color=INK, lw=0.5, zorder=7)


def _pose(view, mech, chain, motion, i, colors, travel, alpha):
    """Sample i: bars, slider, pairs; the first (solid) one also with guide, centre lines, supports, names."""
    s, at, first, bars_at = view.span, {p: j.d[0][i] for p, j in motion.points.items()}, alpha == 1, {p: [] for p in mech.points}
    for l in mech.links:
        for q in l.points[1:] if l.name != GROUND else ():  # each link's own copy of its points (RCCC's part)
            a, b = motion.at(l.name, l.points[0]).d[0][i], motion.at(l.name, q).d[0][i]
            bars_at[l.points[0]].append(b), bars_at[q].append(a)
            view.line(np.array([a, b]), avoid=first, color=colors[l.name], lw=3.4 if first else 2.2, alpha=alpha,
                      solid_capstyle="round", zorder=3)
    for sl in mech.slides:
        u, base, (bl, bw) = np.array(sl.direction), mech.point(sl.point), (0.5 * BLOCK[0] * s, 0.5 * BLOCK[1] * s)
        if first:
            side = _unit(np.cross(u, np.cross(*view.basis)))
            _hatched(view, *(base + t * u for t in travel[sl.name]), side * (-1 if side @ view.basis[1] > 0 else 1), 1.0)
        block = _lathe(at[sl.point] - bl * u, u, [(bw * math.sqrt(2), 0), (bw * math.sqrt(2), 2 * bl)], n=4)
        view.solid(block, colors[sl.slider], 0.55 * alpha, 3.5, avoid=first, shade=True)
    for j in mech.joints:
        c = at[j.name]
        if j.kind == "spherical":
            ball = [(BALL * s * math.sin(v), -BALL * s * math.cos(v)) for v in np.linspace(0, np.pi, 9)]
            view.solid(_lathe(c, np.array([0.0, 0, 1]), ball), (0.82, 0.82, 0.82), alpha, 4.5, avoid=first, shade=view.is3d)
            continue
        moving = next((l for l in j.links if l in motion.frames), None)
        k = np.array(j.axis) if GROUND in j.links or moving is None else motion.frames[moving][i] @ np.array(j.axis)
        view.solid(_lathe(c, k, [(PIN_R * s, -PIN_H * s), (PIN_R * s, PIN_H * s)]), (1.0, 1.0, 1.0), alpha, 4, avoid=first)
        tip = c + 2.2 * PIN_H * s * k  # the axis' centre line, through the centre of a spherical chain
        if first:
            view.line(np.array([chain.centre if chain.centre is not None else 2 * c - tip, tip]), avoid=True, color=INK,
                      lw=0.6, ls=(0, (8, 2, 1, 2)), alpha=0.6, zorder=2.5)
            GROUND in j.links and _support(view, c, k, bars_at[j.name])
    if first:
        _place_labels(view, at | ({"O": chain.centre} if chain.centre is not None else {}))


def _axes(fig, mid, half, span, chain):
    """The projections to one scale; the 3-D view (orthographic) from where the pairs stand farthest apart."""
    keys, views = [chain.a0, chain.A, chain.B, chain.b0], []
    best = max(((az, el) for az in (-150, -135, -120, -60, -45, -30, 30, 45, 60, 120, 135, 150) for el in (20, 28, 35)),
               key=lambda v: min(np.linalg.norm((keys[i] - keys[j]) @ _basis3d(*v).T) for i in range(4) for j in range(i))
               - 0.1 * span * abs(v[0] + 45) / 180)
    for n, (title, a, b) in enumerate(VIEWS):
        ax = fig.add_subplot(2, 2, n + 1, **({"projection": "3d", "computed_zorder": False} if a is None else {}))
        ax.set_title(title, fontsize=10), ax.tick_params(labelsize=7 if a is None else 8, pad=0 if a is None else 3.5)
        if a is None:
            ax.set(proj_type="ortho", **{f"{c}lim": (m - h, m + h) for c, m, h in zip("xyz", mid, half)})
            ax.set_xlabel("x [m]", labelpad=0), ax.set_ylabel("y [m]", labelpad=0), ax.set_zlabel("z [m]", labelpad=0)
            ax.view_init(elev=best[1], azim=best[0]), ax.locator_params(nbins=4)
            ax.set_box_aspect(tuple(2 * half), zoom=0.95)  # equal scale on the three axes
            views.append(_View(ax, _basis3d(*best), True, span))
            continue
        ax.set(xlim=(mid[a] - span / 2, mid[a] + span / 2), ylim=(mid[b] - span / 2, mid[b] + span / 2),
               xlabel=f"{'xyz'[a]} [m]", ylabel=f"{'xyz'[b]} [m]", aspect="equal")
        ax.grid(True, lw=0.3, alpha=0.4)
        views.append(_View(ax, np.eye(3)[[a, b]], False, span))
    return views


def draw_spatial(mech, angles, out: Path, arrows=None) -> Path:
    """The mechanism at crank angles ``angles`` [rad] (one: a skeleton; several: a position plan, the first solid)
    in 3-D and three projections, with the moving points' paths over a turn and, at one angle, ``arrows``
    (``draw.vectors.Arrows``, 3-D) to one scale, written to ``out`` (.png/.svg/.pdf)."""
    plt = plt_module()
    angles, chain = np.atleast_1d(np.asarray(angles, dtype=float)).reshape(-1), assembled_chain(mech)
    motion, turn = solve(mech, angles, chain), full_turn(mech, chain)
    travel = slide_displacement(mech, turn)
    cloud = np.concatenate([*turn.values(), *(mech.point(sl.point) + np.outer(np.nan_to_num(travel[sl.name]), sl.direction)
                                              for sl in mech.slides)])
    if chain.centre is not None:  # the sphere, drawn whole as parallels and meridians (NaN-broken)
        t = np.append(np.linspace(0, 2 * np.pi, 73), np.nan) + np.zeros((5, 1))
        lat, c = np.radians([[-60], [-30], [0], [30], [60]]) + 0 * t, np.cos(t)
        wire = np.linalg.norm(chain.a0 - chain.centre) * np.concatenate([  # rings at latitudes, meridians at 60° + lat
            np.stack([c * np.cos(lat), np.sin(t) * np.cos(lat), np.sin(lat)], -1),
            np.stack([c * np.cos(lat + 1.05), c * np.sin(lat + 1.05), np.sin(t)], -1)]).reshape(-1, 3) + chain.centre
        cloud = np.concatenate([cloud, wire])
    lo, hi = np.nanmin(cloud, 0), np.nanmax(cloud, 0)
    mid, span = 0.5 * (lo + hi), float(np.max(hi - lo)) * 1.3 or 1.0
    travel = {k: (t0 - 0.8 * BLOCK[0] * span, t1 + 0.8 * BLOCK[0] * span) for k, (t0, t1) in slide_travel(mech, turn).items()}
    colors = {GROUND: GROUND_GREY, chain.crank: CRANK, chain.coupler: LINK}
    colors |= {l: OTHERS[k % 3] for k, l in enumerate(l.name for l in mech.links if l.name not in colors)}
    views = _axes(fig := plt.figure(figsize=FIGSIZE, dpi=DPI, layout="constrained"), mid, np.maximum(0.5 * (hi - lo), 0.2 * span) * 1.08, span, chain)
    plane = max((v for v in views if not v.is3d), key=lambda v: abs(np.cross(*v.basis) @ chain.ka))
    for v in views:
        if chain.centre is not None:
            v.line(wire, color=GROUND_GREY, lw=0.4, alpha=0.3, zorder=0.5)
            v.line(chain.centre, marker="+", ms=9, mew=1.4, color=INK, zorder=5, ls="none")
        for k, p in enumerate(p for p in turn if p not in mech.link(GROUND).points):
            v.line(turn[p][::4], avoid=True, color=PATHS[k % len(PATHS)], lw=1.0, ls=(0, (4, 2)), alpha=0.8, zorder=2,
                   label=f"path of {p}")
        for i in range(len(angles) if v is plane and len(angles) > 1 else 0):
            a, c = v.proj(motion.points[chain.pair_a].d[0][i]), v.proj(chain.a0)
            v.text(np.zeros(3), a + (1.6 * BALL + 0.5 * CHAR) * span * _unit(a - c), str(i), fontsize=7, color=CRANK,
                   ha="center", va="center", zorder=8)
        for i in range(len(angles))[::-1]:
            _pose(v, mech, chain, motion, i, colors, travel, 1.0 if i == 0 else PALE)
    if arrows is not None:
        from linkgen.draw.family_vectors import draw_spatial_arrows

        mu = draw_spatial_arrows(views, arrows, span)
    kinds = {j.kind for j in mech.joints} | {"ground"} | ({"centre"} if chain.centre is not None else set())
    handles = [Line2D([], [], color=colors[l.name], lw=3, label=l.name) for l in mech.links if l.name != GROUND] + [
        Line2D([], [], ls="none", marker=m, ms=8, mfc=fc, mec=INK, mew=1.4 if m == "+" else 1, label=t) for kind, m, fc, t in (
            ("spherical", "o", "0.82", "spherical pair"), ("revolute", "s", "white", "revolute pair (along its axis)"),
            ("cylindrical", "s", "white", "cylindrical pair (along its axis)"),
            ("ground", "^", "white", "ground pivot"), ("centre", "+", INK, "centre O and its sphere")) if kind in kinds]
    handles += views[0].ax.get_legend_handles_labels()[0]
    fig.legend(handles=handles, loc="outside lower center", ncol=min(len(handles), 5), fontsize=8, frameon=False)
    if chain.input_slides:  # the input's displacement s [m] where a crank has its angle
        deg, step, sym, unit = angles, np.diff(angles), "s", " m"
    else:
        deg, step, sym, unit = np.degrees(angles), np.diff(np.degrees(angles)), "φ", "°"
    what = (f"{sym} = {deg[0]:.4g}{unit}" if len(angles) == 1 else f"position plan: {len(angles)} positions from "
            f"{sym} = {deg[0]:.4g}{unit}" + (f", every {step[0]:.4g}{unit}" if np.allclose(step, step[0]) else "")
            + f" (0 solid, numbered at the {'input slider' if chain.input_slides else 'crank pin'})")
    if arrows is not None:
        what += f", {arrows.what}: 1 m of drawing = {mu:g} {arrows.unit}"
    fig.suptitle(title_of(mech, 100) + f"\n{what}", fontsize=11)
    save(fig, out)
    return Path(out)


def _columns(plt, path, title, cols, phi, thin, size, xlabel="φ [deg]"):
    """A column a quantity: closed form (line) and MuJoCo (markers) over φ, their difference below."""
    fig = plt.figure(figsize=size, layout="constrained")
    axes, seen = fig.subplots(2, len(cols), sharex="col", squeeze=False, gridspec_kw={"height_ratios": (2, 1)}), {}
    for (head, unit, series), top, low in zip(cols, axes[0], axes[1]):
        for label, (ours, theirs, color) in series.items():
            seen[label] = Line2D([], [], color=color, lw=2, label=label)
            top.plot(phi, ours, color=color, lw=1.3)
            top.plot(phi[::thin], theirs[::thin], "o", ms=4, mfc="none", mec=color, mew=0.9)
            low.plot(phi, theirs - ours, color=color, lw=0.9)
        top.set(title=head, ylabel=f"[{unit}]")
        low.set(xlabel=xlabel, ylabel=f"MuJoCo − closed form [{unit}]", xlim=(phi.min(), phi.max()))
        low.ticklabel_format(axis="y", style="sci", scilimits=(-2, 3))
        top.grid(True, lw=0.3, alpha=0.5), low.grid(True, lw=0.3, alpha=0.5)
    style = [Line2D([], [], color="k", lw=1.3, label="closed form"),
             Line2D([], [], ls="none", marker="o", mfc="none", mec="k", label=f"MuJoCo (every {thin}th sample)")]
    fig.legend(handles=[*seen.values(), *style], loc="outside lower center", ncol=len(seen) + 2, fontsize=8, frameon=False)
    fig.suptitle(title), save(fig, path, dpi=CHECK_DPI)


def plot_spatial_check(check, out_dir: Path, mech=None) -> list[str]:
    """Figures of a ``SpatialCheck`` in ``out_dir``, closed form against MuJoCo over φ: the points' coordinates
    (and the output's angle or travel, given the ``mech``), velocities, accelerations, the balancing torque, the
    loop gap; their file names."""
    plt = plt_module()
    s, name, out_dir, kind = check.samples, check.model, Path(out_dir), f"{check.model} ({check.kind})"
    slides = check.kind in ("PSSR", "PSSP")  # the input's displacement s [m] on the x axis, a balancing force
    phi, thin = (s["phi"] if slides else np.degrees(s["phi"])), max(1, len(s["phi"]) // 36)
    xlabel = "s [m]" if slides else "φ [deg]"
    cols, size = [], (float(s["gap"].max()) / check.gap if check.gap > 0 else None)
    if mech is not None:
        chain = assembled_chain(mech)
        size, ours, b = chain.size, solve(mech, s["phi"], chain).output.d[0], s["points"][chain.pair_b][:, 0]
        if chain.output_slides:
            cols.append((f"output {chain.output}: travel s", "m", {"output travel s": (ours, (b - chain.B) @ chain.kb, "C3")}))
        else:
            theirs = ours + np.remainder(angle_about(chain.kb, b - chain.b0) - ours + np.pi, 2 * np.pi) - np.pi
            cols.append((f"output {chain.output}: angle ψ", "deg",
                         {"output angle ψ": (*(np.degrees(np.unwrap(x)) for x in (ours, theirs)), "C3")}))
    cols += [(f"point {p}", "m", {c: (s["closed"][p][0][:, k], s["points"][p][:, 0, k], f"C{k}") for k, c in enumerate("xyz")})
             for p in s["points"]]
    names = [f"{name}_coordinates.png", f"{name}_velocities.png", f"{name}_accelerations.png", f"{name}_torque.png",
             f"{name}_loop_gap.png"]
    _columns(plt, out_dir / names[0], f"{kind}: positions, closed form vs MuJoCo", cols, phi, thin, (3.4 * len(cols) + 1.8, 6),
             xlabel)
    for order, (fname, what, unit) in enumerate(((names[1], "velocities", "m/s"), (names[2], "accelerations", "m/s²")), 1):
        moving = [(f"point {p}", unit, {c: (s["closed"][p][order][:, k], s["points"][p][:, order, k], f"C{k}")
                                        for k, c in enumerate("xyz")}) for p in s["points"]]
        _columns(plt, out_dir / fname, f"{kind}: {what}, closed form vs MuJoCo", moving, phi, thin,
                 (3.4 * len(moving) + 1.8, 6), xlabel)
    load = ("force on the input slider", "N", "balancing force") if slides else ("torque on the crank", "N·m",
                                                                              "balancing torque")
    _columns(plt, out_dir / names[3], f"{kind}: balancing {load[0]}, closed form vs MuJoCo",
             [("", load[1], {load[2]: (s["closed_torque"], s["torque"], "C3")})], phi, thin, (9, 6), xlabel)
    fig, ax = plt.subplots(figsize=(9.0, 3.8), layout="constrained")
    ax.semilogy(phi, np.maximum(s["gap"], 1e-18), "k", lw=1, label="loop gap in MuJoCo:\ndistance across the closing pair")
    if size:
        ax.axhline(GAP_TOL * size, color="r", ls=":", lw=1.2, label=f"tolerance {GAP_TOL:g} × size = {GAP_TOL * size:.2g} m")
    ax.set(title=f"{kind}: loop gap over the {'input range' if slides else 'revolution'}", xlabel=xlabel, ylabel="[m]",
           xlim=(phi.min(), phi.max()))
    ax.grid(True, which="both", lw=0.3, alpha=0.5)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, frameon=False)
    save(fig, out_dir / names[4], dpi=CHECK_DPI)
    return names
