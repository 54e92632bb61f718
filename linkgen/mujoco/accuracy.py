"""MuJoCo's accuracy at a user's settings, predicted from the closed form before any step.

The crank is driven at its speed (the rotor inertia holds it) and every loop is closed by a
``connect``. MuJoCo solves each equality row with f = −(A + R)⁻¹(a0 − aref), A = J·M⁻¹·Jᵀ,
R = (1 − d)/d·diagApprox, aref = −B·ṙ − K·d·r, with (its constraint model)

    K = 1/(dmax²·τ²·ζ²),  B = 2/(dmax·τ),  τ = max(solref timeconst, 2·timestep) (refsafe),

and d = d(|r|) the impedance of ``solimp`` (dmin at r = 0, dmax past the width; r the norm of
the connect's 3 rows). Where the loop follows the closed form (a1 = J·q̈ + J̇·q̇ = 0), the force
is the closed form's λ, so R·λ = aref = −B·ṙ − K·d·r. The gap holds still where ṙ = −u, u the
velocity the integrator adds to the gap unseen by ṙ, so per row

    r = (B·u − R·λ)/(K·d).

Euler and implicitfast step the positions with the step's end velocity, along the loop's
tangent at the step's end, and open the loop by −½·dt²·J̇·q̇ a step unseen by ṙ = J·q̇: u =
−½·dt·J̇·q̇ (RK4: fourth order, u = 0). The gap reaches this value through the loop's own
dynamics (``mujoco.gap_dynamics``), the rows coupled through A: a1 = P·a0 + Q·aref with
Q = A·(A + R)⁻¹, so ṡ = Q·K·d·(r_λ − r) − Q·B·s, ṙ = s + u (s = J·q̇, r_λ = −R·λ/(K·d)), stepped
as the integrator steps it: a lag where ω·τ is not small, a slow and lightly damped mode where
A is small (along the heavy crank), and the start-up transient where a run starts with its
loops closed. The non-driven joints move by δq = J_nc⁻¹·r (J_nc the in-plane loop
Jacobian without the crank column, square for a mechanism of mobility 1), and their velocities so
that the gap velocity MuJoCo sees, J·q̇, is the s of those dynamics (for Euler and implicitfast −u
where the gap holds still: their velocity is the step's backward difference, ½·dt·q̈ behind).
MuJoCo's own forward dynamics at that predicted state (no step taken), with the loops'
acceleration set to that of the gap dynamics (``loop_terms.forces_at``), gives the reactions and
the crank torque it will report; ``sample_errors`` compares them with the closed
form exactly as it compares a run's samples.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from linkgen.model.turn import full_turn
from linkgen.errors import SimulationError, UnsupportedError
from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.kinematics import solve
from linkgen.families.planar.kinetostatics import forces
from linkgen.mujoco.gap_dynamics import gap_states, impedance, quasi_static_gap, rate, reference_gains
from linkgen.mujoco.forces import ForceSamples
from linkgen.mujoco.loop_terms import diag_approx, forces_at, jdot
from linkgen.mujoco.log import no_log_file
from linkgen.mujoco.loops import closure_forces, closure_jacobian, mechanism_size
from linkgen.mujoco.options import EVALUATIONS, PLACEHOLDER, SOLVER_ITERATIONS, Settings
from linkgen.mujoco.sample import Samples, moving_points
from linkgen.mujoco.state import joint_states
from linkgen.mujoco.timing import crank_phi, crank_time

# Crank angles the prediction evaluates MuJoCo's forward dynamics at (over the drive range).
SCAN = 240
# A predicted sample within this angle [rad] of a left-out window's edge is left out with it
# (rounding of the window's bounds, which are the run's own sample angles).
WINDOW_EDGE = 1e-9
# The quantities, each relative: loop gap / size, point position error / size, reaction error /
# peak reaction, crank-torque error / peak crank torque.
QUANTITIES = ("gap", "position", "reaction", "torque")
@dataclass(frozen=True)
class Errors:
    """The largest errors over the range, each relative (``QUANTITIES``): loop gap and point
    positions to the mechanism's size, reactions to the peak reaction, the crank torque to its
    peak."""

    gap: float
    position: float
    reaction: float
    torque: float

    @property
    def worst(self) -> float:
        return max(self.gap, self.position, self.reaction, self.torque)

    def to_dict(self) -> dict:
        return {q: (float(getattr(self, q)) if math.isfinite(getattr(self, q)) else None) for q in QUANTITIES}


@dataclass(frozen=True)
class AccuracyPrediction:
    """The predicted errors (``errors``) at ``settings`` for the crank driven at ``omega``
    [rad/s]; ``timeconst`` [s] the loop time constant MuJoCo uses (refsafe: ≥ 2·timestep),
    ``size`` [m], ``steps_per_second`` MuJoCo steps per second of simulated time and
    ``evaluations_per_second`` (RK4 evaluates the dynamics four times a step)."""

    settings: Settings
    timeconst: float
    omega: float
    size: float
    errors: Errors

    @property
    def steps_per_second(self) -> float:
        return 1.0 / self.settings.timestep

    @property
    def evaluations_per_second(self) -> float:
        return EVALUATIONS[self.settings.integrator] / self.settings.timestep

    def to_dict(self) -> dict:
        return {"settings": settings_dict(self.settings), "timeconst": self.timeconst, "omega": self.omega,
                "size": self.size, "errors": self.errors.to_dict(), "steps_per_second": self.steps_per_second,
                "evaluations_per_second": self.evaluations_per_second}

    def text(self) -> str:
        e = self.errors
        return (f"{settings_text(self.settings)}: predicted loop gap {e.gap:.2g} of the size, positions {e.position:.2g}, "
                f"reactions {e.reaction:.2g} of the peak, crank torque {e.torque:.2g} of its peak")


def settings_dict(s: Settings) -> dict:
    return {"timestep": s.timestep, "integrator": s.integrator, "solref": [s.timeconst, s.dampratio],
            "solimp": [float(x) for x in s.solimp_text.split()]}


def settings_text(s: Settings) -> str:
    return f"timestep {s.timestep:.3g} s, {s.integrator}, solref \"{s.timeconst:.3g} {s.dampratio:g}\""


def effective_timeconst(settings: Settings) -> float:
    """The loop time constant MuJoCo uses: solref's, raised to 2·timestep (its refsafe clamp)."""
    return max(settings.timeconst, 2.0 * settings.timestep)


