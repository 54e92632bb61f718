"""The report's figures of one compared model: every point's path, every link angle and slider
displacement, every reaction, prismatic normal force and moment, the balancing torque and J(φ),
closed form (wide pale line) against MuJoCo (thin dashed), each over the whole compared range,
and under each kind the errors relative to their scales with the tolerance.

Legends sit outside the axes, so they never cover a curve. A quantity that hardly changes
(its spread below FLAT of its kind's scale, e.g. the angle of a link that only translates) is
drawn on an axis of ± FLAT_SPAN of that scale around its value instead of one that magnifies
rounding noise."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from linkgen.crosscheck.compare import Comparison
from linkgen.outputs import save_figure

# A curve whose spread is below this fraction of its scale is "flat" (see the module docstring).
FLAT = 1e-9
# Half-height of a flat curve's axis, relative to the scale.
FLAT_SPAN = 0.05
# Floor of the error axes: relative errors below it are drawn at it (exact zeros included).
ERROR_FLOOR = 1e-18
DPI = 90


def _plt():
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _colors(plt, n: int) -> list:
    cycle = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    if n <= len(cycle):
        return cycle
    cmap = plt.get_cmap("turbo")
    return [cmap(i / max(n - 1, 1)) for i in range(n)]


def _legend(ax, n: int) -> None:
    if n:
        ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0,
                  ncol=1 if n <= 14 else 2, frameon=False)


def _flat_limits(ax, curves: list[np.ndarray], scale: float) -> None:
    data = np.concatenate([np.ravel(c) for c in curves]) if curves else np.zeros(1)
    lo, hi = float(np.min(data)), float(np.max(data))
    if hi - lo <= FLAT * scale:
        mid = 0.5 * (lo + hi)
        ax.set_ylim(mid - FLAT_SPAN * scale, mid + FLAT_SPAN * scale)


def _drive_axis(cmp: Comparison) -> tuple[np.ndarray, str]:
    """The samples' drive input for the x axes: crank angles [deg], or a prismatic drive's stroke [m]."""
    s = cmp.run.samples
    if cmp.assembly.mechanism.slide_drive:
        return np.asarray(s.crank[0]), "s [m]"
    return np.degrees(s.crank[0]), "φ [deg]"


def _overlay(ax, phi, series: dict[str, tuple[np.ndarray, np.ndarray]], colors, scale: float,
             title: str, unit: str, xlabel: str = "φ [deg]") -> None:
    """Closed form (pale, wide) and MuJoCo (dashed black) of each named series over φ [deg] (or the
    stroke, ``xlabel``)."""
    for i, (name, (ours, theirs)) in enumerate(series.items()):
        ax.plot(phi, ours, color=colors[i % len(colors)], lw=3, alpha=0.45, label=name)
        ax.plot(phi, theirs, color="k", ls="--", lw=0.8)
    _flat_limits(ax, [s[0] for s in series.values()], scale)
    ax.set(title=title, xlabel=xlabel, ylabel=f"[{unit}]")
    ax.set_xlim(phi.min(), phi.max())
    _legend(ax, len(series))


def _errors(ax, phi, cmp: Comparison, names: list[str], labels: list[str], colors, title: str,
            xlabel: str = "φ [deg]") -> None:
    """Per-sample |MuJoCo − closed form| / scale of the named quantities, with their tolerance."""
    tols = set()
    for i, (name, label) in enumerate(zip(names, labels)):
        q = cmp.quantities[name]
        ax.semilogy(phi, np.maximum(q.errors / q.scale, ERROR_FLOOR), color=colors[i % len(colors)], lw=1,
                    label=label)
        tols.add(q.tolerance)
    for t in sorted(tols):
        ax.axhline(t, color="r", ls=":", lw=1.2, label=f"tolerance {t:g}")
    ax.set(title=f"|MuJoCo − closed form| / scale: {title}", xlabel=xlabel)
    ax.set_xlim(phi.min(), phi.max())
    _legend(ax, len(names) + len(tols))


def plot_paths(cmp: Comparison, path: Path) -> None:
    """Every moving point's path in the plane, closed form against MuJoCo."""
    plt = _plt()
    s, mo = cmp.run.samples, cmp.closed_form
    fig, ax = plt.subplots(figsize=(8, 6), constrained_layout=True)
    colors = _colors(plt, len(s.points))
    for i, p in enumerate(s.points):
        ours, theirs = mo.points[p][0], s.points[p][0]
        ax.plot(ours[:, 0], ours[:, 1], color=colors[i % len(colors)], lw=3, alpha=0.45, label=p)
        ax.plot(theirs[:, 0], theirs[:, 1], "k--", lw=0.8)
        ax.plot(*ours[0], "o", color=colors[i % len(colors)], ms=4)
    ax.set(title=f"{cmp.model}: point paths (closed form; MuJoCo dashed; dot = start)", xlabel="x [m]",
           ylabel="y [m]", aspect="equal")
    _legend(ax, len(s.points))
    save_figure(fig, path, dpi=DPI)
    plt.close(fig)


