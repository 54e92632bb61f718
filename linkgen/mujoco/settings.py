"""MuJoCo settings derived from the mechanism: loop-closure time constant, timestep, rotor.

A ``connect`` is soft. With impedance d and time constant τ (damping ratio 1) MuJoCo's
constraint acceleration is a1 = (1 − d)·a0 + d·(−b·ṙ − k·r), k = 1/(d²τ²), b = 2/(dτ), where a0
is the acceleration the loop would open with if the constraint pushed nothing. MuJoCo
regularises the constraint with R = (1 − d)/d·A_diag (A_diag its approximate inverse inertia,
``efc_diagA``), so a loop held steady by force λ opens by r = R·λ/k = (1 − d)·d·τ²·A_diag·λ.
The closed form knows λ at every crank angle and MuJoCo knows A_diag at the closed-form pose:
before the run, ``derive`` scans the range for the peak of a0 = |A_diag·λ| and picks

    τ = min(τ_gap, τ_phase):
        τ_gap   so that the predicted gap is GAP_TARGET·L·σ (L the mechanism's size, σ the
                smallest singular value of the loop Jacobian over the non-driven joints, which
                turns a gap into a joint-position error of gap/σ);
        τ_phase = PHASE / ω: the loop answers a change of load within PHASE radians of crank.
    dt = τ / STEPS_PER_TAU (RK4 integrates the constraint's own dynamics, frequency 1/τ).

The cost per revolution is 2π·STEPS_PER_TAU/(ω·τ): constant (2π·STEPS_PER_TAU/PHASE) while
inertia sets τ, growing only where gravity or loads dominate the loop forces at a slow crank
(then τ_gap < τ_phase). The rotor inertia that holds the crank speed is ARMATURE_RATIO times the
mechanism's peak reduced inertia, or LOAD_ROTOR_RATIO times its peak crank torque over ω² where
that is larger. Values are rounded down to a few steps per decade so that written MJCF
does not depend on the last bits of a float.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import mujoco
import numpy as np

from linkgen.model.turn import full_turn
from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.description import Mechanism
from linkgen.errors import SimulationError
from linkgen.families.planar.kinetostatics import forces
from linkgen.mujoco.options import IMPEDANCE, MAX_STEPS, Settings
from linkgen.mujoco.tolerances import GAP_TOL, REL_TOL
from linkgen.mujoco.loops import acceleration_scale, closure_diag, closure_forces, closure_jacobian, mechanism_size
from linkgen.mujoco.state import joint_states
from linkgen.mujoco.scene import switch_off_servo
from linkgen.mujoco.tree import spanning_tree
from linkgen.mujoco.log import no_log_file
from linkgen.mujoco.loop_modes import slowest_share

# Aimed-for loop gap relative to the size: a third of the gap tolerance (compare.GAP_TOL = 1e-8);
# the prediction below is itself an upper bound (measured gaps 0.5-0.9 of it).
GAP_TARGET = 3e-9
# Aimed-for joint-position error relative to the size: a tenth of compare.REL_TOL. A gap r moves
# the joints by up to r/σ, so near a dead centre (small σ) the gap is aimed lower.
POSITION_TARGET = 1e-7
# Crank angle [rad] within which a loop answers a load change. 0.01 rad is the measured setting
# that holds the four-bar at ω = 10 rad/s (τ = 1 ms) to 2e-7 of its accelerations.
PHASE = 0.01
# RK4 steps per loop time constant. Measured on the four-bar (τ = 1 ms): dt = τ/10 leaves the
# accelerations 3.3e-6 of their peak off, τ/20 1.9e-7 (the constraint's stiffness 1/τ² turns an
# integration error of the gap into an acceleration error).
STEPS_PER_TAU = 20
# Rotor inertia on the driven joint over the mechanism's peak reduced inertia J(φ): the speed
# then changes by ~1e-6 relative over a revolution (comparisons use the measured speed anyway).
ARMATURE_RATIO = 1e6
# Rotor inertia over T_peak/ω² (T_peak the crank's peak torque): the loads then change the speed
# by at most 1e-3 relative a radian (``derive``).
LOAD_ROTOR_RATIO = 1e3
# float64 rounding, the margin kept above it, and the error it must stay under relative to the
# accelerations' scale (a tenth of compare.REL_TOL), for the loop-stiffness floor below.
EPS = 2.220446049250313e-16
PRECISION_MARGIN = 1.0
SETTLE_ERROR = 1e-7
# Before a run coarsened to its step budget, it is not started when even GAP_PREDICTION_LOW
# times its predicted gap (Scales.predicted_gap) exceeds the gap tolerance. Measured ratios of
# gap to prediction at coarsened settings (generated mechanisms, max_groups=3, budget 150 000):
# 0.073 (seed 131) to 5.8 (seed 125); the floor is 2.4 below the lowest.
GAP_PREDICTION_LOW = 0.03
# Crank angles scanned for the loop forces and conditioning.
SCAN = 181
# Every this many scanned angles the loop modes' shares are computed (``loop_modes``): they
# change with the pose as smoothly as the inertia does, at a few milliseconds each.
SHARE_EVERY = 6


@dataclass(frozen=True)
class Scales:
    """What the settings were derived from: size [m], crank speed [rad/s], peak loop
    acceleration a0 [m/s²], smallest loop-Jacobian singular value σ (dimensionless) and the
    crank angle [rad] where it occurs, peak reduced inertia [kg·m²], and the two candidate
    time constants [s]."""

    size: float
    omega: float
    loop_acceleration: float
    sigma_min: float
    sigma_min_at: float
    reduced_inertia: float
    tau_gap: float
    tau_phase: float
    tau_floor: float
    capped: bool
    acceleration_scale: float = math.nan  # size·(ω² + |ε|) + |g| [m/s²]
    tau_needed: float = math.nan  # the derived τ before a step budget coarsened it [s]
    loop_acceleration_closure: str = ""  # the loop-closing joint where a0 peaks
    loop_acceleration_at: float = math.nan  # the crank angle where a0 peaks [rad]
    loop_inverse_inertia: float = math.nan  # MuJoCo's A_diag there [1/kg]
    loop_force: float = math.nan  # the loop force λ there [N]
    # The smallest share ρ of the soft model's stiffness and damping a loop direction gets,
    # min eig(A·(A + R)⁻¹) over the scan (``loop_modes.slowest_share``; 1 for no loop).
    loop_share: float = 1.0

    def predicted_gap(self, timeconst: float) -> float:
        """The loop gap [m] a run with loop time constant ``timeconst`` [s] is predicted to
        reach, (1 − d)·d·τ²·a0 (an upper bound: measured gaps 0.5–0.9 of it)."""
        return (1 - IMPEDANCE) * IMPEDANCE * timeconst**2 * self.loop_acceleration

    def to_json(self) -> dict:
        """The fields, a non-finite number (no loop to close: τ_gap = ∞, no closure) as None."""
        return {k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in asdict(self).items()}


_STEPS = (8, 6, 5, 4, 3, 2.5, 2, 1.5, 1.2, 1)


def round_down(x: float) -> float:
    """The largest of (1, 1.2, 1.5, 2, 2.5, 3, 4, 5, 6, 8) × 10^k not above x (x > 0): at most
    20 % below x, and the same value whatever the last bits of x."""
    k = math.floor(math.log10(x))
    for m in _STEPS:
        v = float(f"{m}e{k}")
        if v <= x * (1 + 1e-9):
            return v
    return float(f"8e{k - 1}")


def scan_angles(asm: Assembly, n: int = SCAN) -> np.ndarray:
    d = asm.mechanism.drive
    full = full_turn(asm.mechanism)
    return np.linspace(d.start, d.stop, n, endpoint=not full)


@no_log_file()  # it steps MuJoCo's forward dynamics at every scanned pose
def derive(asm: Assembly, model: mujoco.MjModel, *, omega: float, epsilon: float = 0.0,
           duration: float | None = None, max_steps: int = MAX_STEPS) -> tuple[Settings, Scales]:
    """Settings for a run at crank speed ω [rad/s] (peak over the run) and ε [rad/s²].

    ``model`` is any compiled model of the mechanism (its joints and masses are read, not its
    options). ``duration`` [s], if given, caps the steps at ``max_steps``."""

    phi = scan_angles(asm)
    n = phi.shape[0]
    w = np.full(n, abs(omega))
    e = np.full(n, epsilon)
    cf = forces(asm, phi, w, e)
    qpos, qvel, _ = joint_states(asm, model, phi, w, e)
    data = mujoco.MjData(model)
    size = mechanism_size(asm)
    a0, sigma = np.zeros(n), np.zeros(n)
    where = np.zeros(n, dtype=int)  # the closure where a0 peaks at each angle
    inv_inertia, force = np.zeros(n), np.zeros(n)
    for k in range(n):
        data.qpos[:], data.qvel[:] = qpos[k], qvel[k]
        mujoco.mj_forward(model, data)
        jac = closure_jacobian(asm, model, data)
        if jac.shape[0] == 0:
            sigma[k] = 1.0
            continue
        lam = closure_forces(asm, model, cf.reactions, k).reshape(-1, 2)
        per = np.linalg.norm(closure_diag(asm, model, data) * lam, axis=1)
        where[k] = int(np.argmax(per))
        a0[k] = float(per[where[k]])
        inv_inertia[k] = float(np.abs(closure_diag(asm, model, data)[where[k]]).max())
        force[k] = float(np.linalg.norm(lam[where[k]]))
        sigma[k] = sigma_min(model, jac, asm.mechanism.drive.joint, size)
    a_peak = max(float(a0.max()), 1e-300)
    k_min = int(np.argmin(sigma))
    s_min = float(sigma[k_min])
    if not s_min > 0.0:
        raise SimulationError(f"the loop constraints are singular at crank angle {math.degrees(phi[k_min]):.3f}° "
                              f"(the loops' Jacobian loses rank): no settings can hold them there")
    gap = size * min(GAP_TARGET, POSITION_TARGET * s_min)
    d = IMPEDANCE
    tau_gap = math.sqrt(gap / ((1 - d) * d * a_peak)) if a_peak > 1e-300 else math.inf
    tau_phase = PHASE / max(abs(omega), 1e-300)
    tau_floor = precision_floor(size, omega, epsilon, float(np.hypot(*asm.mechanism.gravity)))
    tau = min(tau_gap, tau_phase)
    if tau < tau_floor:
        # Stiffer loops than float64 resolves: the gap (∝ τ²) and the rounding (∝ 1/τ²) are
        # balanced at their tolerances, τ = √(τ at the gap tolerance · τ at the rounding one).
        tau = math.sqrt(tau_gap * math.sqrt(GAP_TOL / GAP_TARGET) * tau_floor * math.sqrt(SETTLE_ERROR / REL_TOL))
    tau = round_down(tau)
    tau_needed = tau
    dt = tau / STEPS_PER_TAU
    capped = False
    if duration is not None and duration / dt > max_steps:
        dt = duration / max_steps
        tau = dt * STEPS_PER_TAU
        capped = True
    j_peak = float(np.abs(cf.reduced.inertia).max())
    # The rotor holds the speed against the crank's torque too: a torque T changes the speed by
    # T/(J·ω²) relative a radian, so J ≥ LOAD_ROTOR_RATIO·T_peak/ω² keeps it within 1e-3 (a slow
    # crank under gravity turned backwards with the rotor sized on J(φ) alone: fidelity corpus
    # seed 109). Not ARMATURE_RATIO: comparisons use the measured speed, and a larger rotor only
    # amplifies the noise of its acceleration in the crank torque MuJoCo reports.
    j_load = LOAD_ROTOR_RATIO * float(np.abs(cf.balancing_torque).max()) / max(float(omega) ** 2, 1e-300)
    j_rotor = max(ARMATURE_RATIO * j_peak, j_load if math.isfinite(j_load) else 0.0)
    armature = round_down(j_rotor) if j_rotor > 0 else 1.0
    settings = Settings(timestep=dt, timeconst=tau, armature=armature,
                        label="derived, coarsened to the step budget" if capped else "derived")
    if asm.mechanism.cams:  # a cam's contact needs a shorter step than the loops may
        from linkgen.mujoco.cam_pair import cam_settings

        settings = cam_settings(asm, settings)
    k_a = int(np.argmax(a0))
    dof = model.joint(asm.mechanism.drive.joint).dofadr[0]
    before = float(model.dof_armature[dof])
    set_armature(model, dof, armature)  # the run's rotor: the crank's share of every loop's inertia
    share = slowest_share(asm, model, qpos[::SHARE_EVERY], qvel[::SHARE_EVERY], IMPEDANCE)
    set_armature(model, dof, before)
    closures = spanning_tree(asm).closures
    scales = Scales(size, abs(omega), a_peak, s_min, float(phi[k_min]), j_peak, tau_gap, tau_phase, tau_floor,
                    capped, acceleration_scale(size, omega, epsilon, float(np.hypot(*asm.mechanism.gravity))),
                    tau_needed, closures[where[k_a]].name if closures else "", float(phi[k_a]),
                    float(inv_inertia[k_a]), float(force[k_a]), share)
    return settings, scales


def check_budget(scales: Scales, settings: Settings, duration: float, max_steps: int) -> None:
    """Raise SimulationError, before any step, when the step budget forces a loop time constant
    at which even the lowest measured fraction of the predicted gap exceeds the gap tolerance."""
    gap = scales.predicted_gap(settings.timeconst)
    if GAP_PREDICTION_LOW * gap <= GAP_TOL * scales.size:
        return
    need = duration * STEPS_PER_TAU / scales.tau_needed
    a_scale = max(scales.acceleration_scale, 1e-300)
    raise SimulationError(
        f"not run: the loops need a time constant of {scales.tau_needed:.3g} s ({need:.3g} steps per segment) to "
        f"hold their gap under {GAP_TOL:g} of the size {scales.size:.3g} m; the step budget of {max_steps:g} "
        f"allows {settings.timeconst:.3g} s, where the gap is predicted at {gap / scales.size:.2g} of the size. "
        f"The stiffest loop closes at joint {scales.loop_acceleration_closure!r}: at "
        f"{math.degrees(scales.loop_acceleration_at):.1f}° it carries {scales.loop_force:.3g} N through bodies whose "
        f"inverse inertia is {scales.loop_inverse_inertia:.3g} 1/kg, a loop acceleration of "
        f"{scales.loop_acceleration:.3g} m/s² ({scales.loop_acceleration / a_scale:.3g}× the mechanism's own scale "
        f"size·(ω² + |ε|) + |g|); the run lasts {duration:.3g} s. A larger step budget (max_steps) would run it")


def precision_floor(size: float, omega: float, epsilon: float = 0.0, gravity: float = 0.0) -> float:
    """The smallest loop time constant [s] float64 allows: the loop's stiffness 1/τ² turns the
    rounding of positions (ε_mach·size) into accelerations of ε_mach·size/τ², which must stay
    PRECISION_MARGIN times below SETTLE_ERROR of the accelerations' scale size·(ω² + |ε|) + |g|.
    Measured: the seven-link near its assembly limit at τ = 2.6 µs (a fifth of this floor, 12 µs)
    was off by 1e-3 everywhere where τ = 60 µs gave 1e-7; a generated 5 cm linkage at ω = 0.8
    rad/s improved from 1.3e-6 to 4e-7 when τ went from 1.5 to 0.75 of its floor (0.1 ms), so
    the floor is not set higher."""
    a_scale = acceleration_scale(size, omega, epsilon, gravity)
    return math.sqrt(PRECISION_MARGIN * EPS * size / (SETTLE_ERROR * max(a_scale, 1e-300)))


def sigma_min(model: mujoco.MjModel, jac: np.ndarray, drive_joint: str, size: float) -> float:
    """Smallest singular value of the loop Jacobian ``jac`` (rows, nv) over the non-driven
    joints, hinge columns scaled by 1/size [m] so that every column is dimensionless."""
    crank = model.joint(drive_joint).dofadr[0]
    cols = [i for i in range(model.nv) if i != crank]
    scale = np.array([1.0 / size if model.jnt_type[model.dof_jntid[i]] == mujoco.mjtJoint.mjJNT_HINGE else 1.0
                      for i in cols])
    j = jac[:, cols] * scale
    s = np.linalg.svd(j, compute_uv=False)
    return float(s[-1]) if s.size else 1.0


def crank_only(mech: Mechanism, omega: float) -> Settings:
    """Settings from the crank speed (τ = PHASE/ω) and, for the rotor, Σ (m·L² + I) over the
    links (L the mechanism's size) instead of J(φ): for mechanisms the closed form does not
    cover, so neither the loop forces nor J are known before the run."""
    from linkgen.families.planar.geometry import effective_mass_properties, link_shapes
    from linkgen.families.planar.pose import mechanism_size

    shapes = link_shapes(mech)
    size = mechanism_size(mech)
    j = sum(mp.mass * size**2 + mp.inertia
            for mp in (effective_mass_properties(mech, shapes, n) for n in mech.moving_links))
    tau = round_down(PHASE / max(omega, 1e-300))
    return Settings(timestep=tau / STEPS_PER_TAU, timeconst=tau, armature=round_down(ARMATURE_RATIO * j),
                    label="from the crank speed (no closed form for this structure)")


def apply(model: mujoco.MjModel, settings: Settings, drive_joint: str) -> None:
    """Put ``settings`` into a compiled model (timestep, integrator, solver, every connect's
    solref/solimp, the rotor inertia on the driven joint)."""
    model.opt.timestep = settings.timestep
    model.opt.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{settings.integrator.upper()}")
    model.opt.iterations = settings.iterations
    model.opt.tolerance = settings.tolerance
    model.eq_solref[:] = (settings.timeconst, settings.dampratio)
    model.eq_solimp[:, :3] = [float(x) for x in settings.solimp_text.split()][:3]
    if settings.solimp is not None and len(settings.solimp) == 5:
        model.eq_solimp[:, 3:5] = settings.solimp[3:5]
    set_armature(model, model.joint(drive_joint).dofadr[0], settings.armature)
    switch_off_servo(model)
    model.jnt_limited[model.joint(drive_joint).id] = 0  # the range limit is for a viewer; runs lead in past it


def set_armature(model: mujoco.MjModel, dof: int, armature: float) -> None:
    """Set a compiled model's armature [kg·m²] on one dof. MuJoCo also keeps the armature in
    ``dof_M0`` (the mass matrix diagonal at qpos0, computed at compile time), which it uses as
    the whole inertia of a "simple" body (a crank alone turning about its centre of mass): that
    copy is moved by the same amount, and nothing else of the compiled constants changes."""
    model.dof_M0[dof] += armature - model.dof_armature[dof]
    model.dof_armature[dof] = armature


__all__ = ["Scales", "Settings", "apply", "check_budget", "derive", "set_armature", "round_down", "scan_angles", "sigma_min"]
