"""The report's rows and sections, one writer per kind of validation result (the family
adapters, ``pipeline``, say which an entry takes): a linkage's comparison (``CrossCheck``, with
a machine's joined), a cam on a linkage's crank, a stand-alone cam, a spatial four-bar, and a
file that could not be validated. Each takes the entry of ``linkgen validate --json``."""

from __future__ import annotations

import math

from linkgen.report.report import number


def _ok(r: dict) -> str:
    if r["ok"]:
        return "yes"
    return "**NO** (explained, as predicted)" if r.get("status") == "explained failure" else "**NO**"


def prediction_lines(r: dict) -> list[str]:
    """What validate predicted before the run (``crosscheck.prediction``), the status it gave
    the run, measured over predicted, and, where a limit bound, what MuJoCo reached there."""
    p = r.get("prediction") or {}
    if "text" not in p:
        return [f"No prediction before the run: {p['unavailable']}.", ""] if p.get("unavailable") else []
    line = f"**Prediction before the run** (status: {r.get('status', 'ok' if r.get('ok') else 'failed')}): {p['text']}."
    measured = p.get("measured")
    if measured:
        line += " Measured: " + ", ".join(f"{k} {v:.2g}" for k, v in measured.items()) + "."
    elif "measured" in p:
        line += " The run stopped before any comparison."
    ratios = {k: v for k, v in (p.get("measured_over_predicted") or {}).items() if v is not None}
    if ratios:  # the figures the verdict holds the prediction to
        line += " Measured over predicted: " + ", ".join(f"{k} {v:.2f}" for k, v in ratios.items()) + "."
    best = r.get("best_achievable")
    if best and p.get("binding") != "none":
        line += (f" Best achievable at the step budget ({best['settings']['timestep']:.3g} s steps, loop τ "
                 f"{best['settings']['timeconst']:.3g} s): worst `{best['worst']}` {best['worst_relative_error']:.2e} "
                 f"(tolerance {best['worst_tolerance']:g}), loop gap {best['loop_gap_relative']:.1e} of the size.")
    return [line, ""]


def _figures(r: dict) -> list[str]:
    out = []
    for fig in r.get("figures", []):
        out += [f"![{fig}]({fig})", ""]
    return out


def error_row(r: dict) -> str:
    """A file that could not be validated, or whose runs all failed: why."""
    why = r.get("error") or "; ".join(d["cause"] for d in r.get("diagnosis", [])) or "run failed"
    return f"| {r['model']} | {_ok(r) if 'ok' in r else '**NO**'} | {why} |  |  |  |  |  |  |  |  |  |  |"


def error_section(r: dict) -> list[str]:
    """No run compared anything: the section says why (nothing for a file that did not load)."""
    return ["", f"## {r['model']}", ""] + prediction_lines(r) + diagnosis_lines(r["diagnosis"]) if r.get("diagnosis") else []


def _worst(quantities: dict, kind: str) -> str:
    def group(k: str) -> str:
        if k.startswith("inverse."):
            return "inv"
        return "fwd" if k.startswith(("reactions.", "prismatic.", "balancing", "reduced", "friction.")) else "kin"

    g = {k: q for k, q in quantities.items() if group(k) == kind}
    if not g:
        return "– | –"
    worst = max(g, key=lambda k: g[k]["relative_error"])
    return f"`{worst}` | {g[worst]['relative_error']:.2e}"


def linkage_row(r: dict) -> str:
    """A linkage's comparison (``CrossCheck.to_dict``): the worst kinematic, forward and inverse
    quantities, the loop gap, the settings, steps and wall time."""
    if not r.get("quantities"):
        return error_row(r)
    q, st = r["quantities"], r["settings"]
    cells = " | ".join(_worst(q, k) for k in ("kin", "fwd", "inv"))
    return (f"| {r['model']} | {_ok(r)} | {cells} | {r['loop_gap']['relative']:.1e} | "
            f"{st['timestep']:.3g} | {st['timeconst']:.3g} | {r['steps']} | {r['total_wall_s']:.2f} |")


