"""The spatial four-bar's closed-form stages as results (``linkgen structure|analyze|forces``,
``linkgen.kinematics|forces|structure|summary``): ``to_dict()`` (JSON), ``columns()`` (CSV)
and ``text()``, one name per quantity in all three (``linkgen.model.results``)."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping

import numpy as np

from linkgen.model.results import AngleMotion, PointMotion, Reaction, SlideMotion, column, per_sample, plain, shaped

# The kinds driven by a slider: the input's coordinate s [m] (the "phi" key), its velocity [m/s]
# and acceleration [m/s²] ("omega", "epsilon"), transfer functions per metre of s, and a balancing
# force [N] for the torque.
INPUT_SLIDES = ("PSSR", "PSSP")
SLIDE_UNITS = {"phi": "m", "omega": "m/s", "epsilon": "m/s²", "d1": "per m", "d2": "per m²", "d3": "per m³"}
UNITS = {"position": "m", "velocity": "m/s", "acceleration": "m/s²", "jerk": "m/s³", "angle": "rad",
         "angular_velocity": "rad/s", "angular_acceleration": "rad/s²", "angular_jerk": "rad/s³", "displacement": "m",
         "d1": "per rad", "d2": "per rad²", "d3": "per rad³"}


@dataclass(frozen=True, repr=False)
class SpatialKinematics:
    """Every point's position (3,) [m], velocity, acceleration, jerk and transfer functions d1..d3
    at the crank angles ``phi`` [rad], with the turning links and the sliders named as in every
    family (``linkgen.model.summary``): ``links`` the crank (its angle φ, ω, ε) and a turning
    output under its link's name (angle, angular_velocity, ...), ``sliders`` a sliding output
    under its prismatic pair's name (displacement, velocity, ...), each with transfer functions."""

    model: str
    kind: str
    phi: np.ndarray | float
    omega: float
    epsilon: float
    points: Mapping[str, PointMotion]
    links: Mapping[str, AngleMotion]
    sliders: Mapping[str, SlideMotion]

    def to_dict(self, transfer: bool = True) -> dict:
        return {"model": self.model, "kind": self.kind, "phi": plain(self.phi), "omega": self.omega,
                "epsilon": self.epsilon, "units": UNITS | (SLIDE_UNITS if self.kind in INPUT_SLIDES else {}),
                "points": {n: p.to_dict(transfer) for n, p in self.points.items()},
                "links": {n: q.to_dict(transfer) for n, q in self.links.items()},
                "sliders": {n: q.to_dict(transfer) for n, q in self.sliders.items()}}

    def columns(self, transfer: bool = True) -> dict[str, np.ndarray]:
        cols = {"phi [m]" if self.kind in INPUT_SLIDES else "phi [rad]": column(self.phi)}  # the input under one name, its unit saying which
        for table in (self.points, self.links, self.sliders):
            for n, q in table.items():
                cols |= q.columns(n, q.names(transfer))
        return cols

    def singular_lines(self) -> list[str]:
        return []

    @per_sample
    def text(self, transfer: bool = False) -> str:
        d = self.to_dict(transfer=False)
        phi = float(self.phi)
        lines = [f"{self.model} ({self.kind}): " + (
            f"s = {phi:.9g} m, v = {self.omega:g} m/s, a = {self.epsilon:g} m/s²" if self.kind in INPUT_SLIDES else
            f"φ = {math.degrees(phi):.6g}° ({phi:.9g} rad), ω = {self.omega:g} rad/s, ε = {self.epsilon:g} rad/s²")]
        head = "".join(f"{h:>13}" for h in ("x [m]", "y [m]", "z [m]", "vx [m/s]", "vy [m/s]", "vz [m/s]", "ax [m/s²]",
                                              "ay [m/s²]", "az [m/s²]", "jx [m/s³]", "jy [m/s³]", "jz [m/s³]"))
        lines.append(f"{'point':<8}{head}")
        for n, q in d["points"].items():
            lines.append(f"{n:<8}" + "".join(f"{x:>13.6g}" for x in q["position"] + q["velocity"] + q["acceleration"]
                                              + q["jerk"]))
        for kind in ("links", "sliders"):
            for n, q in d[kind].items():
                lines.append(f"{kind[:-1]} {n}: " + ", ".join(f"{k} {v:.9g}" for k, v in q.items()))
        if transfer:  # the output: the slider, or the turning link after the crank
            out = next(iter(self.sliders.values()), None) or list(self.links.values())[-1]
            x = "s" if self.kind in INPUT_SLIDES else "phi"
            out = (list(self.sliders.values()) + list(self.links.values()))[-1] if self.kind in INPUT_SLIDES else out
            lines.append(f"transfer functions (derivatives with respect to {'s' if x == 's' else 'φ'}) of the output: "
                         + ", ".join(f"{k} {float(getattr(out, q)):.9g}" for k, q in (
                             (f"d/d{x}", "d1"), (f"d2/d{x}2", "d2"), (f"d3/d{x}3", "d3"))))
        return "\n".join(lines)

    def __repr__(self) -> str:
        return f"SpatialKinematics({self.model!r}, {np.size(self.phi)} angles, {len(self.points)} points)"


