"""Why a cam's MuJoCo run missed its tolerance: per failing quantity, the cam-angle ranges and
the cause — the closed form's follower leaving the cam, the roller leaving the cam in MuJoCo
(and the impact where it lands), the roller sinking into the profile, impacts, or the faceted
contact's bouncing — with the figures behind it. The same ``Finding`` as a linkage's diagnosis."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkgen.crosscheck.diagnose import Finding
from linkgen.families.cam.kinetics import state
from linkgen.errors import angle_ranges
from linkgen.mujoco.cam import CAM_TOLERANCES, WINDOWS, quantity_names
from linkgen.mujoco.cam_run import window_means

# The roller is said to have left the cam when it is off the profile for longer than this cam
# angle [rad]: its bounces over the profile's facets last a few steps (STEPS_PER_TURN steps a turn:
# 0.018° a step), a fly-off tens of steps or more.
LEFT_FOR = math.radians(0.5)
# An instantaneous contact force above this multiple of the closed form's peak is an impact: the
# faceted contact's train of small impacts reaches about twice the peak (docs/cams.md).
IMPACT_FACTOR = 3.0
# Steps before a failing range searched for its cause, as a cam angle [rad].
LOOK_BACK = math.radians(10.0)


def _runs(mask: np.ndarray) -> list[tuple[int, int]]:
    """Contiguous runs of True in ``mask`` as (first, last) indices."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], mask.astype(np.int8), [0]])))
    return [(int(a), int(b) - 1) for a, b in zip(edges[::2], edges[1::2])]


@dataclass(frozen=True)
class ContactTrace:
    """One cam contact over a MuJoCo run, per step: the cam angle [rad], whether the roller
    touches the profile, the contact normal force [N] and its closed form, the penetration [m];
    the cam turn per step [rad] and the roller centre's travel over the stroke [m]."""

    theta: np.ndarray
    touching: np.ndarray
    force: np.ndarray
    force_closed: np.ndarray
    penetration: np.ndarray
    step_angle: float
    travel: float


def _steps(angle: float, t: ContactTrace) -> int:
    """Whole steps of the run within the cam angle ``angle`` [rad] (none if a step turned the cam
    by no measurable angle: a run that could not advance)."""
    return int(angle / t.step_angle) if t.step_angle > 0 else 0


def _cause(t: ContactTrace, lo: int, hi: int) -> tuple[str, str]:
    """The cause of a miss over the steps lo..hi (and LOOK_BACK before them)."""
    deg = math.degrees
    lo = max(0, lo - _steps(LOOK_BACK, t))
    th = t.theta % (2 * math.pi)
    cf = t.force_closed
    peak = float(np.abs(cf).max()) or 1.0
    if cf[lo:hi + 1].min() < 0:
        k = lo + int(np.argmin(cf[lo:hi + 1]))
        return ("follower leaves the cam", f"the closed form's contact force is {cf[k]:.3g} N at {deg(th[k]):.2f}°: the "
                "spring cannot hold the follower on the cam at this speed (a stronger spring_preload or spring_rate, "
                "or a lower omega)")
    off = [(a, b) for a, b in _runs(~t.touching[lo:hi + 1]) if (b - a + 1) * t.step_angle > LEFT_FOR]
    if off:
        a, b = max(off, key=lambda r: r[1] - r[0])
        a, b = a + lo, b + lo
        land = slice(b + 1, min(b + 1 + _steps(LEFT_FOR, t), th.shape[0]))
        hit = float(t.force[land].max()) if land.start < land.stop else 0.0
        return ("contact lost", f"the roller left the cam at {deg(th[a]):.2f}° and stayed off for "
                f"{deg((b - a + 1) * t.step_angle):.2f}° ({b - a + 1} steps) though the closed form's contact force "
                f"there is {cf[a]:.3g} N; it landed at {deg(th[min(b + 1, th.shape[0] - 1)]):.2f}° with an impact of {hit:.3g} N "
                f"({hit / peak:.2g}× the closed form's peak {peak:.3g} N)")
    if t.penetration[lo:hi + 1].max() > CAM_TOLERANCES["displacement"] * t.travel:
        k = lo + int(np.argmax(t.penetration[lo:hi + 1]))
        return ("penetration", f"the roller sank {t.penetration[k]:.3g} m into the profile at {deg(th[k]):.2f}° "
                f"({t.penetration[k] / t.travel:.2g} of the roller's travel {t.travel:.3g} m)")
    seg = t.force[lo:hi + 1]
    k = lo + int(np.argmax(seg))
    if seg.max() > IMPACT_FACTOR * peak:
        return ("impact", f"an impact of {seg.max():.3g} N ({seg.max() / peak:.2g}× the closed form's peak) at "
                f"{deg(th[k]):.2f}°")
    share = 1.0 - float(np.mean(t.touching[lo:hi + 1]))
    return ("faceted contact", f"the roller bounces over the profile's facets (off the cam in {share:.0%} of the steps "
            f"there; largest contact force {seg.max():.3g} N, {seg.max() / peak:.2g}× the closed form's peak)")


