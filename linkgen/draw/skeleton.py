"""The kinematic skeleton as a textbook draws it, on a matplotlib axes.

Ground pivots are hatched supports, bars are lines, links of three or more points are plates
(their points' convex hull), sliders are blocks on their guides (a hatched line when the guide
is the ground, a slot along the guide link otherwise), revolute joints are small circles, and
every point carries its name. The crank carries an arrow for the sense of ω; springs are
zig-zags between their points and torsion springs spirals about their joints (``draw.springs``). Every size is a
fraction of the mechanism's extent, so a 2 cm slider-crank and a 2 m press look alike."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkgen.families.planar.positions import Positions
from linkgen.families.planar.description import GROUND
from linkgen.families.planar.plate import convex_hull
from linkgen.draw.springs import draw_springs

# Sizes as fractions of the mechanism's extent (the diagonal of its points' bounding box).
JOINT_RADIUS = 0.011
BLOCK = (0.075, 0.042)  # slider block: length along the guide, width across it
SUPPORT = (0.05, 0.04)  # ground support triangle: base width, height
HATCH = 0.014  # length of a hatch stroke
LABEL_OFFSET = 0.022
ARROW_RADIUS = 0.06
PLATE_FILL = 0.12  # a plate's fill opacity
SLOT_BLOCK = 0.65  # a block in a moving slot, against one on a ground guide
# Colours: the MJCF's materials, so drawings and MuJoCo frames read alike.
CRANK = (0.85, 0.3, 0.2)
LINK = (0.25, 0.45, 0.8)
GROUND_GREY = (0.35, 0.35, 0.35)
INK = (0.1, 0.1, 0.1)


@dataclass(frozen=True)
class Frame:
    """What stays fixed between the positions drawn: the scale and each slider's travel."""

    size: float
    travel: dict[str, tuple[float, float]]


def frame_of(paths: Positions) -> Frame:
    """The drawing frame from positions over the whole range (sizes, guide lengths)."""
    size = paths.size()
    return Frame(size, {p: paths.travel(p) for p in paths.guides})


def _color(mech, link: str) -> tuple[float, float, float]:
    return CRANK if link == mech.crank else GROUND_GREY if link == GROUND else LINK


def _rot(u: np.ndarray) -> np.ndarray:
    return np.array([-u[1], u[0]])