def linkage_section(r: dict) -> list[str]:
    """A linkage's section: its figures, the design summary, the diagnosis, what was left out,
    what MuJoCo's usual settings cost and every compared quantity."""
    if not r.get("quantities"):  # no run compared anything: the section says why
        return error_section(r)
    lines = ["", f"## {r['model']}", ""] + _figures(r)
    if r.get("summary"):
        lines += _summary_lines(r["summary"])
    lines += prediction_lines(r)
    lines += diagnosis_lines(r["diagnosis"])
    if r["left_out"]:
        lines.append("Left out of the comparison: " + "; ".join(
            f"{lo['samples']} samples after the {lo['reason']} at {math.degrees(lo['phi_from']):.1f}°" for lo in r["left_out"]))
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
    return lines


def cam_linkage_row(r: dict) -> str:
    """A cam on a linkage's crank (``CamLinkageCheck.to_dict``): the worst motion and force."""
    e = r["quantities"]
    kin = max((k for k in e if not k.endswith(("normal_force", "torque"))), key=lambda k: e[k]["relative_error"])
    frc = max((k for k in e if k.endswith(("normal_force", "torque"))), key=lambda k: e[k]["relative_error"])
    return (f"| {r['model']} | {_ok(r)} | cam contact: `{kin}` | {e[kin]['relative_error']:.2e} | `{frc}` (5° means) | "
            f"{e[frc]['relative_error']:.2e} |  |  |  | {r['settings']['timestep']:.3g} |  | {r['steps']} | "
            f"{r['total_wall_s']:.2f} |")


def cam_linkage_section(r: dict) -> list[str]:
    """A cam on a linkage's crank: its figures and every compared quantity."""
    lines = ["", f"## {r['model']} (a cam on the crank)", ""] + [f"![{f}]({f})\n" for f in r.get("figures", [])]
    return lines + _quantity_lines(r["quantities"])


def _quantity_lines(quantities: dict) -> list[str]:
    """The table of compared quantities every family's result has (``mujoco.result_shape``)."""
    return ["| quantity | relative error | tolerance | ok |", "|---|---|---|---|"] + [
        f"| `{k}` | {e['relative_error']:.2e} | {e['tolerance']:g} | {'yes' if e['ok'] else '**NO**'} |"
        for k, e in quantities.items()]


def cam_row(r: dict) -> str:
    """A stand-alone cam (``CamCheck.to_dict``): the follower's displacement and the contact force."""
    (moved, e_moved), (pushed, e_pushed) = ((k, q["relative_error"]) for k, q in list(r["quantities"].items())[:2])
    return (f"| {r['model']} | {_ok(r)} | cam: `{moved}` | {e_moved:.2e} | cam: `{pushed}` (5° means) | "
            f"{e_pushed:.2e} |  |  |  | {r['settings']['timestep']:.3g} |  | {r['steps']} | {r['total_wall_s']:.2f} |")


def spatial_row(r: dict) -> str:
    """A spatial four-bar (``SpatialCheck.to_dict``): the worst kinematic, forward and inverse
    quantities, the loop gap, the settings, steps and wall time."""
    q = r["quantities"]
    kin = {k: v for k, v in q.items() if k.startswith(("points.", "links."))}
    inv = {k: v for k, v in q.items() if k.startswith("inverse.")}
    frc = {k: v for k, v in q.items() if k not in kin and k not in inv}
    wk, wf, wi = (max(g, key=lambda k, g=g: g[k]["relative_error"]) for g in (kin, frc, inv))
    return (f"| {r['model']} | {_ok(r)} | {r['kind']}: `{wk}` | {kin[wk]['relative_error']:.2e} | `{wf}` | "
            f"{frc[wf]['relative_error']:.2e} | `{wi}` | {inv[wi]['relative_error']:.2e} | "
            f"{r['loop_gap']['relative']:.1e} | {r['settings']['timestep']:.3g} | {r['settings']['timeconst']:.3g} | "
            f"{r['steps']} | {r['total_wall_s']:.2f} |")