def plot_kinematics(cmp: Comparison, path: Path) -> None:
    """Link angles and slider displacements over φ; errors of every kinematic quantity."""
    plt = _plt()
    s, mo = cmp.run.samples, cmp.closed_form
    phi, xlabel = _drive_axis(cmp)
    fig, axes = plt.subplots(2, 3, figsize=(17, 8), constrained_layout=True)
    links = {n: (np.degrees(np.unwrap(mo.links[n][0])), np.degrees(np.unwrap(s.links[n][0]))) for n in s.links}
    _overlay(axes[0, 0], phi, links, _colors(plt, len(links)), 180.0, "link angles", "deg", xlabel)
    ax = axes[0, 1]
    if s.sliders:
        sl = {n: (mo.sliders[n][0], s.sliders[n][0]) for n in s.sliders}
        _overlay(ax, phi, sl, _colors(plt, len(sl)), cmp.size, "slider displacements", "m", xlabel)
    else:
        ax.set_axis_off()
        ax.text(0.5, 0.5, "no prismatic pairs", ha="center", va="center", transform=ax.transAxes)
    ax = axes[0, 2]
    ax.semilogy(phi, np.maximum(s.violation / cmp.size, ERROR_FLOOR), "k", lw=1, label="loop gap / size")
    ax.axhline(cmp.gap.tolerance, color="r", ls=":", lw=1.2, label=f"tolerance {cmp.gap.tolerance:g}")
    ax.set(title="loop gap in MuJoCo", xlabel=xlabel)
    ax.set_xlim(phi.min(), phi.max())
    _legend(ax, 2)
    for j, (kind, lk, sk) in enumerate((("position", "angle", "displacement"),
                                        ("velocity", "angular_velocity", "velocity"),
                                        ("acceleration", "angular_acceleration", "acceleration"))):
        names, labels = [], []
        for p in s.points:
            names.append(f"points.{p}.{kind}"), labels.append(p)
        for n in s.links:
            names.append(f"links.{n}.{lk}"), labels.append(f"link {n}")
        for n in s.sliders:
            names.append(f"sliders.{n}.{sk}"), labels.append(f"slider {n}")
        keep = [i for i, n in enumerate(names) if n in cmp.quantities]
        _errors(axes[1, j], phi, cmp, [names[i] for i in keep], [labels[i] for i in keep],
                _colors(plt, len(keep)), kind, xlabel)
    fig.suptitle(f"{cmp.model}: kinematics — closed form (wide pale lines) vs MuJoCo (black dashed)")
    save_figure(fig, path, dpi=DPI)
    plt.close(fig)


def plot_forces(cmp: Comparison, path: Path) -> None:
    """Reactions (magnitude), prismatic normal forces and moments, the balancing torque and
    J(φ) over φ; errors of every force quantity (forward and inverse routes)."""
    plt = _plt()
    s, cf = cmp.run.samples, cmp.closed_forces
    phi, xlabel = _drive_axis(cmp)
    slides = cmp.assembly.mechanism.slide_drive  # a prismatic drive: a balancing force [N], a reduced mass [kg]
    f_scale = max((float(np.abs(r).max()) for r in cf.reactions.values()), default=1.0) or 1.0
    fig, axes = plt.subplots(2, 3, figsize=(17, 8), constrained_layout=True)
    rx = {k: (np.linalg.norm(r, axis=1), np.linalg.norm(s.forces.reactions[k], axis=1)) for k, r in cf.reactions.items()}
    _overlay(axes[0, 0], phi, rx, _colors(plt, len(rx)), f_scale, "reaction magnitudes |F|", "N", xlabel)
    ax = axes[0, 1]
    if cf.normal_force:
        nf = {f"{k} N": (cf.normal_force[k], s.forces.normal_force[k]) for k in cf.normal_force}
        nf |= {f"{k} M / size": (cf.moment[k] / cmp.size, s.forces.moment[k] / cmp.size) for k in cf.moment}
        _overlay(ax, phi, nf, _colors(plt, len(nf)), f_scale, "prismatic: normal force N, moment M / size", "N",
                 xlabel)
    else:
        ax.set_axis_off()
        ax.text(0.5, 0.5, "no prismatic pairs", ha="center", va="center", transform=ax.transAxes)
    torque = {"Assur groups": (cf.balancing_torque, s.forces.balancing_torque),
              "power balance": (cf.power_balance_torque, s.forces.balancing_torque)}
    _overlay(axes[0, 2], phi, torque, _colors(plt, 2), f_scale * (1.0 if slides else cmp.size),
             "balancing force" if slides else "balancing torque", "N" if slides else "N·m", xlabel)
    j_peak = float(np.abs(cf.reduced.inertia).max()) or 1.0
    _overlay(axes[1, 0], phi, {"m(s)" if slides else "J(φ)": (cf.reduced.inertia, s.reduced_inertia)}, _colors(plt, 1),
             j_peak, "reduced mass" if slides else "reduced moment of inertia", "kg" if slides else "kg·m²", xlabel)
    for ax, prefix, route in ((axes[1, 1], "", "forward route"), (axes[1, 2], "inverse.", "inverse route")):
        names = [n for n in cmp.quantities if n.startswith(prefix)
                 and n[len(prefix):].startswith(("reactions.", "prismatic.", "balancing_torque", "reduced_inertia"))]
        if not names:
            ax.set_axis_off()
            ax.text(0.5, 0.5, f"no {route}", ha="center", va="center", transform=ax.transAxes)
            continue
        labels = [n[len(prefix):].replace("reactions.", "").replace(".force", "") for n in names]
        _errors(ax, phi, cmp, names, labels, _colors(plt, len(names)), f"forces, {route}", xlabel)
    fig.suptitle(f"{cmp.model}: forces — closed form (wide pale lines) vs MuJoCo (black dashed)")
    save_figure(fig, path, dpi=DPI)
    plt.close(fig)


def plot_model(cmp: Comparison, out: Path) -> list[str]:
    """Draw the model's figures into ``out``; returns their file names."""
    names = [f"{cmp.model}_paths.png", f"{cmp.model}_kinematics.png", f"{cmp.model}_forces.png"]
    for fn, name in zip((plot_paths, plot_kinematics, plot_forces), names):
        fn(cmp, out / name)
    return names


__all__ = ["plot_forces", "plot_kinematics", "plot_model", "plot_paths"]
