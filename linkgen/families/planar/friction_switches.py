"""Where a linkage's Coulomb friction (``[[friction]]``, ``planar.friction``) changes direction: the
crank angles at which a pair's relative rate changes sign, so its friction jumps by twice its size
(a load switch for MuJoCo's settling, a restart of the machine's integration)."""

from __future__ import annotations

import numpy as np

from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.kinematics import solve
from linkgen.model.names import GROUND


# The grid [rad] on which the pairs' relative rates are searched for sign changes (each then refined
# by bisection to SWITCH_BISECTIONS halvings: 0.25°/2^40 ≈ 4e-15 rad, float64's resolution of an angle).
SWITCH_GRID = np.radians(0.25)
SWITCH_BISECTIONS = 40


def friction_switches(asm: Assembly, phi_a: float, phi_b: float) -> list[float]:
    """Crank angles in [φa, φb] where a pair's friction changes direction (its relative rate
    changes sign): the friction jumps there by twice its size, a load switch for a run's
    settling (``mujoco.timing.switch_angles``) and where the machine's integration restarts
    (``machine.machine``)."""
    mech = asm.mechanism
    if not mech.frictions or phi_b <= phi_a:
        return []

    def rates(phi: np.ndarray) -> np.ndarray:
        kin = solve(asm, phi, on_singular="mark")
        out = []
        for fr in mech.frictions:
            if fr.pin_radius is not None:
                a, b = (0.0 if n == GROUND else kin.links[n].angle.d1 for n in mech.revolute(fr.pair).links)
                out.append(np.broadcast_to(a - b, phi.shape))
            else:
                out.append(kin.sliders[fr.pair].d1)
        return np.array(out)  # (pairs, n)

    grid = np.linspace(phi_a, phi_b, max(2, int(np.ceil((phi_b - phi_a) / SWITCH_GRID)) + 1))
    r = rates(grid)
    found = []
    for i, k in zip(*np.nonzero(np.sign(r[:, :-1]) * np.sign(r[:, 1:]) < 0)):
        lo, hi = grid[k], grid[k + 1]
        for _ in range(SWITCH_BISECTIONS):
            mid = 0.5 * (lo + hi)
            if np.sign(rates(np.array([mid]))[i, 0]) == np.sign(r[i, k]):
                lo = mid
            else:
                hi = mid
        found.append(float(0.5 * (lo + hi)))
    found += [float(g) for i, k in zip(*np.nonzero(r == 0)) for g in (grid[k],)]
    return sorted(set(found))


__all__ = ["SWITCH_BISECTIONS", "SWITCH_GRID", "friction_switches"]
