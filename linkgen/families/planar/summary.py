"""The design summary a designer reads first: each slider's stroke and each rocker's swing with
their limit (dead-centre) positions, the time ratio of a working and a return stroke, each
group's least transmission angle, the peak balancing torque and joint reactions, and each
spring's peak force (``peak_spring_forces``: empty without springs), and with friction in the pairs
the power it takes out, its peak and its mean over the range's samples (None without friction).

Limit positions are the crank angles where an output's first transfer function changes sign,
found on a grid of SAMPLES angles — round the wrap from 2π to 0 over a full turn, and where it
is exactly 0 at a sample — and refined by Brent's method on the closed form to XTOL; the least
transmission angles and the peaks are refined between the samples too (``linkgen.extrema``).
The transmission angle of a class-II group is μ = arcsin|D|, D the group's normalised
transfer-function denominator (``groups``): the angle between the two links at the middle joint
of an RRR group (folded into 0..90°), between the rod and the guide's normal for an RRP group,
90° less the coulisse's offset angle for RPR, and the angle between the guides for PRP and RPP —
the textbook definitions, 90° best and 0° at a dead centre."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from linkgen.model.turn import full_turn
from linkgen.errors import LinkgenError
from linkgen.extrema import peak, stationary
from linkgen.model.summary import Extreme, Limit, Output, output_table, summary_dict
from linkgen.families.planar.description import GROUND
from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.groups import input_poses, place, solve_group
from linkgen.families.planar.kinematics import solve

# Grid over the drive's range for extrema and peaks: one every 0.1° over a full turn.
SAMPLES = 3601
# Limit positions are refined to this crank angle [rad] (Brent's method; the transfer function
# is smooth, so the bracket closes to a few ulps of 2π).
XTOL = 1e-13
# A full turn is a period of a quantity whose values at its two ends agree to this (relative to
# its size; the closed form repeats to ~1e-15): else its range's ends count as extremes.
PERIODIC_TOL = 1e-9


@dataclass(frozen=True)
class DesignSummary:
    """Everything above for one mechanism over its drive's range (SI units, radians), in the
    keys every family's summary shares (``linkgen.model.summary``) and the planar family's own
    ``min_transmission_angle``: group label → ``Extreme`` (least angle [rad], its φ).

    ``peak_balancing_torque`` is None, ``peak_reactions`` empty and ``forces_note`` says why when
    the kinetostatics cannot be solved over the whole range (a dead centre inside it)."""

    model: str
    omega: float
    epsilon: float
    drive_range: tuple[float, float]
    outputs: Mapping[str, Output]
    peak_balancing_torque: Extreme | None
    peak_reactions: Mapping[str, Extreme] = field(default_factory=dict)
    forces_note: str | None = None
    min_transmission_angle: Mapping[str, Extreme] = field(default_factory=dict)
    peak_spring_forces: Mapping[str, Extreme] = field(default_factory=dict)
    peak_friction_power: Extreme | None = None
    mean_friction_power: float | None = None
    stroke: bool = False  # a prismatic drive: phi and drive_range are strokes [m], the balancing load a force [N]
    drive_joint: str = ""  # the driven pair

    @property
    def units(self) -> dict[str, str]:
        out = {"phi": "rad", "drive_range": "rad", "slider": "m", "rocker": "rad", "peak_balancing_torque": "N·m",
               "peak_reactions": "N", "min_transmission_angle": "rad",
               "peak_spring_forces": "N (spring[i]) or N·m (torsion_spring[i])", "peak_friction_power": "W",
               "mean_friction_power": "W"}
        return out | ({"phi": "m", "drive_range": "m", "peak_balancing_torque": "N", "omega": "m/s",
                       "epsilon": "m/s²"} if self.stroke else {})

    def to_dict(self) -> dict:
        return summary_dict(self)

    def text(self) -> str:
        from linkgen.families.planar.texts import summary_text

        return summary_text(self)


def _grid(asm: Assembly) -> tuple[np.ndarray, bool]:
    """SAMPLES crank angles over the drive's range, both ends included, and whether it is a full
    turn (or more)."""
    d = asm.mechanism.drive
    full = full_turn(asm.mechanism)
    return np.linspace(d.start, d.stop, SAMPLES), full


def _period(phi: np.ndarray, v: np.ndarray) -> float | None:
    """2π if the crank angles ``phi`` span one turn and the quantity ``v`` sampled there comes
    back to its first value (a gear train of a non-integer ratio does not), else None: the
    range's ends are then extremes of their own."""
    if abs(float(phi[-1] - phi[0]) - 2 * math.pi) > 1e-12:
        return None
    scale = float(np.max(np.abs(v))) if v.size else 0.0
    return 2 * math.pi if abs(float(v[-1] - v[0])) <= PERIODIC_TOL * max(scale, 1.0) else None