def windows_over(mj: np.ndarray, cf: np.ndarray, windows: int, tol: float) -> np.ndarray:
    """Per step, True in the windows whose means of ``mj`` and ``cf`` differ by more than
    ``tol`` of the peak of ``cf`` (how ``validate`` compares forces)."""
    a, b = window_means(mj, windows), window_means(cf, windows)
    per = mj.shape[0] // windows
    bad = np.zeros(mj.shape[0], dtype=bool)
    for w in np.flatnonzero(np.abs(a - b) / (float(np.abs(cf).max()) or 1.0) > tol):
        bad[w * per:(w + 1) * per] = True
    return bad


def findings(trace: ContactTrace, misses: dict) -> list[Finding]:
    """A Finding per quantity of ``misses`` (name → (per-step mask over its tolerance, error,
    tolerance)), the worst first."""
    th = trace.theta % (2 * math.pi)
    out = []
    for name, (bad, err, tol) in misses.items():
        idx = np.flatnonzero(bad)
        cause, detail = _cause(trace, int(idx[0]), int(idx[-1])) if idx.size else ("", "")
        out.append(Finding(name, angle_ranges(th, bad), err, tol, cause, detail))
    return sorted(out, key=lambda x: -x.relative_error / x.tolerance)


def diagnose_cam(cm, run, errs: dict, windows: int = WINDOWS) -> list[Finding]:
    """A Finding for every quantity of ``errs`` (``mujoco.cam_run.compare_cam`` of ``run``) over its
    tolerance, the worst first."""
    ref = state(cm, run.theta, float(np.mean(run.omega)))
    q = cm.follower.output(run.theta)[0]
    stroke = max(float(np.ptp(q)), 1e-300)
    f = cm.follower
    trace = ContactTrace(run.theta, run.touching, run.contact_force, ref.contact_force, run.penetration,
                         float(np.mean(run.omega)) * run.timestep,
                         stroke * (f.arm_length if f.kind == "oscillating" else 1.0))
    misses, names = {}, quantity_names(f.kind)
    for name, tol in CAM_TOLERANCES.items():
        if errs[name] <= tol:
            continue
        if name == "displacement":
            bad = np.abs(run.displacement - q) / stroke > tol
        else:
            mj, cf = (run.contact_force, ref.contact_force) if name == "contact_force" else (run.cam_torque, ref.cam_torque)
            bad = windows_over(mj, cf, windows, tol)
        misses[names[name]] = (bad, errs[name], tol)
    return findings(trace, misses)


def cam_linkage_findings(r) -> list[Finding]:
    """The diagnosis of a cam linkage's MuJoCo check (``mujoco.cam_linkage.CamLinkageCheck``):
    every quantity over its tolerance with where and why, judged on its cam's contact (``cams``;
    the first cam's for the points and the balancing torque)."""
    out = []
    for name, (err, tol) in r.errors.items():
        if err <= tol:
            continue
        cam = r.cams.get(name, next(iter(r.contacts)))
        out += findings(ContactTrace(**r.contacts[cam]), {name: (r.curves[name] > tol, err, tol)})
    return sorted(out, key=lambda f: -f.relative_error / f.tolerance)


__all__ = ["IMPACT_FACTOR", "LEFT_FOR", "ContactTrace", "cam_linkage_findings", "diagnose_cam", "findings",
           "windows_over"]
