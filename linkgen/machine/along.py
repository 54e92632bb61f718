"""A machine run's samples along time, beyond the crank's: every link's angle and angular
velocity, every point's position and velocity, and the kinetostatics along the real motion (the
balancing torque and every pair's reaction at the ODE's φ, ω and its own ε at each sample), as
columns named as everywhere else (``name.quantity[.x|.y] [unit]``, ``linkgen.model.results``).

Along the real motion the balancing torque is what the drive must add to the mechanism's own
loads and inertia at that state: the motor's torque at the crank less the rotor's and flywheel's
inertia torque and the process load (0 for free motion), which ``tests/test_machine_state.py``
checks."""

from __future__ import annotations

import numpy as np

from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.forces_result import forces
from linkgen.families.planar.motion_result import kinematics
from linkgen.model.names import GROUND

# What a run can add to its samples: option name → what it adds.
KINDS = {"links": "every moving link's angle [rad] and angular velocity [rad/s]",
         "points": "every point's position [m] and velocity [m/s]",
         "reactions": "the balancing torque [N·m] and every pair's reaction [N] along the real motion"}


def along_time(asm: Assembly, phi: np.ndarray, omega: np.ndarray, epsilon: np.ndarray,
               kinds=tuple(KINDS)) -> dict[str, np.ndarray]:
    """Columns (n,) at the run's samples: crank angles φ [rad], speeds ω [rad/s] and the ODE's
    accelerations ε [rad/s²] (each (n,)), for each of ``kinds`` (see KINDS)."""
    cols: dict[str, np.ndarray] = {}
    if "links" in kinds or "points" in kinds:
        kin = kinematics(asm, phi, omega, epsilon)
        if "links" in kinds:
            for n, q in kin.links.items():
                if n != GROUND:  # the frame does not move
                    cols |= q.columns(n, ("angle", "angular_velocity"))
        if "points" in kinds:
            for n, q in kin.points.items():
                cols |= q.columns(n, ("position", "velocity"))
    if "reactions" in kinds:
        f = forces(asm, phi, omega, epsilon)
        cols["balancing_torque [N·m]"] = np.asarray(f.balancing_torque, dtype=float) * np.ones_like(phi)
        cols |= {k: v for k, v in f.columns().items() if k != "phi [rad]" and k != "singular"
                 and not k.startswith(("balancing_torque", "power_balance_torque", "reduced_"))}
    return cols


__all__ = ["KINDS", "along_time"]
