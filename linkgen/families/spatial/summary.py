"""A spatial four-bar's design summary: the output's swing or stroke with its limit positions
(where the first transfer function dq/dφ changes sign, the wrap from 2π to 0 included, refined
by Brent's method), the time ratio of a crank-rocker (or crank-slider), and the peak balancing
torque and pair forces over a turn at the drive's ω and ε, refined between samples — all by
``linkgen.extrema``.

The conventions are the planar summary's (docs/format.md, "Conventions"): a limit position's
value is the output's joint variable as ``analyze`` gives it (a rocker's absolute angle about its
axis, a slider's displacement along its line from the line's given point), the time ratio is
K = (the longer stroke's crank turn) / (the shorter's) ≥ 1, and a peak is a largest magnitude."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkgen.extrema import peak, samples, stationary
from linkgen.families.spatial.description import SpatialMechanism
from linkgen.families.spatial.forces import forces
from linkgen.families.spatial.kinematics import assembled_chain, solve

# Crank angles over a turn at which the output is scanned for its limit positions (every 0.1°).
SCAN = 3600
# Limit positions are refined to this crank angle [rad] (Brent's method on dq/dφ).
ANGLE_TOL = 1e-13


@dataclass(frozen=True)
class SpatialSummary:
    """``unit`` "rad" (a rocker) or "m" (a slider); ``limits``: (kind "min"/"max", crank angle
    [rad], the output's joint variable there: absolute angle [rad] or displacement [m]) in crank
    order; ``swing`` = max − min; ``strokes``: the crank's turn [rad] from min to max and from max
    to min, and ``time_ratio`` = the longer over the shorter (≥ 1 at constant crank speed; both
    None without exactly one working and one return stroke); ``peak_torque``: (largest
    |balancing torque| [N·m], crank angle [rad]); ``peak_pair_forces``: pair → (largest |force|
    [N], crank angle [rad])."""

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
    strokes: tuple[float, float] | None = None

    def to_dict(self) -> dict:
        return {"model": self.model, "kind": self.kind, "output": self.output, "unit": self.unit,
                "limits": [{"kind": k, "phi": a, "value": v} for k, a, v in self.limits], "swing": self.swing,
                "strokes": list(self.strokes) if self.strokes else None, "time_ratio": self.time_ratio,
                "peak_balancing_torque": {"value": self.peak_torque[0], "phi": self.peak_torque[1]},
                "peak_pair_forces": {n: {"value": v, "phi": a} for n, (v, a) in self.peak_pair_forces.items()},
                "statically_indeterminate": self.indeterminate}


def summarize(mech: SpatialMechanism) -> SpatialSummary:
    """The summary over one turn of the crank (it must assemble over the whole turn)."""
    chain = assembled_chain(mech)
    turn = 2 * math.pi
    phi = samples(0.0, turn, SCAN, periodic=True)
    k = solve(mech, phi, chain)
    found = stationary(lambda x: solve(mech, x, chain).turn.d[1], phi, k.turn.d[1], period=turn, xtol=ANGLE_TOL)
    ends = solve(mech, [e.x for e in found], chain) if found else None
    values = ends.output.d[0] if found else []  # the joint variable analyze gives, absolute
    limits = [(e.kind, e.x, float(v)) for e, v in zip(found, values)]
    swing = float(max(values) - min(values)) if limits else None  # None: the output turns fully
    strokes = ratio = None
    if len(limits) == 2:
        lo = next(a for kind, a, _ in limits if kind == "min")
        hi = next(a for kind, a, _ in limits if kind == "max")
        out = (hi - lo) % turn
        strokes = (out, turn - out)
        ratio = max(strokes) / min(strokes)
    w, e = mech.drive.omega, mech.drive.epsilon
    f = forces(mech, phi, w, e, motion=k)
    t_at, _ = peak(lambda x: np.abs(forces(mech, x, w, e).balancing_torque), phi, np.abs(f.balancing_torque),
                   period=turn)
    torque = float(abs(forces(mech, [t_at], w, e).balancing_torque[0]))
    peaks = {}
    if f.indeterminate == 0:
        for name, r in f.reactions.items():
            at, mag = peak(lambda x, n=name: np.linalg.norm(forces(mech, x, w, e).reactions[n].force, axis=1), phi,
                           np.linalg.norm(r.force, axis=1), period=turn)
            peaks[name] = (mag, at)
    return SpatialSummary(mech.name, chain.kind, chain.pair_out, "m" if chain.output_slides else "rad", tuple(limits),
                          swing, ratio, (torque, t_at), peaks, f.indeterminate, strokes)


__all__ = ["ANGLE_TOL", "SCAN", "SpatialSummary", "summarize"]