def kinematics(mech, phi, omega=None, epsilon=None, *, on_singular: str = "raise") -> SpatialKinematics:
    """The spatial family's ``kinematics`` stage (``families.spatial.kinematics.solve``); a
    singular position is always an error here (``on_singular`` is for planar linkages)."""
    from linkgen.families.spatial.jets import motion as jet_motion
    from linkgen.families.spatial.kinematics import solve

    scalar = np.ndim(phi) == 0
    phis = np.atleast_1d(np.asarray(phi, dtype=float))
    w = float(mech.drive.omega if omega is None else omega)
    e = float(mech.drive.epsilon if epsilon is None else epsilon)
    k = solve(mech, phis)
    c = k.chain

    def s(x):
        return shaped(x, scalar)

    # a cylindrical pair's point as its later link carries it (RCCC) is "POINT:LINK", as in the MJCF
    jets = k.points | {f"{p}:{link}": jet for (link, p), jet in k.own.items() if link != c.crank or p != c.drive_point}
    points = {n: PointMotion(*(s(x) for x in (*jet_motion(jet, w, e), jet.d[1], jet.d[2], jet.d[3])))
              for n, jet in jets.items()}
    n = phis.shape[0]
    # The crank turns with φ itself: dφ/dφ = 1, higher transfer functions 0.
    crank = (SlideMotion if c.input_slides else AngleMotion)(
        s(phis), s(np.full(n, w)), s(np.full(n, e)), s(np.zeros(n)), s(np.ones(n)), s(np.zeros(n)), s(np.zeros(n)))
    out = (SlideMotion if c.output_slides else AngleMotion)(
        *(s(x) for x in (*jet_motion(k.output, w, e), k.output.d[1], k.output.d[2], k.output.d[3])))
    # a slider as the input is listed under its pair's name, as a sliding output
    links = ({} if c.input_slides else {c.crank: crank}) | ({} if c.output_slides else {c.output: out})
    sliders = ({c.drive: crank} if c.input_slides else {}) | ({c.pair_out: out} if c.output_slides else {})
    sliders |= {pair: SlideMotion(*(s(x) for x in (*jet_motion(jet, w, e), jet.d[1], jet.d[2], jet.d[3])))
                for pair, jet in k.slides.items()}  # each cylindrical pair's slide (RCCC)
    return SpatialKinematics(mech.name, c.kind, float(phis[0]) if scalar else phis, w, e, points, links, sliders)


# Below this fraction of the largest force or moment a printed reaction component is float64's
# residue (measured ~1e-16..1e-15 of the scale where a pair carries nothing), shown as 0.
ROUNDING = 1e-12