def sample_errors(asm: Assembly, s: Samples) -> Errors:
    """The relative errors (``Errors``) of MuJoCo's samples against the closed form at their
    crank states (φ, ω, ε)."""
    return errors_of(asm, s.crank, {p: v[0] for p, v in s.points.items()}, s.forces, s.violation)


def errors_of(asm: Assembly, crank, points: dict[str, np.ndarray], got: ForceSamples, violation: np.ndarray) -> Errors:
    """``Errors`` of MuJoCo's point positions {name: (m, 2)}, forces and loop gaps (m,) at the
    crank states ``crank`` = (φ, ω, ε), each (m,), against the closed form there."""
    phi, w, e = crank
    mo = solve(asm, phi).motion(w, e)
    size = mechanism_size(asm)
    cf = forces(asm, phi, w, e)
    pos = max((float(np.linalg.norm(xy - mo.points[p][0], axis=1).max()) for p, xy in points.items()), default=0.0)
    peak = max([float(np.linalg.norm(r, axis=1).max()) for r in cf.reactions.values()]
               + [float(np.abs(n).max()) for n in cf.normal_force.values()] + [1e-300])
    reac = [float(np.linalg.norm(got.reactions[k] - v, axis=1).max()) for k, v in cf.reactions.items()]
    reac += [float(np.abs(got.normal_force[k] - v).max()) for k, v in cf.normal_force.items()]
    t_peak = max(float(np.abs(cf.balancing_torque).max()), 1e-300)
    torque = float(np.abs(got.balancing_torque - cf.balancing_torque).max())
    gap = float(np.max(violation)) if np.size(violation) else 0.0
    return Errors(gap / size, pos / size, max(reac, default=0.0) / peak, torque / t_peak)


