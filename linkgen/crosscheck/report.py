"""Validation report: Markdown with PNG plots overlaying closed form and MuJoCo over φ."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from linkgen.crosscheck.compare import Comparison


def plot_comparison(cmp: Comparison, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    s = cmp.run.samples
    phi = np.degrees(s.crank[0])
    mo = cmp.closed_form
    point = list(s.points)[-1]
    fig, axes = plt.subplots(2, 3, figsize=(14, 7), constrained_layout=True)
    for j, (q, unit) in enumerate((("position", "m"), ("velocity", "m/s"), ("acceleration", "m/s²"))):
        ax = axes[0, j]
        for c, comp in enumerate("xy"):
            ax.plot(phi, mo.points[point][j][:, c], lw=2.5, alpha=0.5, label=f"closed form {comp}")
            ax.plot(phi, s.points[point][j][:, c], "k--", lw=1, label=f"MuJoCo {comp}")
        ax.set(title=f"point {point}: {q}", xlabel="φ [deg]", ylabel=f"[{unit}]")
        ax.legend(fontsize=7)
        ax = axes[1, j]
        for p in s.points:
            diff = np.linalg.norm(s.points[p][j] - mo.points[p][j], axis=1)
            scale = cmp.quantities[f"points.{p}.{q}"].scale
            ax.semilogy(phi, np.maximum(diff / scale, 1e-18), lw=1, label=p)
        ax.axhline(cmp.quantities[f"points.{point}.{q}"].tolerance, color="r", ls=":", label="tolerance")
        ax.set(title=f"|MuJoCo − closed form| / scale: {q}", xlabel="φ [deg]")
        ax.legend(fontsize=7, ncol=2)
    fig.suptitle(f"{cmp.model}: closed form vs MuJoCo")
    fig.savefig(path, dpi=90)
    plt.close(fig)


def plot_forces(cmp: Comparison, path: Path) -> None:
    """Reaction components over φ, reaction hodographs, balancing torque, J(φ), force errors."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    s, cf = cmp.run.samples, cmp.closed_forces
    phi = np.degrees(s.crank[0])
    fig, axes = plt.subplots(2, 3, figsize=(15, 8), constrained_layout=True)
    colors = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for c, comp in enumerate("xy"):
        ax = axes[0, c]
        for i, (k, r) in enumerate(cf.reactions.items()):
            col = colors[i % len(colors)]
            ax.plot(phi, r[:, c], color=col, lw=2.5, alpha=0.5, label=k)
            ax.plot(phi, s.forces.reactions[k][:, c], color="k", ls="--", lw=0.8)
        ax.set(title=f"reaction {comp} component (closed form; MuJoCo dashed)", xlabel="φ [deg]", ylabel="[N]")
        ax.legend(fontsize=7, ncol=2)
    ax = axes[0, 2]
    for i, (k, r) in enumerate(cf.reactions.items()):
        ax.plot(r[:, 0], r[:, 1], color=colors[i % len(colors)], lw=1.5, label=k)
    ax.set(title="reaction hodographs", xlabel="Fx [N]", ylabel="Fy [N]", aspect="equal")
    ax.legend(fontsize=7, ncol=2)
    ax = axes[1, 0]
    ax.plot(phi, cf.balancing_torque, lw=2.5, alpha=0.5, label="closed form (Assur groups)")
    ax.plot(phi, cf.power_balance_torque, ":", lw=1.5, label="closed form (power balance)")
    ax.plot(phi, s.forces.balancing_torque, "k--", lw=0.8, label="MuJoCo")
    ax.set(title="balancing torque on the crank", xlabel="φ [deg]", ylabel="[N·m]")
    ax.legend(fontsize=7)
    ax = axes[1, 1]
    ax.plot(phi, cf.reduced.inertia, lw=2.5, alpha=0.5, label="closed form Σ m|v′|² + Iθ′²")
    ax.plot(phi, s.reduced_inertia, "k--", lw=0.8, label="MuJoCo q̇ᵀMq̇/ω² − armature")
    ax.set(title="reduced moment of inertia J(φ)", xlabel="φ [deg]", ylabel="[kg·m²]")
    ax.legend(fontsize=7)
    ax = axes[1, 2]
    for prefix, style in (("", "-"), ("inverse.", ":")):
        for i, k in enumerate(cf.reactions):
            q = cmp.quantities[f"{prefix}reactions.{k}.force"]
            src = s.forces if not prefix else cmp.inverse
            if src is None:
                continue
            diff = np.linalg.norm(src.reactions[k] - cf.reactions[k], axis=1) / q.scale
            ax.semilogy(phi, np.maximum(diff, 1e-18), style, color=colors[i % len(colors)], lw=1,
                        label=f"{k} ({'forward' if not prefix else 'inverse'})")
    ax.axhline(cmp.quantities["balancing_torque"].tolerance, color="r", ls=":", label="forward tolerance")
    ax.set(title="|MuJoCo − closed form| / peak reaction: reactions", xlabel="φ [deg]")
    ax.legend(fontsize=6, ncol=2)
    fig.suptitle(f"{cmp.model}: forces, closed form vs MuJoCo")
    fig.savefig(path, dpi=90)
    plt.close(fig)


