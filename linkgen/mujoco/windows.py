"""Which of a run's samples are compared: the windows left out after its start and its load
switches (``LeftOut``), fixed by the settings before any step, and whether a lead-in before the
range may pass nearer an assembly limit than the range does."""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np

from linkgen.families.planar.assembly import Assembly
from linkgen.mujoco.loops import closure_jacobian, mechanism_size
from linkgen.mujoco.posed import Posed
from linkgen.mujoco.settings import sigma_min
from linkgen.mujoco.state import joint_states
from linkgen.mujoco.timing import crank_time, switch_angles

# A lead-in may pass this many times nearer an assembly limit (in the loops' conditioning σ)
# than the range's closest pose: the lead-in's window, sized on the range (LEAD_TARGET, 1000×
# below what the samples need), covers an amplification of 1/σ by 2 with room. Measured: the
# seven-link's lead-in at 0.79 of its σ_min validates; a generated slow crank whose lead-in fell
# to 0.03 of it started its range 100× off its prediction (fidelity corpus seed 23).
LEAD_SIGMA = 2.0
@dataclass(frozen=True)
class LeftOut:
    """Samples left out of comparisons: why ("start", "load switch"), the crank-angle range
    [rad] and how many."""

    reason: str
    phi_from: float
    phi_to: float
    samples: int

    def to_json(self) -> dict:
        return {"reason": self.reason, "phi_from": self.phi_from, "phi_to": self.phi_to, "samples": self.samples}


def switch_windows(asm: Assembly | Posed, phi_a: float, phi_b: float, w0: float, eps: float, samples: int,
                   full: bool, dt: float, window: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, list]:
    """A run's sample angles [rad] and times [s] over the range, which are kept, and the
    ``LeftOut`` windows after its load switches (each ``window`` [s] long, from a step before
    the switch): fixed by the settings before any step."""
    mech = asm.mechanism
    phi_s = np.linspace(phi_a, phi_b, samples, endpoint=not full)
    t_s = crank_time(phi_s, phi_a, w0, eps)
    keep = np.ones(samples, dtype=bool)
    left: list[LeftOut] = []
    switches = switch_angles(mech, phi_a, phi_b)
    if getattr(mech, "frictions", ()):  # a pair's friction turns round where its relative motion does
        from linkgen.mujoco.friction import friction_switches

        switches = sorted(switches + friction_switches(asm, phi_a, phi_b))
    for sw in switches:
        t_sw = float(crank_time(np.array([sw]), phi_a, w0, eps)[0])
        # a sample is read at its nearest step, up to dt/2 from its time: one due just before the
        # switch may be read after it
        hit = (t_s >= t_sw - dt) & (t_s <= t_sw + window)
        if hit.any():
            keep &= ~hit
            left.append(LeftOut("load switch", sw, float(phi_s[hit].max()), int(hit.sum())))
    return phi_s, t_s, keep, left


def lead_sigma(asm: Assembly | Posed, model: mujoco.MjModel, phi: np.ndarray) -> float:
    """The loops' smallest conditioning σ (``mujoco.settings.sigma_min``) over a lead-in's crank
    angles ``phi`` [rad] before the range: where it falls below the range's own, the lead-in
    would pass nearer an assembly limit than the range does, where the soft loops' start-up
    transient is amplified past what the range's scan sized the lead-in for."""
    if isinstance(asm, Posed):
        return math.inf
    qpos, qvel, _ = joint_states(asm, model, phi, np.ones_like(phi), np.zeros_like(phi))
    data = mujoco.MjData(model)
    size = mechanism_size(asm)
    out = math.inf
    for k in range(phi.shape[0]):
        data.qpos[:], data.qvel[:] = qpos[k], qvel[k]
        mujoco.mj_kinematics(model, data)
        mujoco.mj_comPos(model, data)
        jac = closure_jacobian(asm, model, data)
        if jac.shape[0]:
            out = min(out, sigma_min(model, jac, asm.mechanism.drive.joint, size))
    return out


__all__ = ["LEAD_SIGMA", "LeftOut", "lead_sigma", "switch_windows"]
