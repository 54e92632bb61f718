"""Validation report: Markdown with the figures of ``figures`` and the tables of errors,
settings and practical-settings costs."""

from __future__ import annotations

from pathlib import Path

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
    full = d.stop - d.start >= 2 * np.pi - 1e-12
    plan = np.linspace(d.start, d.stop, PLAN_POSITIONS, endpoint=not full)
    names = [f"{mech.name}_drawing.png", f"{mech.name}_plan.png"]
    skeleton_figure(mech, asm.sketch_phi, out / names[0], paths=paths)
    plan_figure(mech, plan, out / names[1], paths=paths)
    return names


def _summary_lines(s: dict) -> list[str]:
    """The design summary (``DesignSummary.to_dict``) as Markdown lines."""
    import math

    deg = math.degrees
    lines = ["**Design summary** (at the drive's ω and ε)", ""]
    for name, o in s["outputs"].items():
        if o["travel"] is None:
            lines.append(f"- {o['kind']} `{name}`: turns fully round")
            continue
        travel = f"stroke {o['travel']:.6g} m" if o["kind"] == "slider" else f"swing {deg(o['travel']):.4g}°"
        limits = ", ".join(f"{x['kind']} at φ = {deg(x['phi']):.4g}°" for x in o["limits"]) or "extremes at the range's ends"
        ratio = f"; time ratio K = {o['time_ratio']:.4g}" if o["time_ratio"] is not None else ""
        lines.append(f"- {o['kind']} `{name}`: {travel}; limit positions {limits}{ratio}")
    for g, t in s["transmission"].items():
        lines.append(f"- least transmission angle of {g}: {deg(t['minimum']):.4g}° at φ = {deg(t['at']):.4g}°")
    if s["peak_balancing_torque"]:
        t = s["peak_balancing_torque"]
        lines.append(f"- peak balancing torque {t['value']:.4g} N·m at φ = {deg(t['at']):.4g}°")
        worst = sorted(s["peak_reactions"].items(), key=lambda kv: -kv[1]["value"])[:3]
        lines.append("- largest reactions: " + ", ".join(f"{k} {v['value']:.4g} N at {deg(v['at']):.4g}°" for k, v in worst))
    elif s["forces_note"]:
        lines.append(f"- {s['forces_note']}")
    return lines + [""]


def number(x, spec: str) -> str:
    """A figure of the JSON results, or "–" where a failed run left none (null)."""
    return "–" if x is None else format(x, spec)


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
    """The report's README.md from the per-model entries of ``linkgen validate --json`` (each
    validation result's ``to_dict()`` plus file, figures, wall time and line)."""
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
    for r in results:
        if "spatial" in r:
            sp = r["spatial"]
            kin = {k: v for k, v in sp["errors"].items() if k.startswith(("points.", "links."))}
            inv = {k: v for k, v in sp["errors"].items() if k.startswith("inverse.")}
            frc = {k: v for k, v in sp["errors"].items() if k not in kin and k not in inv}
            wk, wf, wi = (max(g, key=lambda k, g=g: g[k]["error"]) for g in (kin, frc, inv))
            lines.append(f"| {r['model']} | {'yes' if r['ok'] else '**NO**'} | {sp['kind']}: `{wk}` | "
                         f"{kin[wk]['error']:.2e} | `{wf}` | {frc[wf]['error']:.2e} | `{wi}` | {inv[wi]['error']:.2e} | "
                         f"{sp['loop_gap']:.1e} | "
                         f"{sp['settings']['timestep']:.3g} | {sp['settings']['timeconst']:.3g} | {sp['steps']} | "
                         f"{r['total_wall_s']:.2f} |")
            continue
        if "cam" in r:
            e = r["cam"]["errors_relative"]
            lines.append(f"| {r['model']} | {'yes' if r['ok'] else '**NO**'} | cam: `displacement` | "
                         f"{e['displacement']:.2e} | cam: `contact_force` (5° means) | {e['contact_force']:.2e} |  |  |  | "
                         f"{r['cam']['timestep']:.3g} |  | {r['cam']['steps']} | {r['total_wall_s']:.2f} |")
            continue
        if "cam_linkage" in r:
            e = r["cam_linkage"]["errors"]
            kin = max((k for k in e if not k.endswith(("contact_force", "torque"))), key=lambda k: e[k]["error"])
            frc = max((k for k in e if k.endswith(("contact_force", "torque"))), key=lambda k: e[k]["error"])
            lines.append(f"| {r['model']} | {'yes' if r['ok'] else '**NO**'} | cam contact: `{kin}` | "
                         f"{e[kin]['error']:.2e} | `{frc}` (5° means) | {e[frc]['error']:.2e} |  |  |  | "
                         f"{r['cam_linkage']['timestep']:.3g} |  | {r['cam_linkage']['steps']} | "
                         f"{r['total_wall_s']:.2f} |")
            continue
        if "quantities" not in r:
            why = r.get("error") or "; ".join(d["cause"] for d in r.get("diagnosis", [])) or "run failed"
            lines.append(f"| {r['model']} | **NO** | {why} |  |  |  |  |  |  |  |  |  |  |")
            continue
        q, st = r["quantities"], r["settings"]
        cells = " | ".join(_worst(q, k) for k in ("kin", "fwd", "inv"))
        lines.append(f"| {r['model']} | {'yes' if r['ok'] else '**NO**'} | {cells} | {r['loop_gap']['relative']:.1e} | "
                     f"{st['timestep']:.3g} | {st['timeconst']:.3g} | {r['steps']} | {r['total_wall_s']:.2f} |")
    for r in results:
        if "spatial" in r:
            lines += _spatial_section(r)
            continue
        if "cam" in r:
            lines += _cam_section(r)
            continue
        if "cam_linkage" in r:
            lines += ["", f"## {r['model']} (a cam on the crank)", ""] + [f"![{f}]({f})\n" for f in r.get("figures", [])]
            lines += ["| quantity | relative error | tolerance | ok |", "|---|---|---|---|"]
            lines += [f"| `{k}` | {e['error']:.2e} | {e['tolerance']:g} | {'yes' if e['error'] <= e['tolerance'] else '**NO**'} |"
                      for k, e in r["cam_linkage"]["errors"].items()]
            continue
        if "quantities" not in r:  # no run compared anything: the section says why
            if r.get("diagnosis"):
                lines += ["", f"## {r['model']}", ""] + _diagnosis_lines(r["diagnosis"])
            continue
        lines += ["", f"## {r['model']}", ""]
        for fig in r.get("figures", []):
            lines += [f"![{fig}]({fig})", ""]
        if r.get("summary"):
            lines += _summary_lines(r["summary"])
        lines += _diagnosis_lines(r["diagnosis"])
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
    atomic_write_text(path, "\n".join(lines) + "\n")
    return path