@dataclass(frozen=True, repr=False)
class SpatialForcesResult:
    """The balancing torque [N·m] (and the same from virtual work), every pair's reaction (3-D
    force [N] and moment [N·m], on one link by another) at the crank angles ``phi`` [rad];
    ``statically_indeterminate``: the degree of static indeterminacy (the reactions then
    least-squares)."""

    model: str
    phi: np.ndarray | float
    omega: float
    epsilon: float
    balancing_torque: np.ndarray | float
    power_balance_torque: np.ndarray | float
    reactions: Mapping[str, Reaction]
    statically_indeterminate: int

    input_slides: bool = False

    @property
    def _drive(self) -> tuple[str, str]:
        """The balancing load's name and unit: a force [N] on a slider input, else a torque."""
        return ("force", "N") if self.input_slides else ("torque", "N·m")

    def to_dict(self, transfer: bool = True) -> dict:
        # one name in every family (a planar prismatic drive's too): ``balancing_torque``, its unit
        # saying what it is, N on a slider input
        what, unit = "torque", self._drive[1]
        return {"model": self.model, "phi": plain(self.phi), "omega": self.omega, "epsilon": self.epsilon,
                "units": {"force": "N", "moment": "N·m", f"balancing_{what}": unit, f"power_balance_{what}": unit}
                | (SLIDE_UNITS if self.input_slides else {}),
                f"balancing_{what}": plain(self.balancing_torque),
                f"power_balance_{what}": plain(self.power_balance_torque),
                "statically_indeterminate": self.statically_indeterminate,
                "reactions": {n: r.to_dict() for n, r in self.reactions.items()}}

    def columns(self, transfer: bool = True) -> dict[str, np.ndarray]:
        what, unit = "torque", self._drive[1]
        cols = {"phi [m]" if self.input_slides else "phi [rad]": column(self.phi),
                f"balancing_{what} [{unit}]": column(self.balancing_torque),
                f"power_balance_{what} [{unit}]": column(self.power_balance_torque)}
        for n, r in self.reactions.items():
            cols |= r.columns(n)
        return cols

    def singular_lines(self) -> list[str]:
        return []

    @per_sample
    def text(self, transfer: bool = False) -> str:
        phi = float(self.phi)
        what, unit = self._drive
        at = (f"s = {phi:.6g} m, v = {self.omega:g} m/s, a = {self.epsilon:g} m/s²" if self.input_slides else
              f"φ = {math.degrees(phi):.6g}°, ω = {self.omega:g} rad/s, ε = {self.epsilon:g} rad/s²")
        lines = [f"{self.model}: {at}: balancing {what} {float(self.balancing_torque):.6g} {unit} (power balance: "
                 f"{float(self.power_balance_torque):.6g} {unit})"]
        # rounding's residue (a pair that carries no moment gets ~1e-15 N·m, different bits in a
        # sampled and a one-angle solve) is shown as 0: below ROUNDING of the largest force or moment
        floor = ROUNDING * max([1e-300] + [float(np.abs(x).max()) for r in self.reactions.values() for x in (r.force, r.moment)])

        def num(x: float) -> str:
            return format(0.0 if abs(x) < floor else x, ".6g")

        for n, r in self.reactions.items():
            lines.append(f"pair {n}: on {r.on} by {r.by}: force [{', '.join(num(x) for x in r.force)}] N, "
                         f"moment [{', '.join(num(x) for x in r.moment)}] N·m")
        if self.statically_indeterminate:
            lines.append(f"statically indeterminate by {self.statically_indeterminate}: the reactions shown are the "
                         "least-squares (minimum-norm) ones; the balancing torque is determined")
        return "\n".join(lines)

    def __repr__(self) -> str:
        return f"SpatialForcesResult({self.model!r}, {np.size(self.phi)} angles, {len(self.reactions)} reactions)"


def forces(mech, phi, omega=None, epsilon=None, *, on_singular: str = "raise") -> SpatialForcesResult:
    """The spatial family's ``forces`` stage (``families.spatial.forces.forces``)."""
    from linkgen.families.spatial.forces import forces as solve_forces

    scalar = np.ndim(phi) == 0
    phis = np.atleast_1d(np.asarray(phi, dtype=float))
    w = float(mech.drive.omega if omega is None else omega)
    e = float(mech.drive.epsilon if epsilon is None else epsilon)
    f = solve_forces(mech, phis, w, e)

    def s(x):
        return shaped(x, scalar)

    return SpatialForcesResult(mech.name, float(phis[0]) if scalar else phis, w, e, s(f.balancing_torque),
                         s(f.power_balance_torque),
                         {n: Reaction(s(r.force), r.on, r.by, s(r.moment)) for n, r in f.reactions.items()},
                         f.indeterminate, mech.drive.slides)


__all__ = ["SpatialForcesResult", "SpatialKinematics", "forces", "kinematics"]
