"""The referee's report (``linkgen referee ... -o DIR``): ``README.md`` (the verdict per column,
its diagnosis), one PNG per column (the user's curve over linkgen's and MuJoCo's, and the
difference relative to the column's scale) and ``verdict.json`` (what ``--json`` prints)."""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np

from linkgen.outputs import atomic_write_text, output_folder, save_figure
from linkgen.referee.verdict import ColumnVerdict, Verdict

DPI = 90
# Relative differences under this are drawn at it on the log axis (exact zeros included).
FLOOR = 1e-18


def figure_name(c: ColumnVerdict) -> str:
    """A file name for a column: its linkgen header with the unit, made safe for any file system."""
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", c.key).strip("_") + ".png"


def write_report(v: Verdict, out: str | Path) -> Path:
    """Write the report into the folder ``out`` (created); returns README.md's path."""
    folder = output_folder(out)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(6.4, 4.8), sharex=True)
    for c in v.columns:
        _draw(fig, top, bottom, c)
        save_figure(fig, folder / figure_name(c), dpi=DPI)
    plt.close(fig)
    atomic_write_text(folder / "verdict.json", json.dumps(v.to_dict(), indent=2, allow_nan=False) + "\n")
    readme = folder / "README.md"
    atomic_write_text(readme, markdown(v))
    return readme


def _draw(fig, top, bottom, c: ColumnVerdict) -> None:
    top.clear()
    bottom.clear()
    phi = np.degrees(c.curves["phi"])
    order = np.argsort(phi, kind="stable")
    for name, style in (("closed_form", "-"), ("mujoco_forward", ":"), ("user", "--")):
        if name in c.curves:
            label = "yours" if name == "user" else name.replace("_", " ")
            top.plot(phi[order], np.asarray(c.curves[name])[order], style, lw=1.2, label=label)
    top.set_ylabel(c.key, fontsize=8)
    top.legend(fontsize=7, frameon=False)
    d = np.abs(np.asarray(c.curves["user"]) - np.asarray(c.curves["closed_form"])) / c.scale
    if c.key.endswith("[rad]") and c.key.split(" ")[0].endswith("angle"):
        d = np.abs((np.asarray(c.curves["user"]) - c.curves["closed_form"] + math.pi) % (2 * math.pi) - math.pi) / c.scale
    bottom.semilogy(phi[order], np.maximum(np.nan_to_num(d[order], nan=FLOOR), FLOOR), lw=1.0)
    bottom.axhline(c.routes["closed_form"].tolerance, color="grey", lw=0.8, ls="--")
    bottom.set_ylabel("|yours − linkgen| / scale", fontsize=8)
    bottom.set_xlabel("crank angle φ [°]")
    kind = f" ({c.diagnosis.kind})" if c.diagnosis else ""
    top.set_title(f"{c.header}: agrees with {c.agrees}{kind}", fontsize=9)
    fig.tight_layout()


def markdown(v: Verdict) -> str:
    """The report's page."""
    d = v.to_dict()
    lines = [f"# Referee: {v.source} against {v.model}", "",
             f"{len(v.columns)} columns at {v.samples} crank angles, ω = {v.omega:g} rad/s, ε = {v.epsilon:g} rad/s²; "
             f"errors relative to each column's scale (the largest closed-form magnitude in its unit), tolerance "
             f"{v.tolerance:g}" + ("; MuJoCo's forward and inverse routes compared too" if v.mujoco else "") + ".", "",
             "| column | error vs closed form | worst at φ | " + ("MuJoCo forward | MuJoCo inverse | " if v.mujoco else "")
             + "agrees with | diagnosis |",
             "|---|---|---|" + ("---|---|" if v.mujoco else "") + "---|---|"]
    for c, cd in zip(v.columns, d["columns"]):
        cf = c.routes["closed_form"]
        mj = ""
        if v.mujoco:
            mj = " | ".join(f"{c.routes[r].error:.2e}" if r in c.routes else "—"
                            for r in ("mujoco_forward", "mujoco_inverse")) + " | "
        diag = c.diagnosis.text if c.diagnosis else ""
        lines.append(f"| [`{c.header}`]({figure_name(c)}) | {cf.error:.2e} | {math.degrees(cf.at_phi):.4g}° | {mj}"
                     f"{c.agrees} | {diag.replace('|', '/')} |")
    lines += ["", "Each column's figure: its curves (yours dashed) and the difference relative to the scale, with the "
              "tolerance dashed.", "", "`verdict.json` holds the same as `linkgen referee --json`.", ""]
    return "\n".join(lines)
