"""The skeleton as a teacher puts it on the board: the mechanism at one crank angle with its links'
names and lengths, the vectors of ``draw.vectors`` as arrows to one stated scale (a scale bar of
a round value), and a box with the design summary (each output's stroke or swing and time ratio,
the least transmission angle of each group)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from linkgen.draw.plan import DPI, input_at, plt_module, rates_of, save, title_of
from linkgen.draw.polygons import nice_length
from linkgen.draw.skeleton import INK, LINK, draw_skeleton, frame_of, set_limits
from linkgen.families.planar.description import GROUND

TEACHING_FIGSIZE = (10.0, 6.5)  # inches: the drawing and the summary box beside it
# The longest arrow on paper, a fraction of the mechanism's extent.
LONGEST = 0.3
COLORS = {"velocity": (0.1, 0.55, 0.2), "acceleration": (0.6, 0.1, 0.6), "tangential": (0.85, 0.45, 0.0),
          "normal": (0.2, 0.35, 0.85), "load": (0.8, 0.1, 0.1), "weight": (0.45, 0.3, 0.15),
          "inertia": (0.5, 0.5, 0.5), "reaction": (0.1, 0.45, 0.6)}


def paper_scale(arrows, size: float) -> float:
    """Units of the arrows per metre of the drawing (a round 1, 2, 5 × 10^k): the longest arrow
    takes at most LONGEST of the mechanism's extent ``size``."""
    longest = max((float(np.linalg.norm(a.vector)) for a in arrows.arrows), default=0.0)
    if longest == 0.0:
        return 1.0
    raw = longest / (LONGEST * size)
    k = math.floor(math.log10(raw))
    for m in (1.0, 2.0, 5.0, 10.0):
        if m * 10.0 ** k >= raw:
            return m * 10.0 ** k
    return 10.0 ** (k + 1)


def draw_arrows(ax, arrows, size: float) -> float:
    """Draw ``arrows`` on ``ax`` (data in metres) to one scale; returns the scale [unit per m]."""
    from matplotlib.patches import FancyArrowPatch

    mu = paper_scale(arrows, size)
    ends = [a.at + a.vector / mu for a in arrows.arrows]
    if ends:  # every arrow's tip inside the drawing, with a margin for its name
        pts = np.array(ends)
        (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
        m = 0.06 * size
        ax.set_xlim(min(x0, pts[:, 0].min() - m), max(x1, pts[:, 0].max() + m))
        ax.set_ylim(min(y0, pts[:, 1].min() - m), max(y1, pts[:, 1].max() + m))
    for a in arrows.arrows:
        tip = a.at + a.vector / mu
        if float(np.linalg.norm(a.vector)) == 0.0:
            continue
        color = COLORS[a.kind]
        ax.add_patch(FancyArrowPatch(tuple(a.at), tuple(tip), arrowstyle="-|>", mutation_scale=12, color=color,
                                     lw=1.8 if a.active else 1.0, alpha=1.0 if a.active else 0.35, shrinkA=0,
                                     shrinkB=0, zorder=8, linestyle="-" if a.active else (0, (3, 2))))
        q = tip + 0.02 * size * a.vector / float(np.linalg.norm(a.vector))
        ax.text(q[0], q[1], tex_label(a.label), fontsize=8, color=color, ha="center", va="center", zorder=9,
                alpha=1.0 if a.active else 0.6, bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.7))
    return mu


def tex_label(label: str) -> str:
    """``a_B^t rest`` → the symbol with its subscript and superscript set as a formula, then the rest
    as written (``v_A``, ``R_O on ground``, ``Φ_rod = −m·a_S``)."""
    import re

    m = re.match(r"^([A-Za-zΦ]+)_([A-Za-z0-9]+)(?:\^([a-z]))?(.*)$", label)
    if not m:
        return label
    sym, sub, sup, rest = m.groups()
    sym = r"\Phi" if sym == "Φ" else sym
    return f"${sym}_{{{sub}}}" + (f"^{{{sup}}}" if sup else "") + "$" + rest.replace("$", r"\$")