def hatch_line(ax, p0, p1, side: np.ndarray, size: float, *, alpha: float = 1.0, z: float = 1.0) -> None:
    """A fixed line from p0 to p1 with hatch strokes on ``side`` (unit normal)."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    ax.plot([p0[0], p1[0]], [p0[1], p1[1]], color=INK, lw=1.4, alpha=alpha, zorder=z, solid_capstyle="butt")
    length = float(np.hypot(*(p1 - p0)))
    if length == 0.0:
        return
    u = (p1 - p0) / length
    step = 0.6 * HATCH * size
    k = max(int(length / step), 1)
    stroke = HATCH * size * (side - u) / math.sqrt(2.0)
    segs = [(p0 + u * (j + 0.5) * length / k, p0 + u * (j + 0.5) * length / k + stroke) for j in range(k)]
    from matplotlib.collections import LineCollection

    ax.add_collection(LineCollection(segs, colors=[INK], linewidths=0.7, alpha=alpha, zorder=z))


def _support(ax, p: np.ndarray, size: float, alpha: float) -> None:
    w, h = SUPPORT[0] * size, SUPPORT[1] * size
    tri = np.array([p, p + (-0.5 * w, -h), p + (0.5 * w, -h)])
    from matplotlib.patches import Polygon

    ax.add_patch(Polygon(tri, closed=True, facecolor="white", edgecolor=INK, lw=1.0, alpha=alpha, zorder=1.5))
    hatch_line(ax, p + (-0.8 * w, -h), p + (0.8 * w, -h), np.array([0.0, -1.0]), size, alpha=alpha, z=1.5)


def _block(ax, centre: np.ndarray, u: np.ndarray, size: float, color, alpha: float, z: float = 4.0) -> None:
    from matplotlib.patches import Polygon

    a, b = 0.5 * BLOCK[0] * size * u, 0.5 * BLOCK[1] * size * _rot(u)
    corners = np.array([centre - a - b, centre + a - b, centre + a + b, centre - a + b])
    ax.add_patch(Polygon(corners, closed=True, facecolor=(*color, 0.6 * alpha), edgecolor=(*INK, alpha),
                         lw=1.0, zorder=z))


def _guide(ax, pos: Positions, frame: Frame, pair: str, i: int, alpha: float) -> None:
    g = pos.guides[pair]
    base, u = pos.guide_line(pair, i)
    lo, hi = frame.travel[pair]
    pad = 0.5 * BLOCK[0] * frame.size + HATCH * frame.size
    p0, p1 = base + (lo - pad) * u, base + (hi + pad) * u
    half = 0.5 * BLOCK[1] * frame.size * _rot(u)
    if g.guide == GROUND:
        hatch_line(ax, p0 - half, p1 - half, -_rot(u), frame.size, alpha=alpha, z=2)
        return
    color = _color(pos.mechanism, g.guide)
    for s in (-1.0, 1.0):  # a slot along the moving guide link
        q0, q1 = p0 + s * half, p1 + s * half
        ax.plot([q0[0], q1[0]], [q0[1], q1[1]], color=color, lw=1.2, alpha=alpha, zorder=2)


def _drive_arrow(ax, pos: Positions, frame: Frame, i: int, alpha: float) -> None:
    from matplotlib.patches import FancyArrowPatch

    mech = pos.mechanism
    if mech.slide_drive:  # a straight arrow along the driven guide beside the slider, its sense that of the speed
        _, u = pos.guide_line(mech.drive.joint, i)
        g = pos.guides[mech.drive.joint]
        c = pos.local_to_world(g.slider, g.point, i)
        sense = 1.0 if mech.drive.omega >= 0.0 else -1.0
        r = ARROW_RADIUS * frame.size
        side = np.array([-u[1], u[0]]) * 1.2 * r
        p0, p1 = c + side - 0.5 * sense * r * u, c + side + 0.9 * sense * r * u
        ax.add_patch(FancyArrowPatch(p0, p1, arrowstyle="-|>", mutation_scale=10, color=CRANK, lw=1.2,
                                     alpha=alpha, zorder=6))
        q = c + 1.8 * side
        ax.text(q[0], q[1], "ṡ", color=CRANK, fontsize=10, ha="center", va="center", alpha=alpha, zorder=6)
        return
    pivot = pos.points[mech.revolute(mech.drive.joint).point][i]
    th = float(pos.angles[mech.crank][i])
    sense = 1.0 if mech.drive.omega >= 0.0 else -1.0
    r = ARROW_RADIUS * frame.size
    a0, a1 = th + sense * 0.35, th + sense * 1.35
    p0 = pivot + r * np.array([math.cos(a0), math.sin(a0)])
    p1 = pivot + r * np.array([math.cos(a1), math.sin(a1)])
    ax.add_patch(FancyArrowPatch(p0, p1, connectionstyle=f"arc3,rad={0.35 * sense}", arrowstyle="-|>",
                                 mutation_scale=10, color=CRANK, lw=1.2, alpha=alpha, zorder=6))
    mid = 0.5 * (a0 + a1)
    q = pivot + 1.45 * r * np.array([math.cos(mid), math.sin(mid)])
    ax.text(q[0], q[1], "ω", color=CRANK, fontsize=10, ha="center", va="center", alpha=alpha, zorder=6)


def _label_direction(pos: Positions, name: str, i: int) -> np.ndarray:
    """Unit vector from a point to its label: away from the bars that meet there (and from the
    support under a ground pivot)."""
    here = pos.points[name][i]
    pull = np.zeros(2)
    for link in pos.mechanism.links:
        if name not in link.points:
            continue
        if link.name == GROUND:
            pull += np.array([0.0, -1.0])
            continue
        for other in link.points:
            r = pos.points[other][i] - here
            n = float(np.hypot(*r))
            if other != name and n > 0.0:
                pull += r / n
    n = float(np.hypot(*pull))
    if n < 1e-9:
        return np.array([1.0, 1.0]) / math.sqrt(2.0)
    return -pull / n


def draw_skeleton(ax, pos: Positions, frame: Frame, i: int, *, alpha: float = 1.0, labels: bool = True,
                  arrow: bool = True) -> None:
    """Draw the mechanism at index ``i`` of ``pos`` on ``ax`` (data units: metres)."""
    from matplotlib.patches import Circle, Polygon

    mech, size = pos.mechanism, frame.size
    for rev in mech.revolutes:
        if GROUND in rev.links:
            _support(ax, pos.points[rev.point][i], size, alpha)
    for pair in pos.guides:
        _guide(ax, pos, frame, pair, i, alpha)
    for g in mech.gears:  # pitch circles: the fixed gear about the crank's pivot, the planet about its centre
        pivot = pos.points[mech.revolute(mech.drive.joint).point][i]
        centre = pos.points[mech.link(g.planet).points[0]][i]
        ax.add_patch(Circle(pivot, g.fixed_radius, fill=False, edgecolor=GROUND_GREY, lw=1.0, ls=(0, (6, 3)),
                            alpha=alpha, zorder=1))
        ax.add_patch(Circle(centre, g.planet_radius, facecolor=(*LINK, 0.08 * alpha), edgecolor=(*LINK, alpha),
                            lw=1.2, ls=(0, (6, 3)), zorder=2.5))
    _cams(ax, pos, frame, i, alpha)
    guides = {g.guide for g in pos.guides.values()}
    for link in mech.links:
        if link.name == GROUND:
            continue
        color = _color(mech, link.name)
        xy = np.array([pos.points[p][i] for p in link.points])
        # A plate is its points' hull, filled only in a solid drawing (overlaid positions would stack
        # their fills into a blur); a guide link stays bars, so that its slot reads as the line it is.
        if len(xy) >= 3 and link.name not in guides:
            hull = convex_hull(xy)
            if len(hull) >= 3:
                fill = (*color, PLATE_FILL * alpha) if alpha >= SOLID_ALPHA else "none"
                ax.add_patch(Polygon(hull, closed=True, facecolor=fill, edgecolor=(*color, alpha),
                                     lw=2.2, zorder=3, joinstyle="round"))
                continue
        if len(xy) >= 2:
            first = xy[0]
            for q in xy[1:]:
                ax.plot([first[0], q[0]], [first[1], q[1]], color=color, lw=2.6, alpha=alpha, zorder=3,
                        solid_capstyle="round")
    draw_springs(ax, pos, size, i, alpha)
    for pair, g in pos.guides.items():
        _, u = pos.guide_line(pair, i)
        centre = pos.local_to_world(g.slider, g.point, i)
        # a block in a moving link's slot is drawn smaller, over any block on the same pin
        _block(ax, centre, u, size * (1.0 if g.guide == GROUND else SLOT_BLOCK), _color(mech, g.slider), alpha,
               z=4.0 if g.guide == GROUND else 4.2)
    for rev in mech.revolutes:
        c = pos.points[rev.point][i]
        ax.add_patch(Circle(c, JOINT_RADIUS * size, facecolor="white", edgecolor=INK, lw=1.0, alpha=alpha, zorder=5))
    if arrow:
        _drive_arrow(ax, pos, frame, i, alpha)
    if labels:
        d = LABEL_OFFSET * size
        for name, p in pos.points.items():
            u = _label_direction(pos, name, i)
            q = p[i] + 1.6 * d * u
            ax.text(q[0], q[1], name, fontsize=9, color=INK, alpha=alpha, zorder=7, ha="center", va="center")


# Drawings at this opacity or above are a plan's solid position (or a single drawing).
SOLID_ALPHA = 0.99


def _cams(ax, pos: Positions, frame: Frame, i: int, alpha: float) -> None:
    """Each cam's profile turned with the crank, and its roller on the follower."""
    from matplotlib.patches import Circle, Polygon

    mech = pos.mechanism
    if not mech.cams:
        return
    from linkgen.families.planar.cam_profile import drawn_profiles

    profiles = drawn_profiles(mech)
    o = pos.points[mech.revolute(mech.drive.joint).point][i]
    k = pos.points[mech.link(mech.crank).points[1]][i]
    a = math.atan2(k[1] - o[1], k[0] - o[0])  # the crank's frame: x from its first point to its second
    c, s = math.cos(a), math.sin(a)
    for cam in mech.cams:
        xy = o + profiles[cam.name] @ np.array([[c, s], [-s, c]])
        if alpha >= SOLID_ALPHA:  # a position plan draws the profile once, with its solid position
            ax.add_patch(Polygon(xy, closed=True, facecolor=(*CRANK, 0.15 * alpha), edgecolor=(*CRANK, alpha), lw=1.2,
                                 zorder=2.5))
        if cam.roller_radius > 0:
            ax.add_patch(Circle(pos.points[cam.roller][i], cam.roller_radius, facecolor=(1, 1, 1, alpha),
                                edgecolor=(*LINK, alpha), lw=1.2, zorder=3.5))


