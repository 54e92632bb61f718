"""The kinetostatics of a planar linkage as one result (``linkgen forces``, ``linkgen.forces``):
reactions, prismatic loads, tooth and contact forces, the balancing torque and the reduced
dynamics, with ``to_dict()`` (JSON), ``columns()`` (CSV) and ``text()``, one name per quantity in
all three (``linkgen.model.results``). Conventions: ``linkgen.families.planar.kinetostatics``."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar, Mapping

import numpy as np

from linkgen.model.names import GROUND
from linkgen.model.results import ContactForce, Reaction, Record, column, per_sample, plain, shaped

UNITS = {"phi": "rad", "omega": "rad/s", "epsilon": "rad/s²", "force": "N", "torque": "N·m", "moment": "N·m",
         "normal_force": "N", "reduced_inertia": "kg·m²", "reduced_inertia_derivative": "kg·m²/rad",
         "reduced_moment": "N·m"}
# With friction (``[[friction]]``): each pair's friction (a couple [N·m] or a force [N]) and the power lost.
FRICTION_UNITS = {"friction_couple": "N·m", "friction_force": "N", "friction_power": "W"}
# With springs (``[[spring]]``, ``[[torsion_spring]]``): their forces, moments, lengths and deflections.
SPRING_UNITS = {"spring_force": "N", "damper_force": "N", "length": "m", "spring_moment": "N·m",
                "damper_moment": "N·m", "deflection": "rad"}
# A prismatic drive: the input is a stroke s [m], the balancing load a force [N] along the guide on
# the slider, the reduced mass [kg] (under the names of the crank's quantities).
STROKE_UNITS = {"phi": "m", "omega": "m/s", "epsilon": "m/s²", "torque": "N", "reduced_inertia": "kg",
                "reduced_inertia_derivative": "kg/m", "reduced_moment": "N"}
# The crank-level quantities, their units, in the order the CSV gives them.
SCALARS = (("balancing_torque", "N·m"), ("power_balance_torque", "N·m"), ("reduced_inertia", "kg·m²"),
           ("reduced_inertia_derivative", "kg·m²/rad"), ("reduced_moment", "N·m"))


@dataclass(frozen=True, repr=False)
class PrismaticLoad(Record):
    """A prismatic pair: the guide's ``normal_force`` [N] on the slider along the guide's left
    normal and the ``moment`` [N·m] the pair carries about the slider's point, acting on the
    slider ``on``, exerted by the guide ``by``."""

    normal_force: np.ndarray | float
    on: str
    by: str
    moment: np.ndarray | float
    UNIT: ClassVar[str] = "N"
    UNITS: ClassVar[dict[str, str]] = {"moment": "N·m"}


@dataclass(frozen=True, repr=False)
class PairFriction(Record):
    """A pair's Coulomb friction (``[[friction]]``): at a revolute the ``friction_couple`` [N·m] on
    its first link ``on`` from its second ``by``; at a prismatic pair the ``friction_force`` [N] on
    the slider ``on`` along its guide's direction, from the guide ``by``."""

    on: str
    by: str
    friction_couple: np.ndarray | float | None = None
    friction_force: np.ndarray | float | None = None
    UNIT: ClassVar[str] = "N"
    UNITS: ClassVar[dict[str, str]] = {"friction_couple": "N·m"}


@dataclass(frozen=True, repr=False)
class SpringForce(Record):
    """A spring between points (``[[spring]]``, keyed ``spring[i]`` as the design summary names it,
    between its ``points`` "P-Q"): its ``force`` [N], the tension (positive pulls its points
    together), the sum of the ``spring_force`` k·(L − L₀) and the ``damper_force`` c·dL/dt at the
    crank speed, and its ``length`` L [m]."""

    points: str
    force: np.ndarray | float
    spring_force: np.ndarray | float
    damper_force: np.ndarray | float
    length: np.ndarray | float
    UNIT: ClassVar[str] = "N"
    UNITS: ClassVar[dict[str, str]] = {"length": "m"}


@dataclass(frozen=True, repr=False)
class TorsionMoment(Record):
    """A torsion spring (``[[torsion_spring]]``, keyed ``torsion_spring[i]`` as the design summary
    names it, at its revolute ``joint``): the ``moment`` [N·m] it applies to its second link (its
    opposite on the first), the sum of the ``spring_moment`` −k·(θ − θ₀) and the ``damper_moment``
    −c·dθ/dt, and its ``deflection`` θ − θ₀ [rad]."""

    joint: str
    moment: np.ndarray | float
    spring_moment: np.ndarray | float
    damper_moment: np.ndarray | float
    deflection: np.ndarray | float
    UNIT: ClassVar[str] = "N·m"
    UNITS: ClassVar[dict[str, str]] = {"deflection": "rad"}


