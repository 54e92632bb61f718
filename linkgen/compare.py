"""Closed form against MuJoCo at the same crank states: errors per quantity."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .assembly import Assembly
from .kinematics import solve
from .kinetostatics import Forces, forces
from .mjforces import ForceSamples, inverse_forces
from .motion import Motion
from .simulate import Run, joint_states

# Every kinematic quantity within this fraction of its peak magnitude (issue 3).
REL_TOL = 1e-6
# Loop-closure gap allowed at every step [m] (issue 3).
VIOLATION_TOL = 1e-8
# Forces (issue 4): the forward run within this of the peak, like the kinematics it rests on;
# the inverse route (closed-form state, no integration) within this, a few hundred roundings.
FORCE_TOL = 1e-6
INVERSE_TOL = 1e-10
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
    closed_forces: Forces
    inverse: ForceSamples

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


def _size(asm: Assembly) -> float:
    """The sketch's diagonal [m]: the mechanism's natural length scale."""
    xy = np.array(list(asm.mechanism.points.values()))
    return float(np.hypot(*(xy.max(axis=0) - xy.min(axis=0))))


def _error(ours: np.ndarray, theirs: np.ndarray, floor: float, tol: float, wrap: bool = False) -> QuantityError:
    """Largest |theirs − ours| (vector norm for (m, 2)) against ours' peak, at least ``floor``;
    ``wrap`` compares angles modulo 2π."""
    diff = theirs - ours
    if wrap:
        diff = np.angle(np.exp(1j * diff))
    err = np.linalg.norm(diff, axis=1) if diff.ndim == 2 else np.abs(diff)
    mag = np.linalg.norm(ours, axis=1) if ours.ndim == 2 else np.abs(ours)
    return QuantityError(float(err.max()), max(float(mag.max()), floor), tol)


def _scales(asm: Assembly, omega: np.ndarray, epsilon: np.ndarray) -> dict[str, float]:
    """Floors for a quantity's peak, so a quantity that is identically zero in the closed form
    (a slider that never turns) is judged against the mechanism's natural scale, not 0."""
    size = _size(asm)
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
        out[name] = _error(ours, theirs, PEAK_FLOOR * floor[kind], REL_TOL, wrap)

    for p, mj in s.points.items():
        for j, q in enumerate(("position", "velocity", "acceleration")):
            add(f"points.{p}.{q}", q, mo.points[p][j], mj[j])
    for l, mj in s.links.items():
        for j, q in enumerate(("angle", "angular_velocity", "angular_acceleration")):
            add(f"links.{l}.{q}", q, mo.links[l][j], mj[j], wrap=(j == 0))
    for n, mj in s.sliders.items():
        for j, q in enumerate(("displacement", "velocity", "acceleration")):
            add(f"sliders.{n}.{q}", {"displacement": "position"}.get(q, q), mo.sliders[n][j], mj[j])
    cf = forces(asm, phi, omega, epsilon)
    inv = _inverse(asm, run)
    _force_errors(asm, cf, s.forces, "", FORCE_TOL, out)
    _force_errors(asm, cf, inv, "inverse.", INVERSE_TOL, out)
    j = cf.reduced.inertia
    out["reduced_inertia"] = _error(j, s.reduced_inertia, 0.0, FORCE_TOL)
    gap = float(max(run.violation.max(), s.violation.max()))
    out["constraint_violation"] = QuantityError(gap, 1.0, VIOLATION_TOL)  # judged in metres: peak 1 m
    return Comparison(asm.mechanism.name, out, mo, run, cf, inv)


def _inverse(asm: Assembly, run: Run) -> ForceSamples:
    """The inverse-dynamics route at the closed-form state of every sampled (φ, ω, ε)."""
    import mujoco

    d = mujoco.MjData(run.model)
    phi = run.samples.crank[0]
    qpos, qvel, qacc = joint_states(asm, run.model, *run.samples.crank)
    return ForceSamples.stack([inverse_forces(asm, run.model, d, float(phi[k]), qpos[k], qvel[k], qacc[k])
                               for k in range(phi.shape[0])])


def _force_errors(asm: Assembly, cf: Forces, mj: ForceSamples, prefix: str, tol: float,
                  out: dict[str, QuantityError]) -> None:
    """Errors of every force quantity; peaks floored at PEAK_FLOOR of the largest reaction
    (forces) or of that times the mechanism's size (torques, moments)."""
    size = _size(asm)
    force_scale = max([float(np.linalg.norm(r, axis=1).max()) for r in cf.reactions.values()]
                      + [float(np.abs(n).max()) for n in cf.normal_force.values()])
    f_floor, m_floor = PEAK_FLOOR * force_scale, PEAK_FLOOR * force_scale * size

    def add(name, ours, theirs, floor):
        out[prefix + name] = _error(ours, theirs, floor, tol)

    add("balancing_torque", cf.balancing_torque, mj.balancing_torque, m_floor)
    for k, r in cf.reactions.items():
        add(f"reactions.{k}.force", r, mj.reactions[k], f_floor)
    for k in cf.normal_force:
        add(f"prismatic.{k}.normal_force", cf.normal_force[k], mj.normal_force[k], f_floor)
        add(f"prismatic.{k}.moment", cf.moment[k], mj.moment[k], m_floor)