def _on_range(phi: np.ndarray, period: float | None, fx: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The samples to search: without the repeated end over a period."""
    return (phi[:-1], fx[:-1]) if period else (phi, fx)


def _output(asm: Assembly, kind: str, phi: np.ndarray, full: bool, pick) -> Output:
    """``pick(kin)`` → (value (n,), d/dφ (n,)) of the output."""
    kin = solve(asm, phi, on_singular="mark")
    v, d1 = pick(kin)
    if kind == "rocker":
        v = np.unwrap(v)
        if full and abs(v[-1] - v[0]) > math.pi:  # turns fully round: no swing, no limits
            return Output(kind, None, ())
    period = _period(phi, v)
    x, dx = _on_range(phi, period, d1)
    found = stationary(lambda p: pick(solve(asm, p, on_singular="mark"))[1], x, dx, period=period, xtol=XTOL)
    at = np.array([e.x for e in found])
    values = pick(solve(asm, at, on_singular="mark"))[0] if found else np.zeros(0)
    extremes = []
    for e, value in zip(found, values):
        if kind == "rocker":  # on the unwrapped branch of the samples
            k = min(int(np.searchsorted(phi, e.x)), len(v) - 1)
            value = value + 2 * math.pi * round((v[k] - value) / (2 * math.pi))
        extremes.append((e, float(value)))
    limits = [Limit(e.x, value, e.kind) for e, value in extremes if not e.end]
    travel = float(np.max(v) - np.min(v))
    if extremes:
        travel = max(value for _, value in extremes) - min(value for _, value in extremes)
    strokes = ratio = None
    if period and len(limits) == 2:
        lo, hi = (limits[0], limits[1]) if limits[0].kind == "min" else (limits[1], limits[0])
        out = (hi.phi - lo.phi) % (2 * math.pi)
        strokes = (out, 2 * math.pi - out)
        ratio = max(strokes) / min(strokes)
    return Output(kind, travel, tuple(limits), strokes, ratio)


def _peak(f, phi: np.ndarray, fx: np.ndarray, kind: str = "max") -> tuple[float, float]:
    """(crank angle, value) of the refined peak of ``f`` (vectorised over crank angles)."""
    period = _period(phi, fx)
    x, fx = _on_range(phi, period, fx)
    return peak(f, x, fx, kind=kind, period=period)


def transmission_angles(asm: Assembly, phi: np.ndarray) -> dict[str, np.ndarray]:
    """μ (n,) [rad] of every class-II group at crank angles ``phi`` (n,) (module docstring)."""
    mech = asm.mechanism
    poses = input_poses(mech, asm.structure, asm.shapes, phi)
    out = {}
    with np.errstate(invalid="ignore", divide="ignore"):
        for group, m in zip(asm.structure.groups, asm.branches):
            p1, p2, res = solve_group(group, m, poses, asm.shapes, asm.guides, mech, phi)
            den = np.abs(np.broadcast_to(res.denominator, phi.shape))
            out[group.label] = np.arcsin(np.clip(den, 0.0, 1.0))
            place(group, poses, p1, p2, res)
    return out


def summarize(asm: Assembly, omega: float | None = None, epsilon: float | None = None) -> DesignSummary:
    """The design summary over the drive's range at crank speed ω [rad/s] and acceleration
    ε [rad/s²] (default the drive's).

    Raises:
        AssemblyError: the mechanism does not assemble over its whole range.
    """
    from linkgen.families.planar.kinetostatics import forces

    mech = asm.mechanism
    w = mech.drive.omega if omega is None else float(omega)
    e = mech.drive.epsilon if epsilon is None else float(epsilon)
    phi, full = _grid(asm)
    found = [(name, _output(asm, "slider", phi, full, lambda k, n=name: (k.sliders[n].v, k.sliders[n].d1)))
             for name in asm.guides]
    pivoted = {p for r in mech.revolutes if GROUND in r.links for p in r.links if p != GROUND}
    for link in mech.links:
        if link.name in pivoted and link.name != mech.crank:
            found.append((link.name, _output(asm, "rocker", phi, full,
                                             lambda k, n=link.name: (k.links[n].angle.v, k.links[n].angle.d1))))
    outputs = output_table(found)
    trans = {}
    for label, mu in transmission_angles(asm, phi).items():
        at, least = _peak(lambda p, n=label: transmission_angles(asm, p)[n], phi, mu, "min")
        trans[label] = Extreme(least, at)
    torque, peaks, note, lost = None, {}, None, (None, None)
    try:
        f = forces(asm, phi, w, e)
    except LinkgenError as exc:
        note = f"no peak forces: {exc}"
    else:
        at, value = _peak(lambda p: np.abs(forces(asm, p, w, e).balancing_torque), phi,
                          np.abs(f.balancing_torque))
        torque = Extreme(value, at)
        for name, r in f.reactions.items():
            def mag(p, n=name):
                r = np.asarray(forces(asm, p, w, e).reactions[n])
                return np.hypot(r[:, 0], r[:, 1])
            at, value = _peak(mag, phi, np.hypot(r[:, 0], r[:, 1]))
            peaks[name] = Extreme(value, at)
        if mech.frictions:  # the mean over equal steps of φ: over time too at constant ω
            at, value = _peak(lambda p: forces(asm, p, w, e).friction_power, phi, f.friction_power)
            lost = (Extreme(value, at), float(np.mean(f.friction_power[:-1] if full else f.friction_power)))
    return DesignSummary(mech.name, w, e, (mech.drive.start, mech.drive.stop), outputs, torque, peaks, note, trans,
                         spring_peaks(asm, phi, w), *lost, mech.slide_drive, mech.drive.joint)


def spring_peaks(asm: Assembly, phi: np.ndarray, omega: float) -> dict[str, Extreme]:
    """Each spring's largest |tension| [N] (``spring[i]``) and each torsion spring's largest
    |torque| [N·m] (``torsion_spring[i]``), dampers included at crank speed ω, over ``phi``."""
    from linkgen.families.planar.spring_loads import spring_tension, torsion_torque

    mech = asm.mechanism
    items = [(f"spring[{i}]", lambda kin, s=s: spring_tension(kin, s, omega)[0]) for i, s in enumerate(mech.springs)]
    items += [(f"torsion_spring[{i}]", lambda kin, t=t: torsion_torque(kin, t, omega))
              for i, t in enumerate(mech.torsion_springs)]
    out = {}
    for name, value in items:
        def mag(p, value=value):
            return np.abs(value(solve(asm, p, on_singular="mark")))
        at, top = _peak(mag, phi, mag(phi))
        out[name] = Extreme(top, at)
    return out

__all__ = ["DesignSummary", "Extreme", "Limit", "Output", "SAMPLES", "XTOL", "spring_peaks", "summarize",
           "transmission_angles"]
