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

from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from linkgen.extrema import peak, samples, stationary
from linkgen.families.spatial.description import SpatialMechanism
from linkgen.families.spatial.forces import forces
from linkgen.families.spatial.kinematics import assembled_chain, solve
from linkgen.model.summary import Extreme, Limit, Output, summary_dict

# The kinds driven by a slider.
INPUT_SLIDES = ("PSSR", "PSSP")
# Crank angles over a turn at which the output is scanned for its limit positions (every 0.1°).
SCAN = 3600
# Limit positions are refined to this crank angle [rad] (Brent's method on dq/dφ).
ANGLE_TOL = 1e-13


@dataclass(frozen=True)
class SpatialSummary:
    """The keys every family's summary shares (``linkgen.model.summary``) and the spatial ones:
    ``kind`` (RSSR, RSSP, Bennett, ...) and ``statically_indeterminate`` (the degree of static
    indeterminacy; the pair forces are not summarised when it is not 0, ``forces_note`` says so).

    The output is keyed as in a planar linkage: a turning output by its link's name, a sliding
    one by its prismatic pair's name (a planar four-bar written as an RSSR gives the planar
    summary's key, e.g. "rocker")."""

    model: str
    omega: float
    epsilon: float
    drive_range: tuple[float, float]
    kind: str
    outputs: Mapping[str, Output]
    peak_balancing_torque: Extreme
    peak_reactions: Mapping[str, Extreme] = field(default_factory=dict)
    forces_note: str | None = None
    statically_indeterminate: int = 0

    @property
    def input_slides(self) -> bool:
        """The input is a slider (PSSR, PSSP): its coordinate s [m] stands for φ, its balancing
        force [N] for the torque."""
        return self.kind in INPUT_SLIDES

    @property
    def units(self) -> dict[str, str]:
        if self.input_slides:
            return {"phi": "m", "drive_range": "m", "omega": "m/s", "epsilon": "m/s²", "slider": "m", "rocker": "rad",
                    "peak_balancing_torque": "N", "peak_reactions": "N"}
        return {"phi": "rad", "drive_range": "rad", "slider": "m", "rocker": "rad", "peak_balancing_torque": "N·m",
                "peak_reactions": "N"}

    def to_dict(self) -> dict:
        return summary_dict(self)

    def text(self) -> str:
        from linkgen.families.spatial.texts import summary_text

        return summary_text(self)


def summarize(mech: SpatialMechanism) -> SpatialSummary:
    """The summary over one turn of the crank (it must assemble over the whole turn), or over
    a prismatic input's range (limit positions inside it and its ends; no time ratio: the
    slider does not return by itself)."""
    chain = assembled_chain(mech)
    lo, hi = chain.input_range
    period = None if chain.input_slides else hi - lo  # a crank's turn wraps; a slider's range does not
    phi = samples(lo, hi, SCAN, periodic=period is not None)
    k = solve(mech, phi, chain)
    found = stationary(lambda x: solve(mech, x, chain).turn.d[1], phi, k.turn.d[1], period=period, xtol=ANGLE_TOL)
    ends = solve(mech, [e.x for e in found], chain) if found else None
    values = ends.output.d[0] if found else []  # the joint variable analyze gives, absolute
    limits = tuple(Limit(e.x, float(v), e.kind) for e, v in zip(found, values))
    swing = float(max(values) - min(values)) if limits else None  # None: the output turns fully
    strokes = ratio = None
    if len(limits) == 2 and period is not None:
        turn = period
        lo_at = next(x.phi for x in limits if x.kind == "min")
        hi_at = next(x.phi for x in limits if x.kind == "max")
        out = (hi_at - lo_at) % turn
        strokes = (out, turn - out)
        ratio = max(strokes) / min(strokes)
    slides = chain.output_slides
    output = Output("slider" if slides else "rocker", swing, limits, strokes, ratio)
    w, e = mech.drive.omega, mech.drive.epsilon
    f = forces(mech, phi, w, e, motion=k)
    t_at, _ = peak(lambda x: np.abs(forces(mech, x, w, e).balancing_torque), phi, np.abs(f.balancing_torque),
                   period=period)
    torque = float(abs(forces(mech, [t_at], w, e).balancing_torque[0]))
    peaks, note = {}, None
    if f.indeterminate == 0:
        for name, r in f.reactions.items():
            at, mag = peak(lambda x, n=name: np.linalg.norm(forces(mech, x, w, e).reactions[n].force, axis=1), phi,
                           np.linalg.norm(r.force, axis=1), period=period)
            peaks[name] = Extreme(mag, at)
    else:
        note = f"pair forces: statically indeterminate by {f.indeterminate}, not summarised"
    name = chain.pair_out if slides else chain.output  # a slider by its pair, a rocker by its link, as planar
    return SpatialSummary(mech.name, w, e, (lo, hi), chain.kind, {name: output}, Extreme(torque, t_at), peaks,
                          note, f.indeterminate)


def summary(mech: SpatialMechanism, omega: float | None = None, epsilon: float | None = None) -> SpatialSummary:
    """The spatial family's ``summary`` stage over one turn at ω and ε (default the drive's)."""
    from dataclasses import replace

    d = mech.drive
    drive = replace(d, omega=d.omega if omega is None else float(omega),
                    epsilon=d.epsilon if epsilon is None else float(epsilon))
    return summarize(mech if drive == d else replace(mech, drive=drive))


__all__ = ["ANGLE_TOL", "SCAN", "SpatialSummary", "summarize", "summary"]