def _scale_bar(ax, mu: float, unit: str, size: float) -> None:
    value = nice_length(0.2 * size * mu)
    length = value / mu
    x0, x1 = ax.get_xlim()
    y0, _ = ax.get_ylim()
    p = np.array([x0 + 0.04 * (x1 - x0), y0 + 0.03 * size])
    ax.plot([p[0], p[0] + length], [p[1], p[1]], color=INK, lw=2.2, solid_capstyle="butt", zorder=9)
    ax.text(p[0] + length + 0.015 * size, p[1], f"{value:g} {unit}  (1 m of drawing = {mu:g} {unit})",
            ha="left", va="center", fontsize=8, zorder=9, bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none"))


def label_links(ax, pos, size: float) -> None:
    """Each moving link's name and length (a bar) at its middle, beside the bar."""
    mech = pos.mechanism
    centroid = np.mean([p[0] for p in pos.points.values()], axis=0)
    for link in mech.links:
        if link.name == GROUND or not link.points:
            continue
        xy = np.array([pos.points[p][0] for p in link.points])
        if len(xy) == 2:
            d = xy[1] - xy[0]
            n = float(np.linalg.norm(d))
            if n == 0.0:
                continue
            nrm = np.array([-d[1], d[0]]) / n
            mid = 0.5 * (xy[0] + xy[1])
            if link.name == mech.crank:  # the side the ω arrow is not on
                side = -1.0 if mech.drive.omega >= 0.0 else 1.0
            else:  # away from the mechanism's middle
                side = 1.0 if float(nrm @ (mid - centroid)) >= 0.0 else -1.0
            q = mid + side * 0.035 * size * nrm
            angle = math.degrees(math.atan2(d[1], d[0]))
            angle = angle - 180.0 if angle > 90.0 else angle + 180.0 if angle < -90.0 else angle
            text = f"{link.name} {n:.4g} m"
        else:
            q = xy.mean(axis=0)
            angle = 0.0
            text = link.name
        ax.text(q[0], q[1], text, fontsize=7.5, color=LINK, rotation=angle, rotation_mode="anchor", ha="center",
                va="center", zorder=7, style="italic")


def summary_lines(summary) -> list[str]:
    """The design summary in a few lines: each output's stroke or swing and time ratio, the least
    transmission angle of each group (where: a crank angle, or a prismatic input's stroke)."""
    lines = []
    stroke = bool(getattr(summary, "stroke", False) or getattr(summary, "input_slides", False))

    def at(phi: float) -> str:  # where on the input's range: a crank angle, or a prismatic input's stroke
        return f"s = {phi:.4g} m" if stroke else f"φ = {math.degrees(phi):.4g}°"

    for name, o in summary.outputs.items():
        if o.travel is None:
            continue
        what = f"stroke {o.travel:.4g} m" if o.kind == "slider" else f"swing {math.degrees(o.travel):.4g}°"
        k = f", K = {o.time_ratio:.4g}" if o.time_ratio is not None else ""
        lines.append(f"{name}: {what}{k}")
    pressure = getattr(summary, "max_pressure_angle", None)
    if pressure is not None:
        lines.append(f"largest pressure angle: {math.degrees(pressure.value):.4g}° at {at(pressure.phi)}")
    for label, ex in getattr(summary, "min_transmission_angle", {}).items():
        lines.append(f"least γ {label.split(' [')[0]}: {math.degrees(ex.value):.4g}° at {at(ex.phi)}")
    return lines


def teaching_figure(asm, phi: float, out: Path | None = None, *, arrows=None, summary=None):
    """The skeleton at crank angle ``phi`` [rad] with link names and lengths, ``arrows``
    (``draw.vectors.Arrows``, or None) and the ``summary`` box (a design summary, or None);
    saved to ``out`` when given. Returns (figure, arrows, scale [unit per m of drawing] or None: no
    arrow, or every one zero)."""
    from linkgen.families.planar.positions import drive_angles, positions

    plt = plt_module()
    mech = asm.mechanism
    paths = positions(mech, drive_angles(mech))
    frame = frame_of(paths)
    pos = positions(mech, [phi])
    fig, ax = plt.subplots(figsize=TEACHING_FIGSIZE, dpi=DPI, layout="constrained")
    pale = set(arrows.group_links) if arrows is not None and arrows.group_links else None
    draw_skeleton(ax, pos, frame, 0, alpha=0.35 if pale else 1.0)
    for name in sorted(pale or ()):  # a free body: its group's links drawn solid over the pale rest
        xy = np.array([pos.points[p][0] for p in mech.link(name).points])
        ring = np.vstack([xy, xy[:1]]) if len(xy) >= 3 else xy
        ax.plot(ring[:, 0], ring[:, 1], color=LINK, lw=3.0, zorder=6, solid_capstyle="round")
        ax.plot(xy[:, 0], xy[:, 1], "o", ms=6, mfc="white", mec=INK, zorder=6.5)
    label_links(ax, pos, frame.size)
    set_limits(ax, paths, frame)
    mu = None
    if arrows is not None and any(float(np.linalg.norm(a.vector)) > 0.0 for a in arrows.arrows):
        mu = draw_arrows(ax, arrows, frame.size)
        _scale_bar(ax, mu, arrows.unit, frame.size)
    elif arrows is not None and arrows.arrows:  # nothing to draw: the drawing says so rather than a bare scale
        ax.text(0.03, 0.03, f"{arrows.what}: every one zero here ({', '.join(a.label for a in arrows.arrows)})",
                transform=ax.transAxes, fontsize=8.5, color=INK, ha="left", va="bottom")
    if summary is not None:
        lines = summary_lines(summary)
        if lines:  # a figure legend of text only: the layout makes room for it beside the drawing
            from matplotlib.lines import Line2D

            box = fig.legend(handles=[Line2D([], [], lw=0) for _ in lines], labels=lines, title="design summary",
                             loc="outside right lower", fontsize=8, title_fontsize=8, handlelength=0, handletextpad=0,
                             alignment="left", facecolor=(0.97, 0.97, 0.92), edgecolor=(0.6, 0.6, 0.5))
            box.get_frame().set_boxstyle("round")
    what = ""
    if arrows is not None:
        what = f", {arrows.what}" + (f" on group {arrows.group} (free body)" if arrows.group else "")
    fig.suptitle(f"{title_of(mech, 110)}\n{input_at(mech, phi)}, {rates_of(mech, mech.drive.omega)}{what}", fontsize=10)
    if out is not None:
        save(fig, out)
    return fig, arrows, mu


__all__ = ["COLORS", "draw_arrows", "label_links", "paper_scale", "summary_lines", "teaching_figure", "tex_label"]