@dataclass(frozen=True, repr=False)
class ToothForce(Record):
    """A gear pair's tooth force [N] on its planet ``on``, exerted by the fixed gear's link ``by``
    (the ground)."""

    force: np.ndarray
    on: str
    by: str
    UNIT: ClassVar[str] = "N"
    VECTOR: ClassVar[bool] = True


@dataclass(frozen=True, repr=False)
class PlanarForces:
    """Balancing torque [N·m] (and the same from virtual work, ``power_balance_torque``),
    ``reactions`` in the revolutes, ``prismatic`` loads, gear ``tooth`` and cam ``contact``
    forces, and the reduced inertia J [kg·m²], dJ/dφ [kg·m²/rad] and reduced moment [N·m] at the
    crank angles ``phi`` [rad]; ``singular`` True at samples marked singular (0 there)."""

    model: str
    phi: np.ndarray | float
    omega: float
    epsilon: float
    balancing_torque: np.ndarray | float
    power_balance_torque: np.ndarray | float
    reactions: Mapping[str, Reaction]
    prismatic: Mapping[str, PrismaticLoad]
    tooth: Mapping[str, ToothForce]
    contact: Mapping[str, ContactForce]
    reduced_inertia: np.ndarray | float
    reduced_inertia_derivative: np.ndarray | float
    reduced_moment: np.ndarray | float
    singular: np.ndarray | bool
    solution: object = field(default=None, compare=False)  # the planar ``Forces``
    friction: Mapping[str, PairFriction] = field(default_factory=dict)
    friction_power: np.ndarray | float | None = None
    springs: Mapping[str, SpringForce] = field(default_factory=dict)
    torsion_springs: Mapping[str, TorsionMoment] = field(default_factory=dict)
    stroke: bool = field(default=False, compare=False)  # the units say it; a prismatic drive: phi is the stroke s [m], the balancing load a force [N]

    def to_dict(self, transfer: bool = True) -> dict:
        out = {"model": self.model, "phi": plain(self.phi), "omega": plain(self.omega), "epsilon": plain(self.epsilon),
               "units": UNITS | (STROKE_UNITS if self.stroke else {}), "balancing_torque": plain(self.balancing_torque),
               "power_balance_torque": plain(self.power_balance_torque),
               "reactions": {k: r.to_dict() for k, r in self.reactions.items()},
               "prismatic": {k: p.to_dict() for k, p in self.prismatic.items()},
               "reduced_inertia": plain(self.reduced_inertia),
               "reduced_inertia_derivative": plain(self.reduced_inertia_derivative),
               "reduced_moment": plain(self.reduced_moment)}
        if self.tooth:
            out["tooth"] = {k: t.to_dict() for k, t in self.tooth.items()}
        if self.contact:
            out["contact"] = {k: c.to_dict() for k, c in self.contact.items()}
        if self.friction:
            out["friction"] = {k: v.to_dict() for k, v in self.friction.items()}
            out["friction_power"] = plain(self.friction_power)
            out["units"] = out["units"] | FRICTION_UNITS
        if self.springs:
            out["springs"] = {k: v.to_dict() for k, v in self.springs.items()}
        if self.torsion_springs:
            out["torsion_springs"] = {k: v.to_dict() for k, v in self.torsion_springs.items()}
        if self.springs or self.torsion_springs:
            out["units"] = out["units"] | SPRING_UNITS
        if np.ndim(self.phi):  # samples: which are marked singular (one state never is: it raises)
            out["singular"] = plain(self.singular)
        return out

    def columns(self, transfer: bool = True) -> dict[str, np.ndarray]:
        cols = {f"phi [{'m' if self.stroke else 'rad'}]": column(self.phi),
                "singular": np.atleast_1d(np.asarray(self.singular, dtype=bool))}
        stroke = {"balancing_torque": "N", "power_balance_torque": "N", "reduced_inertia": "kg",
                  "reduced_inertia_derivative": "kg/m", "reduced_moment": "N"} if self.stroke else {}
        cols |= {f"{q} [{stroke.get(q, u)}]": column(getattr(self, q)) for q, u in SCALARS}
        for table in (self.reactions, self.prismatic, self.tooth, self.contact, self.friction, self.springs,
                      self.torsion_springs):
            for k, r in table.items():
                cols |= r.columns(k)
        if self.friction:
            cols["friction_power [W]"] = column(self.friction_power)
        return cols

    def singular_lines(self) -> list[str]:
        """The groups singular somewhere (a second kinematic pass, only when some sample is marked),
        and the samples where the friction has no solution."""
        if not np.any(self.singular) or self.solution is None:
            return []
        from linkgen.errors import angle_ranges, format_ranges
        from linkgen.families.planar.motion_result import kinematics

        kin = kinematics(self.solution[0], self.solution[1], on_singular="mark")
        lines = kin.singular_lines()
        locked = np.asarray(self.singular, dtype=bool) & ~np.asarray(kin.singular, dtype=bool)
        if locked.any():  # marked by the friction's iteration, not by a group (``kinetostatics``)
            phi = np.atleast_1d(self.phi)
            lines.append(f"the kinetostatics with friction finds no solution at crank angles "
                         f"{format_ranges(angle_ranges(phi, locked))} ({int(np.count_nonzero(locked))} of {len(phi)} "
                         f"samples: the mechanism self-locks there, or is close to it)")
        return lines

    @per_sample
    def text(self, transfer: bool = False) -> str:
        phi = float(self.phi)
        if self.stroke:
            lines = [f"{self.model}: s = {phi:.6g} m, ṡ = {self.omega:g} m/s, s̈ = {self.epsilon:g} m/s² (the drive's stroke)",
                     f"balancing force on the slider along its guide: {float(self.balancing_torque):.6g} N "
                     f"(power balance: {float(self.power_balance_torque):.6g} N)",
                     f"reduced mass m = {float(self.reduced_inertia):.6g} kg, dm/ds = "
                     f"{float(self.reduced_inertia_derivative):.6g} kg/m, reduced force of loads = "
                     f"{float(self.reduced_moment):.6g} N"]
        else:
            lines = [f"{self.model}: φ = {math.degrees(phi):.6g}°, ω = {self.omega:g} rad/s, ε = {self.epsilon:g} rad/s²",
                     f"balancing torque on the crank: {float(self.balancing_torque):.6g} N·m "
                     f"(power balance: {float(self.power_balance_torque):.6g} N·m)",
                     f"reduced inertia J = {float(self.reduced_inertia):.6g} kg·m², dJ/dφ = "
                     f"{float(self.reduced_inertia_derivative):.6g} kg·m²/rad, reduced moment of loads = "
                     f"{float(self.reduced_moment):.6g} N·m"]
        lines.append(f"{'pair':<18}{'on':>10}{'by':>10}{'Fx [N]':>14}{'Fy [N]':>14}{'|F| [N]':>14}")
        for k, r in self.reactions.items():
            fx, fy = (float(x) for x in r.force)
            lines.append(f"{k:<18}{r.on:>10}{r.by:>10}{fx:>14.6g}{fy:>14.6g}{math.hypot(fx, fy):>14.6g}")
        if self.prismatic:
            lines.append(f"{'prismatic':<18}{'on':>10}{'by':>10}{'N [N]':>14}{'M [N·m]':>14}")
            for k, p in self.prismatic.items():
                lines.append(f"{k:<18}{p.on:>10}{p.by:>10}{float(p.normal_force):>14.6g}{float(p.moment):>14.6g}")
        for k, t in self.tooth.items():
            fx, fy = (float(x) for x in t.force)
            lines.append(f"tooth force of gear {k!r} on {t.on!r} by {t.by!r}: ({fx:.6g}, {fy:.6g}) N, |F| = "
                         f"{math.hypot(fx, fy):.6g} N")
        for k, c in self.contact.items():
            n = float(c.normal_force)
            lines.append(f"contact force of cam {k!r} on its follower {c.on!r} by {c.by!r}: {n:.6g} N along the profile's normal"
                         + ("" if n >= 0 else " — negative: the follower would leave the cam here (a stronger spring "
                                              "keeps it on)"))
        for k, v in self.friction.items():
            if v.friction_couple is not None:
                lines.append(f"friction couple in {k!r} on {v.on!r} by {v.by!r}: {float(v.friction_couple):.6g} N·m")
            else:
                lines.append(f"friction force in {k!r} on {v.on!r} by {v.by!r}: {float(v.friction_force):.6g} N "
                             f"along the guide")
        if self.friction:
            lines.append(f"power lost to friction: {float(self.friction_power):.6g} W")
        for k, v in self.springs.items():
            lines.append(f"{k} ({v.points}): tension {float(v.force):.6g} N (spring {float(v.spring_force):.6g} N, damper "
                         f"{float(v.damper_force):.6g} N), length {float(v.length):.6g} m")
        for k, v in self.torsion_springs.items():
            lines.append(f"{k} (at {v.joint}): moment on its second link {float(v.moment):.6g} N·m (spring {float(v.spring_moment):.6g} "
                         f"N·m, damper {float(v.damper_moment):.6g} N·m), deflection {float(v.deflection):.6g} rad")
        return "\n".join(lines)

    def __repr__(self) -> str:
        n = np.size(self.phi)
        return (f"PlanarForces({self.model!r}, {n} angle{'s' if n != 1 else ''}, {len(self.reactions)} reactions, "
                f"{len(self.prismatic)} prismatic pairs)")


