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


def write_report(comparisons: list[Comparison], timings: dict[str, float], out: Path) -> Path:
    out.mkdir(parents=True, exist_ok=True)
    lines = ["# linkgen validation report", "",
             "Closed-form Assur-group kinematics against MuJoCo at the same crank states "
             "(φ, ω, ε measured in the MuJoCo run). Errors are the largest over the samples after warm-up, "
             "relative to the quantity's peak; the constraint violation is in metres.", "",
             "| model | ok | worst quantity | relative error | constraint violation [m] | MuJoCo run [s] |",
             "|---|---|---|---|---|---|"]
    for c in comparisons:
        kin = {k: q for k, q in c.quantities.items() if k != "constraint_violation"}
        worst = max(kin, key=lambda k: kin[k].relative_error)
        lines.append(f"| {c.model} | {'yes' if c.ok else '**NO**'} | `{worst}` | {kin[worst].relative_error:.2e} | "
                     f"{c.quantities['constraint_violation'].max_abs_error:.2e} | {timings.get(c.model, float('nan')):.2f} |")
    for c in comparisons:
        png = f"{c.model}.png"
        plot_comparison(c, out / png)
        lines += ["", f"## {c.model}", "", f"![{c.model}]({png})", "",
                  "| quantity | max abs error | peak | relative | tolerance | ok |", "|---|---|---|---|---|---|"]
        for k, q in c.quantities.items():
            lines.append(f"| `{k}` | {q.max_abs_error:.3e} | {q.peak:.3e} | {q.relative_error:.2e} | "
                         f"{q.tolerance:g} | {'yes' if q.ok else '**NO**'} |")
    path = out / "README.md"
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")
    return path
