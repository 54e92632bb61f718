"""Validation report: Markdown with the figures of ``figures`` and the tables of errors,
settings and practical-settings costs."""

from __future__ import annotations

from pathlib import Path

from linkgen.model.turn import full_turn
from linkgen.report.figures import plot_model


# Positions in the report's position plan of each model.
PLAN_POSITIONS = 12


def plot_mechanism(asm, out: Path) -> list[str]:
    """The mechanism itself, first in its report section: its skeleton at the sketch's crank
    angle and a position plan of PLAN_POSITIONS positions over the drive's range, into ``out``;
    returns the file names."""
    import numpy as np

    from linkgen.draw.plan import plan_figure, skeleton_figure
    from linkgen.families.planar.positions import drive_angles, positions

    mech = asm.mechanism
    paths = positions(mech, drive_angles(mech))
    d = mech.drive
    full = full_turn(mech)
    plan = np.linspace(d.start, d.stop, PLAN_POSITIONS, endpoint=not full)
    names = [f"{mech.name}_drawing.png", f"{mech.name}_plan.png"]
    skeleton_figure(mech, asm.sketch_phi, out / names[0], paths=paths)
    plan_figure(mech, plan, out / names[1], paths=paths)
    return names


def number(x, spec: str) -> str:
    """A figure of the JSON results, or "–" where a failed run left none (null)."""
    return "–" if x is None else format(x, spec)


def write_index(results: list[dict], out: Path, wall: float, cores: float, parts) -> Path:
    """The report's README.md from the per-model entries of ``linkgen validate --json`` (each
    validation result's ``to_dict()`` plus file, family, figures, wall time and line).
    ``parts(entry)`` gives the entry's (row, section) writers (``report.sections``): its family's
    table row and its section of Markdown lines; the report itself knows no family."""
    from linkgen.outputs import atomic_write_text, output_folder

    output_folder(out)
    lines = ["# linkgen validation report", "",
             "Closed-form Assur-group kinematics and kinetostatics against MuJoCo at the same crank states "
             "(φ, ω, ε measured in the MuJoCo run). Each error is the largest over the compared samples, relative "
             "to the larger of the quantity's own peak and the mechanism's scale for its kind (size L, L·ω, "
             "L·(ω² + |ε|); 1 rad, ω, ω² + |ε|; the peak reaction F, F·L). The loop gap is relative to L. "
             "MuJoCo's settings are derived from each mechanism (see the settings columns).", "",
             f"{len(results)} model(s) in {wall:.1f} s wall, {cores:.2f} cores busy on average. A model's wall time "
             "is the whole of its validation (reading, closed form, MuJoCo runs, figures), the figure `validate` "
             "prints.", "",
             "| model | ok | worst kinematic quantity | rel. error | worst force (forward) | rel. error "
             "| worst force (inverse) | rel. error | loop gap / L | timestep [s] | loop τ [s] | steps | wall [s] |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    writers = [parts(r) for r in results]
    lines += [row(r) for r, (row, _) in zip(results, writers)]
    for r, (_, section) in zip(results, writers):
        lines += section(r)
    path = out / "README.md"
    atomic_write_text(path, "\n".join(lines) + "\n")
    return path


__all__ = ["PLAN_POSITIONS", "number", "plot_mechanism", "plot_model", "write_index"]