def set_limits(ax, paths: Positions, frame: Frame, margin: float = 0.12) -> None:
    """Equal scale, the whole range's extent plus a margin (a fraction of the size)."""
    x0, x1, y0, y1 = paths.bounds()
    mech = paths.mechanism
    for g in mech.gears:  # the fixed gear's pitch circle is part of the drawing
        px, py = paths.points[mech.revolute(mech.drive.joint).point][0]
        r = g.fixed_radius
        x0, x1, y0, y1 = min(x0, px - r), max(x1, px + r), min(y0, py - r), max(y1, py + r)
    if mech.cams:  # a cam's profile turns within the circle of its largest radius
        from linkgen.families.planar.cam_profile import cam_reach

        px, py = paths.points[mech.revolute(mech.drive.joint).point][0]
        r = cam_reach(mech)
        x0, x1, y0, y1 = min(x0, px - r), max(x1, px + r), min(y0, py - r), max(y1, py + r)
    m = margin * frame.size
    ax.set_xlim(x0 - m, x1 + m)
    ax.set_ylim(y0 - m - SUPPORT[1] * frame.size, y1 + m)
    ax.set_aspect("equal", adjustable="box")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.grid(True, lw=0.3, alpha=0.4)


__all__ = ["Frame", "draw_skeleton", "frame_of", "hatch_line", "set_limits"]