def _diagnosis_lines(diagnosis: list[dict]) -> list[str]:
    if not diagnosis:
        return []
    lines = ["**Diagnosis**", ""]
    for d in diagnosis:
        if d["relative_error"] is None and not d["ranges_deg"]:  # no run compared anything: why, alone
            lines.append(f"- {d['cause']}: {d['detail']}")
            continue
        rng = ", ".join(f"{a:.1f}°..{b:.1f}°" for a, b in d["ranges_deg"][:3])
        lines.append(f"- `{d['quantity']}` {number(d['relative_error'], '.2e')} (tolerance {d['tolerance']:g}) at {rng}: "
                     f"{d['cause']} — {d['detail']}")
    return lines + [""]


def _cam_section(r: dict) -> list[str]:
    """A stand-alone cam's section: its drawing, the follower's motion and the contact, closed
    form against MuJoCo, the diagnosis and every compared quantity."""
    c = r["cam"]
    lines = ["", f"## {r['model']} (a cam)", ""]
    for fig in r.get("figures", []):
        lines += [f"![{fig}]({fig})", ""]
    lines += [f"MuJoCo: a {c['profile_points']}-vertex profile, timestep {c['timestep']:.3g} s ({c.get('integrator', '')}), "
              f"{c['steps']} steps; the contact force and cam torque compared as {360 / c['windows']:g}° means.", ""]
    lines += _diagnosis_lines(r.get("diagnosis", []))
    lines += ["| quantity | relative error | tolerance | ok |", "|---|---|---|---|"]
    for k, tol in c["tolerances"].items():
        e = c["errors_relative"][k]
        lines.append(f"| `{k}` | {e:.2e} | {tol:g} | {'yes' if e <= tol else '**NO**'} |")
    for k in ("contact_force", "cam_torque"):
        lines.append(f"| `{k}` (instantaneous, not held to a tolerance) | {c['errors_relative'][k + '_instantaneous']:.2e} "
                     f"|  |  |")
    return lines


def _spatial_section(r: dict) -> list[str]:
    """A spatial model's section: its figures and every compared quantity."""
    sp = r["spatial"]
    lines = ["", f"## {r['model']} (spatial {sp['kind']})", ""]
    for fig in r.get("figures", []):
        lines += [f"![{fig}]({fig})", ""]
    if sp["note"]:
        lines += [sp["note"][:1].upper() + sp["note"][1:] + ".", ""]
    lines += ["| quantity | relative error | tolerance | ok |", "|---|---|---|---|"]
    for k, e in sp["errors"].items():
        lines.append(f"| `{k}` | {e['error']:.2e} | {e['tolerance']:g} | {'yes' if e['error'] <= e['tolerance'] else '**NO**'} |")
    lines.append(f"| loop gap / L | {sp['loop_gap']:.2e} | {sp['loop_gap_tolerance']:g} | "
                 f"{'yes' if sp['loop_gap'] <= sp['loop_gap_tolerance'] else '**NO**'} |")
    return lines


__all__ = ["PLAN_POSITIONS", "number", "plot_mechanism", "plot_model", "write_index"]