def _summary_lines(s: dict) -> list[str]:
    """A planar design summary (``DesignSummary.to_dict``) as Markdown lines."""
    import math

    deg = math.degrees
    lines = ["**Design summary** (at the drive's ω and ε)", ""]
    stroke = bool(s.get("stroke"))  # a prismatic drive: strokes [m], a balancing force [N]

    def at(x: float) -> str:
        return f"s = {x:.4g} m" if stroke else f"φ = {deg(x):.4g}°"

    def short(x: float) -> str:
        return f"s = {x:.4g} m" if stroke else f"{deg(x):.4g}°"
    for key, o in s["outputs"].items():
        name = key.removesuffix(f" ({o['kind']})")
        if o["travel"] is None:
            lines.append(f"- {o['kind']} `{name}`: turns fully round")
            continue
        travel = f"stroke {o['travel']:.6g} m" if o["kind"] == "slider" else f"swing {deg(o['travel']):.4g}°"
        limits = ", ".join(f"{x['kind']} at {at(x['phi'])}" for x in o["limits"]) or "extremes at the range's ends"
        ratio = f"; time ratio K = {o['time_ratio']:.4g}" if o["time_ratio"] is not None else ""
        lines.append(f"- {o['kind']} `{name}`: {travel}; limit positions {limits}{ratio}")
    for g, t in s.get("min_transmission_angle", {}).items():
        lines.append(f"- least transmission angle of {g}: {deg(t['value']):.4g}° at {at(t['phi'])}")
    if s["peak_balancing_torque"]:
        t = s["peak_balancing_torque"]
        what = "balancing force {:.4g} N" if s.get("stroke") else "balancing torque {:.4g} N·m"
        lines.append(f"- peak {what.format(t['value'])} at {at(t['phi'])}")
        worst = sorted(s["peak_reactions"].items(), key=lambda kv: -kv[1]["value"])[:3]
        lines.append("- largest reactions: " + ", ".join(f"{k} {v['value']:.4g} N at {short(v['phi'])}"
                                                         for k, v in worst))
    elif s["forces_note"]:
        lines.append(f"- {s['forces_note']}")
    springs = s.get("peak_spring_forces") or {}
    if springs:
        lines.append("- peak spring forces: " + ", ".join(
            f"{k} {v['value']:.4g} {'N·m' if k.startswith('torsion') else 'N'} at {short(v['phi'])}"
            for k, v in springs.items()))
    if s.get("peak_friction_power"):
        p = s["peak_friction_power"]
        lines.append(f"- power lost to friction in the pairs: peak {p['value']:.4g} W at {short(p['phi'])}, mean "
                     f"{s['mean_friction_power']:.4g} W")
    return lines + [""]


def diagnosis_lines(diagnosis: list[dict]) -> list[str]:
    if not diagnosis:
        return []
    from linkgen.crosscheck.diagnose import finding_line

    return ["**Diagnosis**", ""] + [f"- {finding_line(d, '`{}` ')}" for d in diagnosis] + [""]


def cam_section(r: dict) -> list[str]:
    """A stand-alone cam's section: its drawing, the follower's motion and the contact, closed
    form against MuJoCo, the diagnosis and every compared quantity."""
    lines = ["", f"## {r['model']} (a cam)", ""]
    for fig in r.get("figures", []):
        lines += [f"![{fig}]({fig})", ""]
    lines += [f"MuJoCo: a {r['profile_points']}-vertex profile, timestep {r['settings']['timestep']:.3g} s "
              f"({r['settings']['integrator']}), {r['steps']} steps; the contact force and cam torque compared as "
              f"{360 / r['windows']:g}° means.", ""]
    lines += diagnosis_lines(r.get("diagnosis", []))
    lines += _quantity_lines(r["quantities"])
    for k, e in r["instantaneous"].items():
        lines.append(f"| `{k}` (instantaneous, not held to a tolerance) | {e:.2e} |  |  |")
    return lines


def spatial_section(r: dict) -> list[str]:
    """A spatial model's section: its figures and every compared quantity."""
    lines = ["", f"## {r['model']} (spatial {r['kind']})", ""]
    for fig in r.get("figures", []):
        lines += [f"![{fig}]({fig})", ""]
    if r["note"]:
        lines += [r["note"][:1].upper() + r["note"][1:] + ".", ""]
    gap = r["loop_gap"]
    return lines + _quantity_lines(r["quantities"]) + [
        f"| loop gap / L | {gap['relative']:.2e} | {gap['tolerance']:g} | {'yes' if gap['ok'] else '**NO**'} |"]


# (row, section) of each kind of entry, for the family adapters to choose from.
LINKAGE = (linkage_row, linkage_section)
CAM_LINKAGE = (cam_linkage_row, cam_linkage_section)
CAM = (cam_row, cam_section)
SPATIAL = (spatial_row, spatial_section)
ERROR = (error_row, error_section)

__all__ = ["CAM", "CAM_LINKAGE", "ERROR", "LINKAGE", "SPATIAL", "diagnosis_lines", "number"]
