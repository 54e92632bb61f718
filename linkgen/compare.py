"""Closed form against MuJoCo at the same crank states: errors per quantity."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .kinematics import Assembly, Motion, solve
from .simulate import Run

# Every kinematic quantity within this fraction of its peak magnitude (issue 3).
REL_TOL = 1e-6
# Loop-closure gap allowed at every step [m] (issue 3).
VIOLATION_TOL = 1e-8
# A quantity's peak is at least this fraction of the mechanism's natural scale for its kind
# (size, size·ω, size·ω², π, ω, ω²), so that an identically-zero quantity is judged absolutely.
PEAK_FLOOR = 1e-3


@dataclass(frozen=True)
class QuantityError:
    max_abs_error: float
    peak: float
    tolerance: float

    @property
    def relative_error(self) -> float:
        return self.max_abs_error / self.peak

    @property
    def ok(self) -> bool:
        return self.relative_error <= self.tolerance


@dataclass(frozen=True)
class Comparison:
    """Errors per quantity (``points.B.velocity``, ``links.rocker.angle``, …) and the curves."""

    model: str
    quantities: dict[str, QuantityError]
    closed_form: Motion
    run: Run

    @property
    def ok(self) -> bool:
        return all(q.ok for q in self.quantities.values())

    def to_json(self) -> dict:
        return {
            "model": self.model,
            "quantities": {k: {"max_abs_error": q.max_abs_error, "peak": q.peak, "relative_error": q.relative_error,
                               "tolerance": q.tolerance, "ok": q.ok} for k, q in self.quantities.items()},
            "ok": self.ok,
        }


def _scales(asm: Assembly, omega: np.ndarray, epsilon: np.ndarray) -> dict[str, float]:
    """Floors for a quantity's peak, so a quantity that is identically zero in the closed form
    (a slider that never turns) is judged against the mechanism's natural scale, not 0."""
    xy = np.array(list(asm.mechanism.points.values()))
    size = float(np.hypot(*(xy.max(axis=0) - xy.min(axis=0))))
    w, e = float(np.abs(omega).max()), float(np.abs(epsilon).max())
    return {"position": size, "velocity": size * w, "acceleration": size * (w * w + e), "angle": math.pi,
            "angular_velocity": w, "angular_acceleration": w * w + e, "displacement": size}


def compare(asm: Assembly, run: Run) -> Comparison:
    s = run.samples
    phi, omega, epsilon = s.crank
    mo = solve(asm, phi).motion(omega, epsilon)
    floor = _scales(asm, omega, epsilon)
    out: dict[str, QuantityError] = {}

    def add(name: str, kind: str, ours: np.ndarray, theirs: np.ndarray, wrap: bool = False) -> None:
        diff = theirs - ours
        if wrap:
            diff = np.angle(np.exp(1j * diff))
        err = np.linalg.norm(diff, axis=1) if diff.ndim == 2 else np.abs(diff)
        mag = np.linalg.norm(ours, axis=1) if ours.ndim == 2 else np.abs(ours)
        out[name] = QuantityError(float(err.max()), max(float(mag.max()), PEAK_FLOOR * floor[kind]), REL_TOL)

    for p, mj in s.points.items():
        for j, q in enumerate(("position", "velocity", "acceleration")):
            add(f"points.{p}.{q}", q, mo.points[p][j], mj[j])
    for l, mj in s.links.items():
        for j, q in enumerate(("angle", "angular_velocity", "angular_acceleration")):
            add(f"links.{l}.{q}", q, mo.links[l][j], mj[j], wrap=(j == 0))
    for n, mj in s.sliders.items():
        for j, q in enumerate(("displacement", "velocity", "acceleration")):
            add(f"sliders.{n}.{q}", {"displacement": "position"}.get(q, q), mo.sliders[n][j], mj[j])
    gap = float(max(run.violation.max(), s.violation.max()))
    out["constraint_violation"] = QuantityError(gap, 1.0, VIOLATION_TOL)  # judged in metres: peak 1 m
    return Comparison(asm.mechanism.name, out, mo, run)
