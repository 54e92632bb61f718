"""Velocity and acceleration plans drawn as a textbook draws them: from the pole, every point's
vector (thin, grey) to its vertex, named by the point's lower-case letter; each link's relative
vectors in its own colour (in the acceleration plan the normal part dashed, the tangential part
solid; a slider's Coriolis part dotted), vertices that fall together named together (``p ≡ o, c``),
and a scale bar of a round length. The plan's data (``families.planar.vector_plan.VectorPlan``)
is returned with the figure, so that what is drawn can be checked without reading pixels."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from linkgen.draw.plan import DPI, FIGSIZE, input_at, plt_module, rates_of, save, title_of
from linkgen.draw.skeleton import INK

STYLES = {"absolute": dict(color=(0.55, 0.55, 0.55), lw=0.9, ls="-"), "relative": dict(lw=1.8, ls="-"),
          "normal": dict(lw=1.5, ls=(0, (5, 2))), "tangential": dict(lw=1.8, ls="-"),
          "coriolis": dict(lw=1.5, ls=(0, (1.5, 1.5))), "sliding": dict(lw=1.8, ls="-")}
# Vertices closer than this fraction of the plan's size are one place on paper: named together.
SAME_PLACE = 0.01
LABEL_GAP = 0.035  # label distance from its vertex, a fraction of the plan's size


def nice_length(x: float) -> float:
    """The largest of 1, 2, 5 × 10^k not above ``x`` (> 0): a scale bar's length."""
    k = math.floor(math.log10(x))
    for m in (5.0, 2.0, 1.0):
        if m * 10.0 ** k <= x:
            return m * 10.0 ** k
    return 10.0 ** k


def _arrow(ax, a, b, color, style, z: float) -> None:
    from matplotlib.patches import FancyArrowPatch

    if float(np.linalg.norm(np.asarray(b) - np.asarray(a))) == 0.0:
        return
    ax.add_patch(FancyArrowPatch(tuple(a), tuple(b), arrowstyle="-|>", mutation_scale=11, color=color,
                                 lw=style["lw"], linestyle=style["ls"], shrinkA=0, shrinkB=0, zorder=z))


def _places(plan) -> list[tuple[np.ndarray, list[str]]]:
    """Vertices grouped by where they fall on paper: (position, names), the pole's group first."""
    tol = SAME_PLACE * (plan.size or 1.0)
    named = dict(plan.vertices)
    for c in plan.chains:  # intermediate vertices (a guide's coincident point, n_ba, k_a) have no closed-form vector
        for name, xy in zip(c.names, c.xy):
            named.setdefault(name, xy)
    places: list[tuple[np.ndarray, list[str]]] = []
    for name, xy in named.items():
        for at, names in places:
            if float(np.linalg.norm(at - xy)) <= tol:
                names.append(name)
                break
        else:
            places.append((np.asarray(xy, dtype=float), [name]))
    return places


def plan_axes(ax, plan, colors: dict[str, tuple]) -> None:
    """Draw ``plan`` on ``ax`` in its own units (m/s or m/s²), equal on both axes."""
    size = plan.size or 1.0
    for name, v in plan.vertices.items():
        if name != plan.pole and float(np.linalg.norm(v)) > SAME_PLACE * size:
            _arrow(ax, (0.0, 0.0), v, STYLES["absolute"]["color"], STYLES["absolute"], 3)
    for c in plan.chains:
        color = colors.get(c.link, INK)
        for (a, b), kind in zip(zip(c.xy[:-1], c.xy[1:]), c.kinds):
            if kind != "absolute":
                _arrow(ax, a, b, color, STYLES[kind], 4)
    centre = np.mean([v for v in plan.vertices.values()], axis=0)
    for at, names in _places(plan):
        main = [n for n in names if "_" not in n]
        minor = [n for n in names if "_" in n]
        text = " ≡ ".join(main[:1] + ([", ".join(main[1:])] if main[1:] else [])) if main else ", ".join(minor)
        d = at - centre
        n = float(np.linalg.norm(d))
        u = d / n if n > 1e-12 * size else np.array([0.7071, 0.7071])
        q = at + (LABEL_GAP if main else -LABEL_GAP) * size * u  # the minor names on the other side
        ax.plot(*at, "o", ms=2.5, color=INK, zorder=5)
        ax.text(q[0], q[1], text, fontsize=10 if main else 7, style="italic", color=INK, ha="center", va="center",
                zorder=6, bbox=dict(boxstyle="round,pad=0.1", fc="white", ec="none", alpha=0.8))
    bar = nice_length(0.3 * size)
    every = np.concatenate([c.xy for c in plan.chains] + [np.zeros((1, 2))])
    x0, y0 = float(every[:, 0].min()), float(every[:, 1].min()) - 0.12 * size  # under the plan, at its left
    ax.plot([x0, x0 + bar], [y0, y0], color=INK, lw=2.0, solid_capstyle="butt")
    ax.text(x0 + 0.5 * bar, y0 + 0.03 * size, f"{bar:g} {plan.unit}", ha="center", va="bottom", fontsize=9)
    ax.set_aspect("equal", adjustable="datalim")
    ax.margins(0.12)
    ax.set_xlabel(f"x [{plan.unit}]")
    ax.set_ylabel(f"y [{plan.unit}]")
    ax.grid(True, lw=0.3, alpha=0.4)


