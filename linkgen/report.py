"""Validation report: Markdown with PNG plots overlaying closed form and MuJoCo over φ."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .compare import Comparison


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
            peak = cmp.quantities[f"points.{p}.{q}"].peak
            ax.semilogy(phi, np.maximum(diff / peak, 1e-18), lw=1, label=p)
        ax.axhline(cmp.quantities[f"points.{point}.{q}"].tolerance, color="r", ls=":", label="tolerance")
        ax.set(title=f"|MuJoCo − closed form| / peak: {q}", xlabel="φ [deg]")
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
            diff = np.linalg.norm(src.reactions[k] - cf.reactions[k], axis=1) / q.peak
            ax.semilogy(phi, np.maximum(diff, 1e-18), style, color=colors[i % len(colors)], lw=1,
                        label=f"{k} ({'forward' if not prefix else 'inverse'})")
    ax.axhline(cmp.quantities["balancing_torque"].tolerance, color="r", ls=":", label="forward tolerance")
    ax.set(title="|MuJoCo − closed form| / peak: reactions", xlabel="φ [deg]")
    ax.legend(fontsize=6, ncol=2)
    fig.suptitle(f"{cmp.model}: forces, closed form vs MuJoCo")
    fig.savefig(path, dpi=90)
    plt.close(fig)


def write_report(comparisons: list[Comparison], timings: dict[str, float], out: Path) -> Path:
    out.mkdir(parents=True, exist_ok=True)
    lines = ["# linkgen validation report", "",
             "Closed-form Assur-group kinematics against MuJoCo at the same crank states "
             "(φ, ω, ε measured in the MuJoCo run). Errors are the largest over the samples after warm-up, "
             "relative to the quantity's peak; the constraint violation is in metres.", "",
             "Forces: the closed-form kinetostatics against MuJoCo's forward run (cfrc_int, efc_force) and "
             "against inverse dynamics (mj_inverse at the closed-form state, loop forces by projection).", "",
             "| model | ok | worst kinematic quantity | rel. error | worst force (forward) | rel. error "
             "| worst force (inverse) | rel. error | constraint violation [m] | MuJoCo run [s] |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for c in comparisons:
        groups = {"kin": {}, "fwd": {}, "inv": {}}
        for k, q in c.quantities.items():
            if k == "constraint_violation":
                continue
            kind = "inv" if k.startswith("inverse.") else (
                "fwd" if k.startswith(("reactions.", "prismatic.", "balancing", "reduced")) else "kin")
            groups[kind][k] = q
        cells = []
        for kind in ("kin", "fwd", "inv"):
            g = groups[kind]
            worst = max(g, key=lambda k: g[k].relative_error)
            cells.append(f"`{worst}` | {g[worst].relative_error:.2e}")
        lines.append(f"| {c.model} | {'yes' if c.ok else '**NO**'} | {' | '.join(cells)} | "
                     f"{c.quantities['constraint_violation'].max_abs_error:.2e} | {timings.get(c.model, float('nan')):.2f} |")
    for c in comparisons:
        png, fpng = f"{c.model}.png", f"{c.model}_forces.png"
        plot_comparison(c, out / png)
        plot_forces(c, out / fpng)
        lines += ["", f"## {c.model}", "", f"![{c.model}]({png})", "", f"![{c.model} forces]({fpng})", "",
                  "| quantity | max abs error | peak | relative | tolerance | ok |", "|---|---|---|---|---|---|"]
        for k, q in c.quantities.items():
            lines.append(f"| `{k}` | {q.max_abs_error:.3e} | {q.peak:.3e} | {q.relative_error:.2e} | "
                         f"{q.tolerance:g} | {'yes' if q.ok else '**NO**'} |")
    path = out / "README.md"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path
