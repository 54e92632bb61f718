"""Why a comparison missed its tolerance: per failing quantity, the crank-angle ranges, the
cause (near-singular pose, load switch, loop gap, time budget) and the figures behind it."""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from linkgen.crosscheck.compare import Comparison
from linkgen.errors import angle_ranges, format_ranges
from linkgen.mujoco.loops import closure_jacobian
from linkgen.mujoco.settings import sigma_min

# A pose is called near-singular when the loop Jacobian's smallest singular value (columns
# made dimensionless by the size) is below this: joint errors then exceed 10× the loop gap.
NEAR_SINGULAR_SIGMA = 0.1
# A failure this many settling windows after a load switch is put down to the switch.
SWITCH_REACH = 3.0


@dataclass(frozen=True)
class Finding:
    """One failing quantity: where (crank-angle ranges [rad]), how much, and why."""

    quantity: str
    ranges: list[tuple[float, float]]
    relative_error: float
    tolerance: float
    cause: str
    detail: str

    def to_json(self) -> dict:
        return {"quantity": self.quantity,
                "ranges": [[float(a), float(b)] for a, b in self.ranges],
                "relative_error": self.relative_error if math.isfinite(self.relative_error) else None,
                "tolerance": self.tolerance,
                "cause": self.cause, "detail": self.detail}

    def text(self) -> str:
        if not self.ranges and not math.isfinite(self.relative_error):  # no run compared anything
            return f"{self.cause}: {self.detail}"
        return (f"{self.quantity}: {self.relative_error:.2e} of its scale (tolerance {self.tolerance:g}) at "
                f"{format_ranges(self.ranges, 3)} — {self.cause}: {self.detail}")


def finding_line(d: dict, name: str = "{}: ") -> str:
    """One finding of a result's JSON (``Finding.to_json``) as the CLI and the report print it:
    the quantity (through ``name``), its error against its tolerance, the first three crank-angle
    ranges [°] and the cause; a finding where no run compared anything gives its cause alone."""
    if d["relative_error"] is None and not d["ranges"]:
        return f"{d['cause']}: {d['detail']}"
    rng = ", ".join(f"{math.degrees(a):.1f}°..{math.degrees(b):.1f}°" for a, b in d["ranges"][:3])
    err = "–" if d["relative_error"] is None else format(d["relative_error"], ".2e")
    return f"{name.format(d['quantity'])}{err} (tolerance {d['tolerance']:g}) at {rng}: {d['cause']} — {d['detail']}"


def _sigma_at(cmp: Comparison, k: int) -> float:
    """The loop Jacobian's smallest singular value at MuJoCo's state of sample k."""
    model = cmp.run.model
    d = mujoco.MjData(model)
    d.qpos[:], d.qvel[:] = cmp.run.samples.qpos[k], cmp.run.samples.qvel[k]
    mujoco.mj_kinematics(model, d)
    mujoco.mj_comPos(model, d)
    return sigma_min(model, closure_jacobian(cmp.assembly, model, d), cmp.assembly.mechanism.drive.joint, cmp.size)


def diagnose(cmp: Comparison, budget_exhausted: bool = False) -> list[Finding]:
    """A Finding for every quantity over its tolerance, the worst first; ``budget_exhausted``:
    no finer run fitted the step budget (or the float64 floor on τ)."""
    run = cmp.run
    phi = run.samples.crank[0]
    switches = [lo.phi_from for lo in run.left_out if lo.reason == "load switch"]
    reach = SWITCH_REACH * run.window * float(np.abs(run.samples.crank[1]).max())
    out = []
    sigma: dict[int, float] = {}  # per sample: the failing quantities share their worst samples
    for name, q in cmp.quantities.items():
        if q.ok:
            continue
        bad = q.errors / q.scale > q.tolerance
        ranges = angle_ranges(phi, bad) if bad.shape == phi.shape and bad.any() else [(float(phi[0]), float(phi[-1]))]
        k = int(np.argmax(q.errors)) if q.errors.shape == phi.shape else 0
        if name == "loop_gap":
            cause = "loop gap"
            detail = f"the loops opened by {q.max_abs_error:.3g} m, {q.relative_error:.2g} of the size {cmp.size:.3g} m"
        elif run.scales is not None and run.scales.capped:
            cause = "time budget"
            detail = "the settings the mechanism needs exceed the step budget"
        elif any(0.0 <= (phi[k] - sw) % (2 * math.pi) <= reach for sw in switches):
            cause = "load switch"
            detail = (f"within {reach * 180 / math.pi:.3g}° after a load switches, the loops' transient "
                      f"(settling window {run.window * 1e3:.3g} ms) is still decaying")
        else:
            sig = sigma[k] if k in sigma else sigma.setdefault(k, _sigma_at(cmp, k))
            if sig < NEAR_SINGULAR_SIGMA:
                cause = "near-singular"
                detail = (f"the loop constraints are ill-conditioned there (condition number {1 / sig:.3g} at "
                          f"{math.degrees(phi[k]):.2f}°): MuJoCo's integration and loop-gap errors are amplified")
            elif budget_exhausted:
                cause = "time budget"
                detail = (f"worst at {math.degrees(phi[k]):.2f}° (condition number {1 / sig:.3g}, loop gap "
                          f"{run.gap_max:.2g} m); a finer run would pass the step budget or float64's floor on τ")
            else:
                cause = "integration error"
                detail = (f"worst at {math.degrees(phi[k]):.2f}° (condition number {1 / sig:.3g}, loop gap "
                          f"{run.gap_max:.2g} m)")
        out.append(Finding(name, ranges, q.relative_error, q.tolerance, cause, detail))
    return sorted(out, key=lambda f: -f.relative_error / f.tolerance)


__all__ = ["Finding", "NEAR_SINGULAR_SIGMA", "diagnose", "finding_line"]
