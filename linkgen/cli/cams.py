"""Cam mechanisms in MuJoCo from the command line: ``validate`` of a stand-alone cam and of a
linkage whose crank carries a cam (``analyze`` and ``profile`` go through the registry:
``cli.closed_form``)."""

from __future__ import annotations

import time
from pathlib import Path


from linkgen.families.cam.summary import cam_summary
from linkgen.errors import LinkgenError


def check_cam_linkage_file(path: Path, asm, report: Path | None, t0: float, progress=None,
                           max_steps: int | None = None) -> dict:
    """A linkage whose crank carries a cam (``mujoco.cam_linkage``): contact in MuJoCo, the cam's tolerances."""
    from linkgen.cli.files import message_for
    from linkgen.mujoco.cam_linkage import check_cam_linkage

    try:
        r = check_cam_linkage(asm, progress, **({} if max_steps is None else {"max_steps": max_steps}))
    except LinkgenError as exc:
        return {"model": path.stem, "file": str(path), "ok": False, "error": message_for(path, exc)}
    out = {"file": str(path), "ok": r.ok, "model": r.model, "cam_linkage": r.to_json(),
           "diagnosis": [f.to_json() for f in cam_linkage_findings(r)]}
    if report is not None:
        from linkgen.report.report import plot_mechanism

        from linkgen.outputs import output_folder

        output_folder(report)
        out["figures"] = plot_mechanism(asm, report)
    out["total_wall_s"] = time.perf_counter() - t0
    out["line"] = r.summary(wall_text(out["total_wall_s"]))
    return out


def cam_linkage_findings(r) -> list:
    """The diagnosis of a cam linkage's MuJoCo check (``CamLinkageCheck``): every quantity over its
    tolerance with where and why, judged on its cam's contact (the first cam's for the points and
    the balancing torque)."""
    from linkgen.crosscheck.diagnose_cam import ContactTrace, findings

    out = []
    for name, (err, tol) in r.errors.items():
        if err <= tol:
            continue
        cam = name.split(".", 1)[0] if name.split(".", 1)[0] in r.contacts else next(iter(r.contacts))
        out += findings(ContactTrace(**r.contacts[cam]), {name: (r.curves[name] > tol, err, tol)})
    return sorted(out, key=lambda f: -f.relative_error / f.tolerance)


def check_cam_file(path: Path, t0: float, report: Path | None = None, progress=None,
                   max_steps: int | None = None) -> dict:
    """A cam mechanism in MuJoCo against its closed form (``mujoco.cam.compare_cam``), with the
    diagnosis of what missed (``crosscheck.diagnose_cam``) and, for a ``report``, its figures;
    ``progress``: the MuJoCo run's (``mujoco.cam.run_cam``)."""
    from linkgen.families.cam.description import load_cam
    from linkgen.cli.files import message_for
    from linkgen.crosscheck.diagnose_cam import diagnose_cam
    from linkgen.mujoco.cam import CAM_TOLERANCES, compare_cam, run_cam

    try:
        cm = load_cam(path)
        run = run_cam(cm, progress=progress, max_steps=max_steps)
        r = compare_cam(cm, run=run)
    except LinkgenError as exc:
        return {"model": path.stem, "file": str(path), "ok": False, "error": message_for(path, exc)}
    e = r["errors_relative"]
    ok = all(e[k] <= tol for k, tol in CAM_TOLERANCES.items())
    out = {"file": str(path), "ok": ok, "cam": r | {"tolerances": CAM_TOLERANCES}, "model": r["model"],
           "diagnosis": [f.to_json() for f in diagnose_cam(cm, run, e, r["windows"])]}
    if report is not None:
        from linkgen.report.figures_cam import plot_cam

        report.mkdir(parents=True, exist_ok=True)
        out["figures"] = plot_cam(cm, run, report)
    out["total_wall_s"] = time.perf_counter() - t0
    return out


def cam_line(r: dict) -> str:
    """The one-line result of a cam file's MuJoCo check."""
    c = r["cam"]
    e, tol = c["errors_relative"], c["tolerances"]
    return (f"{r['model']:<22} {'ok  ' if r['ok'] else 'FAIL'} cam in MuJoCo (contact with a {c['profile_points']}-"
            f"vertex profile): displacement {e['displacement']:.2e} of the stroke (tolerance "
            f"{tol['displacement']:g}), contact force {e['contact_force']:.2e} (tolerance {tol['contact_force']:g}) "
            f"and cam torque {e['cam_torque']:.2e} (tolerance {tol['cam_torque']:g}) of their peaks as "
            f"{360 / c['windows']:g}° means, "
            f"{c['steps']} steps, {wall_text(r['total_wall_s'])}")


def wall_text(seconds: float) -> str:
    """The wall time of one file's validation, as the CLI line and the report table give it."""
    return f"validated in {seconds:.2f} s"


__all__ = ["cam_line", "wall_text", "cam_summary", "check_cam_file", "check_cam_linkage_file"]
