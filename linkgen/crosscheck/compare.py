"""Closed form against MuJoCo at the same crank states: errors per quantity.

Every error is judged relative to a scale that cannot vanish: the larger of the quantity's
own peak and the mechanism's natural scale for its kind (size L, L·ω, L·(ω² + |ε|) + |g| for
points and sliders; 1 rad, ω, ω² + |ε| + |g|/L for links; the peak reaction F for forces and
F·L for torques and moments). The loop gap is judged relative to L.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.kinematics import solve
from linkgen.families.planar.kinetostatics import Forces, forces
from linkgen.families.planar.loads import mass_table
from linkgen.mujoco.forces import ForceSamples, inverse_forces
from linkgen.mujoco.loops import acceleration_scale, mechanism_size
from linkgen.mujoco.state import joint_states
from linkgen.families.planar.motion import Motion
from linkgen.mujoco.simulate import Run

from linkgen.mujoco.tolerances import FORCE_TOL, GAP_TOL, INVERSE_TOL, REL_TOL, gap_tolerance  # noqa: F401 (re-exported)


@dataclass(frozen=True)
class QuantityError:
    """Largest error over the samples, the quantity's own peak, the scale the error is judged
    against (≥ peak) and the tolerance on error/scale; ``at`` is the sample index of the worst."""

    max_abs_error: float
    peak: float
    scale: float
    tolerance: float
    errors: np.ndarray  # (m,) per-sample absolute error

    @property
    def relative_error(self) -> float:
        return self.max_abs_error / self.scale

    @property
    def ok(self) -> bool:
        return bool(self.relative_error <= self.tolerance)

    def to_json(self) -> dict:
        return {"max_abs_error": self.max_abs_error, "peak": self.peak, "scale": self.scale,
                "relative_error": self.relative_error, "tolerance": self.tolerance, "ok": self.ok}


@dataclass(frozen=True)
class Comparison:
    """Errors per quantity (``points.B.velocity``, ``links.rocker.angle``, …), the loop gap
    and the curves of both sides."""

    def __repr__(self) -> str:
        return f"Comparison({self.model!r}, ok={self.ok}, {len(self.quantities)} quantities)"


    model: str
    assembly: Assembly
    quantities: dict[str, QuantityError]
    closed_form: Motion
    run: Run
    closed_forces: Forces
    inverse: ForceSamples | None
    size: float

    @property
    def gap(self) -> QuantityError:
        return self.quantities["loop_gap"]

    @property
    def ok(self) -> bool:
        return all(q.ok for q in self.quantities.values())


def _error(ours: np.ndarray, theirs: np.ndarray, scale: float, tol: float, wrap: bool = False) -> QuantityError:
    """Largest |theirs − ours| (vector norm for (m, 2)) against max(ours' peak, scale);
    ``wrap`` compares angles modulo 2π."""
    diff = theirs - ours
    if wrap:
        diff = np.angle(np.exp(1j * diff))
    err = np.linalg.norm(diff, axis=1) if diff.ndim == 2 else np.abs(diff)
    mag = np.linalg.norm(ours, axis=1) if ours.ndim == 2 else np.abs(ours)
    peak = float(mag.max()) if mag.size else 0.0
    return QuantityError(float(err.max()) if err.size else 0.0, peak, max(peak, scale), tol, err)


def kinematic_scales(size: float, omega: np.ndarray, epsilon: np.ndarray, gravity: float = 0.0) -> dict[str, float]:
    """The natural scale of each kind of kinematic quantity (``gravity`` [m/s²] its magnitude)."""
    w, e = float(np.abs(omega).max()), float(np.abs(epsilon).max())
    a = acceleration_scale(size, w, e, gravity)
    return {"position": size, "velocity": size * w, "acceleration": a, "angle": 1.0,
            "angular_velocity": w, "angular_acceleration": a / size}


def force_scale(cf: Forces, asm: Assembly, size: float, acceleration: float) -> float:
    """The larger of the peak reaction [N] over every pair (revolute reactions and prismatic
    normal forces) and a floor that cannot vanish: the moving masses at the acceleration scale
    [m/s²] plus the applied forces and torques/size (a rotor turning on its own axis carries no
    reaction at all)."""
    mech = asm.mechanism
    floor = (sum(mp.mass for mp in mass_table(asm).values()) * acceleration
             + sum(math.hypot(*f.force) for f in mech.forces) + sum(abs(m.torque) for m in mech.torques) / size)
    return max([float(np.linalg.norm(r, axis=1).max()) for r in cf.reactions.values()]
               + [float(np.abs(n).max()) for n in cf.normal_force.values()] + [floor])


def with_tooth_on_pins(asm: Assembly, cf: Forces) -> Forces:
    """The closed form's reactions as MuJoCo carries them where a gear pair couples two joints:
    the coupling is a pure torque between the planet's pin and the crank, so the tooth force the
    fixed gear puts on the planet reaches the ground through the planet's pin and the crank's
    bearing instead; each of those reactions is compared with the tooth force added."""
    from dataclasses import replace

    mech = asm.mechanism
    if not mech.gears:
        return cf
    reactions = dict(cf.reactions)
    drive = mech.revolute(mech.drive.joint)
    for g in mech.gears:
        pin = next(r for r in mech.revolutes
                   if r.point == mech.link(g.planet).points[0] and set(r.links) == {mech.crank, g.planet})
        tooth = cf.tooth[g.name]
        reactions[pin.name] = reactions[pin.name] + (tooth if pin.links[0] == g.planet else -tooth)
        reactions[drive.name] = reactions[drive.name] + (tooth if drive.links[0] == mech.crank else -tooth)
    return replace(cf, reactions=reactions)


def compare(asm: Assembly, run: Run, *, inverse: bool = True) -> Comparison:
    """Every quantity of the run against the closed form at MuJoCo's measured crank states;
    ``inverse`` also runs the inverse-dynamics route."""
    s = run.samples
    phi, omega, epsilon = s.crank
    mo = solve(asm, phi).motion(omega, epsilon)
    size = mechanism_size(asm)
    scale = kinematic_scales(size, omega, epsilon, float(np.hypot(*asm.mechanism.gravity)))
    out: dict[str, QuantityError] = {}

    def add(name: str, kind: str, ours: np.ndarray, theirs: np.ndarray, wrap: bool = False) -> None:
        out[name] = _error(ours, theirs, scale[kind], REL_TOL, wrap)

    for p, mj in s.points.items():
        for j, q in enumerate(("position", "velocity", "acceleration")):
            add(f"points.{p}.{q}", q, mo.points[p][j], mj[j])
    for n, mj in s.links.items():
        for j, q in enumerate(("angle", "angular_velocity", "angular_acceleration")):
            add(f"links.{n}.{q}", q, mo.links[n][j], mj[j], wrap=(j == 0))
    for n, mj in s.sliders.items():
        for j, q in enumerate(("displacement", "velocity", "acceleration")):
            add(f"sliders.{n}.{q}", {"displacement": "position"}.get(q, q), mo.sliders[n][j], mj[j])
    cf = with_tooth_on_pins(asm, forces(asm, phi, omega, epsilon))
    inv = _inverse(asm, run) if inverse else None
    f_scale = force_scale(cf, asm, size, scale["acceleration"])
    _force_errors(cf, s.forces, "", FORCE_TOL, size, out, f_scale)
    if asm.mechanism.frictions:
        _friction_errors(asm, cf, s, out, f_scale, size)
    if inv is not None:
        _force_errors(cf, inv, "inverse.", INVERSE_TOL, size, out, f_scale)
    j = cf.reduced.inertia
    out["reduced_inertia"] = _error(j, s.reduced_inertia, 0.0, FORCE_TOL)
    gap = max(run.gap_max, float(s.violation.max()) if s.violation.size else 0.0)
    gap_tol = gap_tolerance(run.scales.sigma_min) if run.scales is not None else GAP_TOL
    out["loop_gap"] = QuantityError(gap, gap, size, gap_tol, s.violation)
    return Comparison(asm.mechanism.name, asm, out, mo, run, cf, inv, size)


def _inverse(asm: Assembly, run: Run) -> ForceSamples:
    """The inverse-dynamics route at the closed-form state of every sampled (φ, ω, ε)."""
    import mujoco

    d = mujoco.MjData(run.model)
    phi = run.samples.crank[0]
    qpos, qvel, qacc = joint_states(asm, run.model, *run.samples.crank)
    return ForceSamples.stack([inverse_forces(asm, run.model, d, float(phi[k]), qpos[k], qvel[k], qacc[k])
                               for k in range(phi.shape[0])])


def _friction_errors(asm: Assembly, cf: Forces, s, out: dict[str, QuantityError], f_scale: float,
                     size: float) -> None:
    """``friction.PAIR``: the friction law applied to MuJoCo's own reactions of the run against the
    friction linkgen applied (the closed form's, ``mujoco.friction``): the fixed point in MuJoCo's
    terms. μ·r·|R| moves by μ·r·|ΔR| and μ·max(|N|, 2|M|/L) by μ·(|ΔN| + 2|ΔM|/L), so the scale is
    that of the reactions (F, and F·size for the moment) carried through the law."""
    from linkgen.mujoco.friction import friction_from_reactions

    phi, omega, _ = s.crank
    theirs = friction_from_reactions(asm, phi, omega, s.forces.reactions, s.forces.normal_force, s.forces.moment)
    for fr in asm.mechanism.frictions:
        arm = fr.pin_radius if fr.pin_radius is not None else 1.0 + 2.0 * size / fr.block_length
        out[f"friction.{fr.pair}"] = _error(cf.friction[fr.pair], theirs[fr.pair], fr.coefficient * arm * f_scale,
                                            FORCE_TOL)


def _force_errors(cf: Forces, mj: ForceSamples, prefix: str, tol: float, size: float,
                  out: dict[str, QuantityError], f_scale: float) -> None:
    """Errors of every force quantity against the force scale F (``force_scale``) or F·size
    (torques, moments)."""

    def add(name, ours, theirs, scale):
        out[prefix + name] = _error(ours, theirs, scale, tol)

    add("balancing_torque", cf.balancing_torque, mj.balancing_torque, f_scale * size)
    for k, r in cf.reactions.items():
        add(f"reactions.{k}.force", r, mj.reactions[k], f_scale)
    for k in cf.normal_force:
        add(f"prismatic.{k}.normal_force", cf.normal_force[k], mj.normal_force[k], f_scale)
        add(f"prismatic.{k}.moment", cf.moment[k], mj.moment[k], f_scale * size)
