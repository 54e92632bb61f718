"""The loop-free model's dynamics against the closed form: how far MuJoCo's couplings lag when
they move (``lag``), and how near its driving torque is to the closed form's: MuJoCo's inverse
dynamics of the coupled model along its couplings, at the drive's ω and no acceleration.

The couplings hold positions to their stated error, but a torque needs their slopes and
curvatures too (J(φ) and its derivative, the loads' transfer functions), which a quartic misses
most at the ends of its range. Along the couplings the model has one degree of freedom; the
torque on the crank that moves it at (φ, ω, ε = 0) is, by virtual work, Σ_j q_j′·(qfrc_inverse_j −
(Jᵀ·xfrc)_j), q_j′ = dq_j/dφ from the chain of quartics and qfrc_inverse MuJoCo's inverse dynamics
at q, q̇ = ω·q′, q̈ = ω²·q″ with the couplings and limits switched off (they would add only the soft
constraint's own force), the description's loads applied as linkgen's runs apply them. Against the
closed form's balancing torque at the same φ and ω this is the model's error with MuJoCo's soft
gap left out; ``validation/coupling_study.py`` measures the same error in a MuJoCo run.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np

from linkgen.families.planar.assembly import Assembly
from linkgen.mujoco.coupling import Coupling

# Crank angles over the drive range at which the torque is compared.
TORQUE_SAMPLES = 241
# The crank torque's error is also given over this middle fraction of the range (away from the
# quartics' ends, where their slopes and curvatures err most).
INNER = 0.8


@dataclass(frozen=True)
class TorqueError:
    """Largest |coupled model's torque − closed form's balancing torque| [N·m] over the range,
    its crank angle [rad], the same over the middle INNER of the range, the closed form's largest
    |torque| [N·m], at crank speed ``omega`` [rad/s]."""

    max_error: float
    at: float
    inner: float
    peak: float
    omega: float

    def text(self) -> str:
        rel = self.max_error / self.peak if self.peak > 0 else float("inf")
        return (f"crank torque at {self.omega:g} rad/s within {self.max_error:.2g} N·m of the closed form "
                f"({rel:.2g} of its {self.peak:.3g} N·m peak; {self.inner:.2g} N·m over the middle {INNER:.0%} "
                f"of the range)")




def lag(c: Coupling, timeconst: float, omega: float, samples: int = TORQUE_SAMPLES) -> dict[str, float]:
    """Each coupled joint's largest lag [rad or m] over the range when the crank turns at ω
    [rad/s] and the couplings have MuJoCo's time constant τ = ``timeconst`` [s]: MuJoCo's
    joint equality leaves out the curvature term p″(x)·ẋ² of y = p(x) (measured on mujoco
    4.0: the equality rows' efc_pos of the seven-link at 4 rad/s matched τ²·p″·ẋ² within 35 %,
    sign and all), so its spring of stiffness 1/τ² holds y that far behind: ≈ τ²·|p″(x)|·ẋ²."""
    chain = c.chain(np.linspace(*c.drive_range, samples))
    refs = {c.drive: c.phi_ref} | {j.name: j.ref for j in c.joints}
    P = np.polynomial.polynomial
    out = {}
    for j in c.joints:
        x, dx, _ = chain[j.argument]
        curvature = P.polyval(x - refs[j.argument], P.polyder(np.array(j.fit.coef), 2))
        out[j.name] = float(np.max(timeconst ** 2 * np.abs(curvature) * (dx * omega) ** 2))
    return out


def coupled_torque(asm: Assembly, c: Coupling, model: mujoco.MjModel, phi: np.ndarray, omega: float) -> np.ndarray:
    """The coupled model's crank torque (n,) [N·m] at crank angles φ (n,) and speed ω (module
    docstring). ``model`` is the compiled coupled MJCF; it is not changed."""
    from linkgen.mujoco.forces import applied_generalized, apply_loads

    m = model
    flags = m.opt.disableflags
    m.opt.disableflags = flags | mujoco.mjtDisableBit.mjDSBL_EQUALITY | mujoco.mjtDisableBit.mjDSBL_LIMIT
    try:
        d = mujoco.MjData(m)
        chain = c.chain(phi)
        dofs = {name: (m.joint(name).qposadr[0], m.joint(name).dofadr[0]) for name in chain}
        out = np.zeros(phi.shape[0])
        for k in range(phi.shape[0]):
            slope = np.zeros(m.nv)
            for name, (q, v) in dofs.items():
                value, d1, d2 = (a[k] for a in chain[name])
                d.qpos[q], d.qvel[v], d.qacc[v] = value, omega * d1, omega * omega * d2
                slope[v] = d1
            mujoco.mj_inverse(m, d)
            apply_loads(asm, m, d, float(phi[k]))
            out[k] = slope @ (d.qfrc_inverse - applied_generalized(m, d))
        return out
    finally:
        m.opt.disableflags = flags


def torque_error(asm: Assembly, c: Coupling, model: mujoco.MjModel) -> TorqueError:
    """The coupled model's torque against the closed form's over the drive range at the drive's ω."""
    from linkgen.families.planar.kinetostatics import forces

    omega = asm.mechanism.drive.omega
    phi = np.linspace(*c.drive_range, TORQUE_SAMPLES)
    cf = np.asarray(forces(asm, phi, omega, 0.0).balancing_torque)
    err = np.abs(coupled_torque(asm, c, model, phi, omega) - cf)
    mid, half = 0.5 * (phi[0] + phi[-1]), 0.5 * (phi[-1] - phi[0])
    k = int(np.argmax(err))
    return TorqueError(float(err[k]), float(phi[k]), float(err[np.abs(phi - mid) <= INNER * half].max()),
                       float(np.abs(cf).max()), float(omega))


__all__ = ["INNER", "TORQUE_SAMPLES", "TorqueError", "coupled_torque", "lag", "torque_error"]