def link_colors(links: list[str]) -> dict[str, tuple]:
    """One colour per link or pair, in order (tab10)."""
    plt = plt_module()
    cmap = plt.get_cmap("tab10")
    return {name: cmap(k % 10)[:3] for k, name in enumerate(links)}


def vector_plan_figure(mech, plan, out: Path | None = None, *, title: str | None = None):
    """The figure of ``plan`` (a ``VectorPlan`` of ``mech``); saved to ``out`` when given.
    Returns (figure, plan)."""
    from matplotlib.lines import Line2D

    plt = plt_module()
    owners = list(dict.fromkeys(c.link for c in plan.chains))
    colors = link_colors(owners)
    fig, ax = plt.subplots(figsize=FIGSIZE, dpi=DPI, layout="constrained")
    plan_axes(ax, plan, colors)
    handles = [Line2D([], [], color=colors[o], lw=2, label=o) for o in owners]
    kinds = sorted({k for c in plan.chains for k in c.kinds} - {"absolute", "relative", "sliding"})
    handles += [Line2D([], [], color=INK, lw=STYLES[k]["lw"], ls=STYLES[k]["ls"], label=f"{k} part") for k in kinds]
    handles.append(Line2D([], [], **STYLES["absolute"], label="from the pole"))
    ax.legend(handles=handles, fontsize=8, loc="upper left", bbox_to_anchor=(1.01, 1.0), frameon=False)
    rates = rates_of(mech, plan.omega, plan.epsilon if plan.kind == "acceleration" else None)
    ax.set_title(title or f"{title_of(mech)}\n{plan.kind} plan at {input_at(mech, plan.phi)}, {rates}, "
                 f"pole {plan.pole}", fontsize=10)
    if out is not None:
        save(fig, out)
    return fig, plan


VIEWS = (("top view (x–y)", (0, 1)), ("front view (x–z)", (0, 2)), ("side view (y–z)", (1, 2)))


def spatial_plan_figure(mech, plan, out: Path | None = None):
    """A 3-D plan (a spatial four-bar's) drawn as its top, front and side projections, to one
    scale each; saved to ``out`` when given. Returns (figure, plan)."""
    from linkgen.model.plans import projected

    plt = plt_module()
    owners = list(dict.fromkeys(c.link for c in plan.chains))
    colors = link_colors(owners)
    fig, axes = plt.subplots(1, 3, figsize=(15.0, 5.6), dpi=DPI, layout="constrained")
    for ax, (name, (a, b)) in zip(axes, VIEWS):
        plan_axes(ax, projected(plan, np.eye(3)[[a, b]]), colors)
        ax.set_title(name, fontsize=10)
        ax.set_xlabel(f"{'xyz'[a]} [{plan.unit}]")
        ax.set_ylabel(f"{'xyz'[b]} [{plan.unit}]")
    from matplotlib.lines import Line2D

    handles = [Line2D([], [], color=colors[o], lw=2, label=o) for o in owners]
    fig.legend(handles=handles, loc="outside lower center", ncol=len(handles), fontsize=8, frameon=False)
    fig.suptitle(f"{title_of(mech, 110)}\n{plan.kind} plan at {input_at(mech, plan.phi)}, {rates_of(mech, plan.omega)}, "
                 f"pole {plan.pole}: the 3-D plan's projections", fontsize=10)
    if out is not None:
        save(fig, out)
    return fig, plan


__all__ = ["link_colors", "nice_length", "plan_axes", "spatial_plan_figure", "vector_plan_figure"]
