"""A spatial four-bar's design summary: the output's swing or stroke with its limit positions
(where the first transfer function dq/dφ changes sign, refined by Brent's method), the time
ratio of a crank-rocker (or crank-slider), and the peak balancing torque and pair forces over a
turn at the drive's ω and ε."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from linkgen.spatial.description import SpatialMechanism
from linkgen.spatial.forces import forces
from linkgen.spatial.kinematics import assembled_chain, solve

# Crank angles over a turn at which the output is scanned for its limit positions (every 0.1°).
SCAN = 3600
# Limit positions are refined to this crank angle [rad] (Brent's method on dq/dφ).
ANGLE_TOL = 1e-13


@dataclass(frozen=True)
class SpatialSummary:
    """``unit`` "rad" (a rocker) or "m" (a slider); ``limits``: (kind "min"/"max", crank angle
    [rad], the output's turn from its sketch there) in crank order; ``swing`` = max − min;
    ``time_ratio``: the crank's turn from min to max over its turn from max to min (None without
    one working and one return stroke); peaks: (value, crank angle [rad])."""

    model: str
    kind: str
    output: str
    unit: str
    limits: tuple
    swing: float | None
    time_ratio: float | None
    peak_torque: tuple[float, float]
    peak_pair_forces: dict
    indeterminate: int

    def to_dict(self) -> dict:
        return {"model": self.model, "kind": self.kind, "output": self.output, "unit": self.unit,
                "limits": [{"kind": k, "phi": a, "value": v} for k, a, v in self.limits], "swing": self.swing,
                "time_ratio": self.time_ratio,
                "peak_balancing_torque": {"value": self.peak_torque[0], "phi": self.peak_torque[1]},
                "peak_pair_forces": {n: {"value": v, "phi": a} for n, (v, a) in self.peak_pair_forces.items()},
                "statically_indeterminate": self.indeterminate}


def summarize(mech: SpatialMechanism) -> SpatialSummary:
    """The summary over one turn of the crank (it must assemble over the whole turn)."""
    chain = assembled_chain(mech)
    phi = np.linspace(0.0, 2 * math.pi, SCAN, endpoint=False)
    k = solve(mech, phi, chain)
    d1 = k.turn.d[1]
    limits = []
    for i in np.flatnonzero(np.sign(d1) != np.sign(np.roll(d1, -1))):
        a, b = phi[i], phi[i] + 2 * math.pi / SCAN
        root = brentq(lambda x: float(solve(mech, [x], chain).turn.d[1][0]), a, b, xtol=ANGLE_TOL)
        at = solve(mech, [root], chain)
        kind = "max" if at.turn.d[2][0] < 0 else "min"
        limits.append((kind, math.remainder(root, 2 * math.pi) % (2 * math.pi), float(at.turn.d[0][0])))
    limits.sort(key=lambda x: x[1])
    values = [v for _, _, v in limits]
    swing = float(max(values) - min(values)) if limits else None  # None: the output turns fully
    ratio = None
    if len(limits) == 2:
        lo = next(a for kind, a, _ in limits if kind == "min")
        hi = next(a for kind, a, _ in limits if kind == "max")
        work = (hi - lo) % (2 * math.pi)
        ratio = work / (2 * math.pi - work)
    f = forces(mech, phi, mech.drive.omega, mech.drive.epsilon, motion=k)
    i = int(np.argmax(np.abs(f.balancing_torque)))
    peaks = {}
    if f.indeterminate == 0:
        for name, r in f.reactions.items():
            mag = np.linalg.norm(r.force, axis=1)
            j = int(np.argmax(mag))
            peaks[name] = (float(mag[j]), float(phi[j]))
    return SpatialSummary(mech.name, chain.kind, chain.pair_out, "m" if chain.output_slides else "rad", tuple(limits),
                          swing, ratio, (float(f.balancing_torque[i]), float(phi[i])), peaks, f.indeterminate)


__all__ = ["ANGLE_TOL", "SCAN", "SpatialSummary", "summarize"]
