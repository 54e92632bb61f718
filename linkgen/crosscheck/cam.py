"""Cams through MuJoCo against their closed form, as validation results: a stand-alone cam
(``CamCheck``: ``mujoco.cam_run.compare_cam`` with its diagnosis) and a linkage whose crank carries
a cam (``mujoco.cam_linkage.CamLinkageCheck`` with the diagnosis of its contact)."""

from __future__ import annotations

from dataclasses import dataclass, field, replace

from linkgen.crosscheck.diagnose import Finding
from linkgen.mujoco.cam import CAM_TOLERANCES, quantity_names


@dataclass(frozen=True)
class CamCheck:
    """A stand-alone cam in MuJoCo against its closed form: ``comparison`` as
    ``mujoco.cam_run.compare_cam`` gives it (the errors relative to the stroke and the peaks, steps,
    timestep, windows), the tolerances it is held to, the diagnosis of what missed, and the run
    (for the report's figures)."""

    model: str
    comparison: dict
    tolerances: dict
    diagnosis: tuple[Finding, ...] = ()
    run: object = field(default=None, repr=False, compare=False)

    @property
    def ok(self) -> bool:
        e = self.comparison["errors_relative"]
        return all(e[k] <= tol for k, tol in self.tolerances.items())

    def summary(self, wall: str | None = None) -> str:
        """One line; ``wall``: the wall time as the caller measured it (default: the steps only)."""
        c, e, tol = self.comparison, self.comparison["errors_relative"], self.tolerances
        now = e.get("contact_force_instantaneous")
        every = ("" if now is None else f" (at every step {now:.2g}" + (
            ": not held, the follower leaves the faceted profile at some steps; docs/cams-mujoco.md)"
            if now > tol["contact_force"] else ")"))
        return (f"{'ok  ' if self.ok else 'FAIL'} cam in MuJoCo (contact with a {c['profile_points']}-vertex profile): "
                f"displacement {e['displacement']:.2e} of the stroke (tolerance {tol['displacement']:g}), contact force "
                f"{e['contact_force']:.2e} (tolerance {tol['contact_force']:g}) and cam torque {e['cam_torque']:.2e} "
                f"(tolerance {tol['cam_torque']:g}) of their peaks as {360 / c['windows']:g}° means{every}, "
                f"{c['steps']} steps" + (f", {wall}" if wall else ""))

    def to_json(self) -> dict:
        return self.to_dict()

    @property
    def settings(self) -> dict:
        """The run's timestep [s] and integrator."""
        return {"timestep": self.comparison["timestep"], "integrator": self.comparison["integrator"]}

    @property
    def quantities(self) -> dict:
        """Each compared quantity as ``mujoco.result_shape`` gives it."""
        from linkgen.mujoco.result_shape import quantity

        e, names = self.comparison["errors_relative"], quantity_names(self.comparison["kind"])
        return {names[k]: quantity(e[k], tol) for k, tol in self.tolerances.items()}

    # A cam and its follower make no closed loop in MuJoCo: no loop gap.
    loop_gap = None

    def to_dict(self) -> dict:
        """The result as ``linkgen validate --json`` gives it (``mujoco.result_shape``; no loop,
        so no loop gap), with the errors of the forces step by step, held to no tolerance."""
        from linkgen.mujoco.result_shape import validation

        c, e = self.comparison, self.comparison["errors_relative"]
        return validation(self.model, self.ok, settings=self.settings, quantities=self.quantities,
                          loop_gap=self.loop_gap, diagnosis=self.diagnosis, steps=c["steps"], windows=c["windows"],
                          profile_points=c["profile_points"],
                          instantaneous={quantity_names(c["kind"])[k]: e[k + "_instantaneous"]
                                         for k in ("contact_force", "cam_torque")})


def check_cam(cm, progress=None, max_steps: int | None = None) -> CamCheck:
    """One turn of the cam in MuJoCo (``mujoco.cam_run.run_cam``; ``progress(fraction, seconds)``,
    ``max_steps`` its step budget) compared with the closed form and diagnosed."""
    from linkgen.crosscheck.diagnose_cam import diagnose_cam
    from linkgen.mujoco.cam_run import compare_cam, run_cam

    run = run_cam(cm, progress=progress, max_steps=max_steps)
    r = compare_cam(cm, run=run)
    return CamCheck(r["model"], r, dict(CAM_TOLERANCES),
                    tuple(diagnose_cam(cm, run, r["errors_relative"], r["windows"])), run)


def check_cam_linkage(asm, progress=None, max_steps: int | None = None):
    """A linkage whose crank carries a cam in MuJoCo (``mujoco.cam_linkage.check_cam_linkage``),
    with the diagnosis of its contact (``diagnose_cam.cam_linkage_findings``)."""
    from linkgen.crosscheck.diagnose_cam import cam_linkage_findings
    from linkgen.mujoco.cam_linkage import check_cam_linkage as run_check

    r = run_check(asm, progress, **({} if max_steps is None else {"max_steps": max_steps}))
    return replace(r, diagnosis=tuple(cam_linkage_findings(r)))


__all__ = ["CamCheck", "check_cam", "check_cam_linkage"]