def forces(source, phi, omega=None, epsilon=None, *, on_singular: str = "raise") -> PlanarForces:
    """The planar family's ``forces`` stage (``families.planar.kinetostatics.forces``) at crank
    angles ``phi`` [rad] (scalar or (n,)), speed and acceleration (default the drive's; each a
    scalar or one per angle, as along a machine's real motion)."""
    from linkgen.families.planar.assembly import Assembly, assemble
    from linkgen.families.planar.kinetostatics import forces as solve_forces

    asm = source if isinstance(source, Assembly) else assemble(source)
    mech = asm.mechanism
    scalar = np.ndim(phi) == 0
    phis = np.atleast_1d(np.asarray(phi, dtype=float))
    w, e = (float(x) if np.ndim(x) == 0 else np.asarray(x, dtype=float)
            for x in (mech.drive.omega if omega is None else omega, mech.drive.epsilon if epsilon is None else epsilon))
    f = solve_forces(asm, phis, w, e, on_singular=on_singular)
    first = {r.name: r.links for r in mech.revolutes}
    pairs = {p.name: p for p in mech.prismatics}

    def s(x):
        return shaped(x, scalar)

    return PlanarForces(
        mech.name, float(phis[0]) if scalar else phis, w, e, s(f.balancing_torque), s(f.power_balance_torque),
        {k: Reaction(s(v), first[k][0], first[k][1]) for k, v in f.reactions.items()},
        {k: PrismaticLoad(s(v), pairs[k].slider, pairs[k].guide, s(f.moment[k])) for k, v in f.normal_force.items()},
        {k: ToothForce(s(v), g.planet, GROUND) for (k, v), g in zip(f.tooth.items(), mech.gears)},
        {c.name: ContactForce(s(f.contact[c.name]), c.follower, mech.crank) for c in mech.cams if c.name in f.contact},
        s(f.reduced.inertia), s(f.reduced.inertia_derivative), s(f.reduced.moment),
        bool(f.singular[0]) if scalar else f.singular, (asm, phis),
        {k: PairFriction(f.on[k], f.by[k], *((None, s(v)) if k in pairs else (s(v), None)))
         for k, v in f.friction.items()}, s(f.friction_power) if f.friction else None,
        *_springs(asm, phis, w, f.singular, s), mech.slide_drive)