def number(x, spec: str) -> str:
    """A figure of the JSON results, or "–" where a failed run left none (null)."""
    return "–" if x is None else format(x, spec)


def plot_model(cmp: Comparison, out: Path) -> list[str]:
    """Draw the model's figures into ``out``; returns their file names."""
    png, fpng = f"{cmp.model}.png", f"{cmp.model}_forces.png"
    plot_comparison(cmp, out / png)
    plot_forces(cmp, out / fpng)
    return [png, fpng]


def _worst(quantities: dict, kind: str) -> str:
    def group(k: str) -> str:
        if k.startswith("inverse."):
            return "inv"
        return "fwd" if k.startswith(("reactions.", "prismatic.", "balancing", "reduced")) else "kin"

    g = {k: q for k, q in quantities.items() if group(k) == kind}
    if not g:
        return "– | –"
    worst = max(g, key=lambda k: g[k]["relative_error"])
    return f"`{worst}` | {g[worst]['relative_error']:.2e}"


def write_index(results: list[dict], out: Path, wall: float, cores: float) -> Path:
    """The report's README.md from the per-model results (``CrossCheck.to_json`` plus file,
    figures and wall time)."""
    out.mkdir(parents=True, exist_ok=True)
    lines = ["# linkgen validation report", "",
             "Closed-form Assur-group kinematics and kinetostatics against MuJoCo at the same crank states "
             "(φ, ω, ε measured in the MuJoCo run). Each error is the largest over the compared samples, relative "
             "to the larger of the quantity's own peak and the mechanism's scale for its kind (size L, L·ω, "
             "L·(ω² + |ε|); 1 rad, ω, ω² + |ε|; the peak reaction F, F·L). The loop gap is relative to L. "
             "MuJoCo's settings are derived from each mechanism (see the settings columns).", "",
             f"{len(results)} model(s) in {wall:.1f} s wall, {cores:.2f} cores busy on average.", "",
             "| model | ok | worst kinematic quantity | rel. error | worst force (forward) | rel. error "
             "| worst force (inverse) | rel. error | loop gap / L | timestep [s] | loop τ [s] | steps | wall [s] |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        if "quantities" not in r:
            lines.append(f"| {r['model']} | **NO** | {r.get('error', 'run failed')} |  |  |  |  |  |  |  |  |  |  |")
            continue
        q, st = r["quantities"], r["settings"]
        cells = " | ".join(_worst(q, k) for k in ("kin", "fwd", "inv"))
        lines.append(f"| {r['model']} | {'yes' if r['ok'] else '**NO**'} | {cells} | {r['loop_gap']['relative']:.1e} | "
                     f"{st['timestep']:.3g} | {st['timeconst']:.3g} | {r['steps']} | {r.get('total_wall_s', r['wall_s']):.2f} |")
    for r in results:
        if "quantities" not in r:
            continue
        lines += ["", f"## {r['model']}", ""]
        for fig in r.get("figures", []):
            lines += [f"![{fig}]({fig})", ""]
        if r["diagnosis"]:
            lines += ["**Diagnosis**", ""]
            for d in r["diagnosis"]:
                rng = ", ".join(f"{a:.1f}°..{b:.1f}°" for a, b in d["ranges_deg"][:3])
                lines.append(f"- `{d['quantity']}` {number(d['relative_error'], '.2e')} (tolerance {d['tolerance']:g}) at {rng}: "
                             f"{d['cause']} — {d['detail']}")
            lines.append("")
        if r["left_out"]:
            lines.append("Left out of the comparison: " + "; ".join(
                f"{lo['samples']} samples after the {lo['reason']} at {lo['from_deg']:.1f}°" for lo in r["left_out"]))
            lines.append("")
        if r["practical_settings"]:
            lines += ["What MuJoCo's settings cost (errors relative to the size / peak reaction / peak reaction × size):",
                      "", "| settings | timestep [s] | integrator | loop τ [s] | loop gap / L | reactions | driving torque "
                      "| steps/rev | wall/rev [s] |", "|---|---|---|---|---|---|---|---|---|"]
            for p in r["practical_settings"]:
                if p["failure"]:
                    lines.append(f"| {p['label']} | {p['timestep']:.3g} | {p['integrator']} | {p['solref'][0]:.3g} | "
                                 f"failed: {p['failure']} |  |  |  |  |")
                    continue
                lines.append(f"| {p['label']} | {p['timestep']:.3g} | {p['integrator']} | {p['solref'][0]:.3g} | "
                             f"{number(p['loop_gap_relative'], '.1e')} | {number(p['reaction_error_relative'], '.1e')} | "
                             f"{number(p['driving_torque_error_relative'], '.1e')} | "
                             f"{number(p['steps_per_revolution'], '.0f')} | {number(p['wall_s_per_revolution'], '.3f')} |")
            lines.append("")
        lines += ["| quantity | max abs error | peak | scale | relative | tolerance | ok |", "|---|---|---|---|---|---|---|"]
        for k, q in r["quantities"].items():
            lines.append(f"| `{k}` | {q['max_abs_error']:.3e} | {q['peak']:.3e} | {q['scale']:.3e} | "
                         f"{q['relative_error']:.2e} | {q['tolerance']:g} | {'yes' if q['ok'] else '**NO**'} |")
    path = out / "README.md"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path