def check_supported(asm: Assembly) -> None:
    """Refuse, in one line, what this prediction does not model: cams (a contact, not a loop),
    gears (a joint coupling), and a crank that does not turn forwards (ω ≤ 0: the run it
    predicts drives the crank at ω > 0)."""
    mech = asm.mechanism
    w = mech.drive.omega
    if not (math.isfinite(w) and w > 0):  # the run drives the crank forwards at ω (mujoco.simulate's own rule)
        raise SimulationError(f"drive.omega: must be > 0 rad/s for a MuJoCo run (it drives the crank forwards through "
                              f"its range), got {w!r}")
    if mech.cams or mech.gears:
        kind = "a cam (a contact)" if mech.cams else "a gear pair (a joint coupling)"
        raise UnsupportedError(f"check-settings predicts loops closed by revolute joints; this linkage has {kind}, "
                               "which it does not model")


@no_log_file()
def predict(asm: Assembly, settings: Settings, *, omega: float | None = None, epsilon: float | None = None,
            samples: int = SCAN, left_out: tuple[tuple[float, float], ...] = (), warm: bool = False) -> AccuracyPrediction:
    """The errors a run at ``settings`` (its rotor inertia holding the crank at ω [rad/s], default
    the description's, and ε [rad/s²]) is predicted to reach, from the closed form and MuJoCo's
    constraint model at the closed-form states: no MuJoCo step is taken. ``left_out``: crank-angle
    windows [rad] (from, to) the run leaves out of its comparison (its settling windows after the
    start and after load switches, fixed by the settings): the prediction leaves them out too.
    ``warm``: the run starts with its loops open by their settled gap (``mujoco.warm_start``, a
    validation run's start), so no start-up transient is predicted."""
    from linkgen.mujoco.mjcf import write_mjcf
    from linkgen.mujoco.settings import apply

    check_supported(asm)
    mech = asm.mechanism
    w = mech.drive.omega if omega is None else float(omega)
    eps = mech.drive.epsilon if epsilon is None else float(epsilon)
    model = mujoco.MjModel.from_xml_string(write_mjcf(asm, PLACEHOLDER))
    apply(model, settings, mech.drive.joint)
    full = full_turn(mech)
    phi = np.linspace(mech.drive.start, mech.drive.stop, samples, endpoint=not full)
    t = crank_time(phi, mech.drive.start, w, eps)
    cold = not warm and not full and _starts_cold(asm, settings, w, eps)
    if cold and samples > 1 and settings.timestep < t[1]:  # a run records its first state after one step
        t[0] = settings.timestep
        phi[0] = crank_phi(t[0], mech.drive.start, w, eps)
    wk = w + eps * t
    qpos, qvel, qacc = joint_states(asm, model, phi, wk, np.full(samples, eps))
    lam = np.array([closure_forces(asm, model, forces(asm, phi, wk, np.full(samples, eps)).reactions, k)
                    for k in range(samples)])
    tau = effective_timeconst(settings)
    k_ref, b_ref, solimp = reference_gains(settings)
    euler = settings.integrator != "RK4"
    data = mujoco.MjData(model)
    rows = lam.shape[1]
    r_phys, drift = np.zeros((samples, rows)), np.zeros((samples, rows))
    jac, jdvs, jda = np.zeros((samples, rows, model.nv)), np.zeros((samples, rows)), np.zeros((samples, rows))
    g, hd = np.zeros((samples, rows, rows)), np.zeros((samples, rows, rows))
    drive = model.joint(mech.drive.joint).dofadr[0]
    m_inv_jt = np.zeros((rows, model.nv))
    for k in range(samples):
        data.qpos[:], data.qvel[:] = qpos[k], qvel[k]
        mujoco.mj_forward(model, data)
        jac[k] = closure_jacobian(asm, model, data)
        diag = diag_approx(asm, model, data)
        jdvs[k], jda[k] = jdot(asm, model, data, qacc[k])
        drift[k] = -0.5 * settings.timestep * jdvs[k] if euler else 0.0
        r_qs, d = quasi_static_gap(lam[k], diag, drift[k], k_ref, b_ref, solimp)
        r_phys[k] = r_qs - b_ref * drift[k] / (k_ref * d)  # r_λ = −R·λ/(K·d): the gap without the drift
        if rows:  # a1 = P·a0 + Q·aref, Q = A·(A + R)⁻¹: ṡ = Q·K·d·(r_λ − r) − Q·B·s
            mujoco.mj_solveM(model, data, m_inv_jt, jac[k])
            a_mat = jac[k] @ m_inv_jt.T
            q = a_mat @ np.linalg.pinv(a_mat + np.diag((1.0 - d) / d * diag))  # pinv: a row no body moves (A and R nil) adds nothing
            g[k], hd[k] = q * (k_ref * d)[None, :], q * b_ref
    s_extra = jda + 0.5 * rate(jdvs, t, full)  # 2·H(q̇, q̈) + ½·T(q̇, q̇, q̇), d(J̇·q̇)/dt = T + 2·H(q̇, q̈)
    r, s_gap, a1 = gap_states(settings.integrator, r_phys, jdvs, s_extra, g, hd, settings.timestep, t,
                              max(abs(w), abs(wk[-1])), full, cold)
    cols = [i for i in range(model.nv) if i != drive]
    q_r, v_r = qpos.copy(), qvel.copy()  # hinge and slide joints only: qpos and qvel share their indices
    for k in range(samples):
        q_r[k, cols] += np.linalg.lstsq(jac[k][:, cols], r[k], rcond=None)[0]
        data.qpos[:] = q_r[k]
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        j_r = closure_jacobian(asm, model, data)  # the velocity MuJoCo sees at the reached state is s
        v_r[k, cols] += np.linalg.lstsq(j_r[:, cols], s_gap[k] - j_r @ qvel[k], rcond=None)[0]
    model.opt.iterations, model.opt.tolerance = SOLVER_ITERATIONS, 0.0  # converged, whatever the user's solver
    points = {p: np.zeros((samples, 2)) for p in moving_points(mech)}
    states, crank, gaps = [], np.zeros((3, samples)), np.zeros(samples)
    for k in range(samples):
        states.append(forces_at(asm, model, data, q_r[k], v_r[k], a1[k], settings.armature * eps, phi[k]))
        for p in points:
            points[p][k] = data.site(p).xpos[:2]
        crank[:, k] = phi[k], data.qvel[drive], data.qacc[drive]
        gaps[k] = float(np.abs(data.efc_pos[: data.ne]).max()) if data.ne else 0.0
    # A window opens at a load switch: the scan's two samples before it are left out too, as the
    # gap's velocity and acceleration there (central differences of central differences) reach
    # across the switch.
    before = 2.0 * abs(phi[1] - phi[0]) if samples > 1 else 0.0
    keep = ~np.any([(phi >= a - before - WINDOW_EDGE) & (phi <= b + WINDOW_EDGE) for a, b in left_out], axis=0) \
        if left_out else np.ones(samples, dtype=bool)
    if keep.sum() < 2:  # the run compares too few samples to say anything: predict over them all
        keep[:] = True
    idx = np.flatnonzero(keep)
    errors = errors_of(asm, crank[:, idx], {p: v[idx] for p, v in points.items()},
                       ForceSamples.stack([states[k] for k in idx]), gaps[idx])
    return AccuracyPrediction(settings, tau, w, mechanism_size(asm), errors)


def _starts_cold(asm: Assembly, settings: Settings, omega: float, epsilon: float) -> bool:
    """Whether a run starts at the range's first angle with its loops closed (no gap yet): the
    mechanism does not assemble over the lead-in before it (``mujoco.simulate``), so the loops'
    start-up transient falls on the first samples."""
    from linkgen.errors import AssemblyError, SingularityError
    from linkgen.mujoco.timing import LEAD_TARGET, crank_phi, settle_window

    mech = asm.mechanism
    lead = crank_phi(-settle_window(settings, None, epsilon, LEAD_TARGET, float(np.hypot(*mech.gravity))),
                     mech.drive.start, omega, epsilon)
    try:
        solve(asm, np.linspace(lead, mech.drive.start, 16))
    except (AssemblyError, SingularityError):
        return True
    return False


__all__ = ["AccuracyPrediction", "EVALUATIONS", "Errors", "QUANTITIES", "effective_timeconst", "impedance", "predict",
           "sample_errors", "settings_dict", "settings_text"]