def _springs(asm, phi: np.ndarray, omega, singular: np.ndarray, s) -> tuple[dict, dict]:
    """The springs' forces and the torsion springs' moments at the angles φ (n,) and crank speed ω
    (0 where ``singular``), keyed ``spring[i]`` and ``torsion_spring[i]``."""
    mech = asm.mechanism
    if not mech.springs and not mech.torsion_springs:
        return {}, {}
    from linkgen.families.planar.kinematics import solve
    from linkgen.families.planar.spring_loads import spring_lengths, torsion_deflection

    kin = solve(asm, phi, on_singular="mark")
    keep = ~np.asarray(singular, dtype=bool)
    springs, torsion = {}, {}
    for i, sp in enumerate(mech.springs):
        length, rate, _ = spring_lengths(kin, sp)
        k_part, c_part = sp.stiffness * (length - sp.rest_length), sp.damping * rate * omega
        springs[f"spring[{i}]"] = SpringForce("-".join(sp.points), *(s(np.where(keep, x, 0.0))
                                                                       for x in (k_part + c_part, k_part, c_part, length)))
    for i, t in enumerate(mech.torsion_springs):
        dev, rate = torsion_deflection(kin, t)
        k_part, c_part = -t.stiffness * dev, -t.damping * rate * omega
        torsion[f"torsion_spring[{i}]"] = TorsionMoment(t.joint, *(s(np.where(keep, x, 0.0))
                                                                  for x in (k_part + c_part, k_part, c_part, dev)))
    return springs, torsion


__all__ = ["ContactForce", "PairFriction", "PlanarForces", "PrismaticLoad", "SpringForce", "ToothForce",
           "TorsionMoment", "forces"]
