"""The closed-form motion of a planar linkage as one result (``linkgen analyze``,
``linkgen.kinematics``): points, links, sliders and cam followers at the crank angles φ, with
``to_dict()`` (JSON), ``columns()`` (CSV) and ``text()`` (the terminal), one name per quantity
in all three (``linkgen.model.results``)."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import ClassVar, Mapping

import numpy as np

from linkgen.model.results import AngleMotion, PointMotion, Record, SlideMotion, column, per_sample, plain, shaped

UNITS = {"phi": "rad", "omega": "rad/s", "epsilon": "rad/s²", "position": "m", "velocity": "m/s",
         "acceleration": "m/s²", "angle": "rad", "angular_velocity": "rad/s", "angular_acceleration": "rad/s²",
         "jerk": "m/s³", "angular_jerk": "rad/s³", "displacement": "m", "d1": "per rad", "d2": "per rad²",
         "d3": "per rad³"}
KINDS = ("points", "links", "sliders")
# A prismatic drive's input is a stroke s [m]: phi, omega, epsilon and the transfer functions
# (d/ds) take lengths where a crank's take angles.
STROKE_UNITS = {"phi": "m", "omega": "m/s", "epsilon": "m/s²", "d1": "per m", "d2": "per m²", "d3": "per m³"}


def per_stroke(cols: dict) -> dict:
    """CSV columns of a prismatic drive's results: ``phi [m]``, transfer functions per m (not per rad)."""
    out = {}
    for name, v in cols.items():
        if name == "phi [rad]":
            name = "phi [m]"
        elif any(f".{d}" in name for d in ("d1", "d2", "d3")):
            head, _, unit = name.rpartition(" [")
            num, _, den = unit.rstrip("]").rpartition("/")
            name = f"{head} [{num}/{den.replace('rad', 'm')}]"
        out[name] = v
    return out


@dataclass(frozen=True, repr=False)
class FollowerMotion(Record):
    """A cam pair's follower: its coordinate from the program's lowest position ``displacement``
    (rad for a rocking follower, m for a sliding one, ``unit``), velocity, acceleration and jerk
    (ε constant), and the pressure angle [rad]; ``cam`` names the pair."""

    cam: str
    displacement: np.ndarray | float
    velocity: np.ndarray | float
    acceleration: np.ndarray | float
    jerk: np.ndarray | float
    pressure_angle: np.ndarray | float
    unit: str
    UNIT: ClassVar[str] = "m"

    def unit_of(self, name: str) -> str:
        u = self.unit
        return {"velocity": f"{u}/s", "acceleration": f"{u}/s²", "jerk": f"{u}/s³", "pressure_angle": "rad"}.get(name, u)

    def columns(self, name: str, quantities=None, transfer: bool = True) -> dict[str, np.ndarray]:
        return {f"{name}.{q} [{self.unit_of(q)}]": column(getattr(self, q))
                for q in ("displacement", "velocity", "acceleration", "jerk", "pressure_angle")}


@dataclass(frozen=True, repr=False)
class PlanarKinematics:
    """Positions, velocities, accelerations, jerks (ε constant in time: x‴ω³ + 3x″ωε) and the
    transfer functions d1, d2, d3 (d/dφ, d²/dφ², d³/dφ³) of every point [m], link [rad] and
    slider [m] at the crank angles ``phi`` [rad], speed ``omega`` [rad/s], acceleration
    ``epsilon`` [rad/s²]; ``followers``: each cam pair's follower; ``singular``: True at samples
    marked singular (every other value 0 there)."""

    model: str
    phi: np.ndarray | float
    omega: np.ndarray | float
    epsilon: np.ndarray | float
    points: Mapping[str, PointMotion]
    links: Mapping[str, AngleMotion]
    sliders: Mapping[str, SlideMotion]
    followers: Mapping[str, FollowerMotion]
    singular: np.ndarray | bool
    solution: object = field(default=None, compare=False)  # the planar ``Kinematics`` (singular groups)
    stroke: bool = field(default=False, compare=False)  # the units say it; a prismatic drive: phi is the stroke s [m], omega ṡ, epsilon s̈ (STROKE_UNITS)

    def to_dict(self, transfer: bool = True) -> dict:
        units = UNITS | (STROKE_UNITS if self.stroke else {})
        out = {"model": self.model, "phi": plain(self.phi), "omega": plain(self.omega),
               "epsilon": plain(self.epsilon), "units": units | ({"pressure_angle": "rad"} if self.followers else {})}
        for kind in KINDS:
            out[kind] = {n: q.to_dict(transfer) for n, q in getattr(self, kind).items()}
        if self.followers:
            out["followers"] = {n: f.to_dict() for n, f in self.followers.items()}
        if np.ndim(self.phi):  # samples: which are marked singular (one state never is: it raises)
            out["singular"] = plain(self.singular)
        return out

    def columns(self, transfer: bool = True) -> dict[str, np.ndarray]:
        """CSV columns: phi, singular, each point's, link's and slider's value and time
        derivatives, the followers', then (``transfer``) the transfer functions."""
        cols = {"phi [rad]": column(self.phi), "singular": np.atleast_1d(np.asarray(self.singular, dtype=bool))}
        for kind in KINDS:
            for n, q in getattr(self, kind).items():
                cols |= q.columns(n, q.names(transfer=False))
        for n, f in self.followers.items():
            cols |= f.columns(n)
        if transfer:
            for kind in KINDS:
                for n, q in getattr(self, kind).items():
                    cols |= q.columns(n, ("d1", "d2", "d3"))
        return per_stroke(cols) if self.stroke else cols

    def singular_lines(self) -> list[str]:
        """One line per group with singular samples (``families.planar.kinematics``)."""
        from linkgen.errors import angle_ranges, where_text
        from linkgen.families.planar.kinematics import singular_cause

        kin = self.solution
        if kin is None or not np.any(self.singular):
            return []
        groups = {g.label: g for g in kin.assembly.structure.groups}
        return [f"group {label} is singular at {where_text(angle_ranges(kin.phi, mask), self.stroke)} "
                f"({int(np.count_nonzero(mask))} of {len(kin.phi)} samples: {singular_cause(groups[label])})"
                for label, mask in kin.near_singular.items() if np.any(mask)]

    @per_sample
    def text(self, transfer: bool = False) -> str:
        d = self.to_dict(transfer)
        phi = float(self.phi)
        lines = [f"{self.model}: s = {phi:.9g} m, ṡ = {float(self.omega):g} m/s, s̈ = {float(self.epsilon):g} m/s² "
                 f"(the drive's stroke)" if self.stroke else
                 f"{self.model}: φ = {math.degrees(phi):.6g}° ({phi:.9g} rad), ω = {float(self.omega):g} rad/s, "
                 f"ε = {float(self.epsilon):g} rad/s²"]
        heads = ("x [m]", "y [m]", "vx [m/s]", "vy [m/s]", "ax [m/s²]", "ay [m/s²]", "jx [m/s³]", "jy [m/s³]")
        lines.append(f"{'point':<10}" + "".join(f"{h:>14}" for h in heads))
        for n, q in d["points"].items():
            lines.append(f"{n:<10}" + "".join(f"{x:>14.6g}" for x in q["position"] + q["velocity"] + q["acceleration"]
                                                + q["jerk"]))
        lines.append(f"{'link':<10}{'angle [rad]':>14}{'ω [rad/s]':>14}{'ε [rad/s²]':>14}{'jerk [rad/s³]':>14}")
        for n, q in d["links"].items():
            lines.append(f"{n:<10}" + "".join(f"{q[k]:>14.6g}" for k in ("angle", "angular_velocity",
                                                                            "angular_acceleration", "angular_jerk")))
        if d["sliders"]:
            lines.append(f"{'slider':<10}{'s [m]':>14}{'v [m/s]':>14}{'a [m/s²]':>14}{'j [m/s³]':>14}")
            for n, q in d["sliders"].items():
                lines.append(f"{n:<10}" + "".join(f"{q[k]:>14.6g}" for k in ("displacement", "velocity",
                                                                                "acceleration", "jerk")))
        if transfer:
            lines += _transfer_lines(d, self.stroke)
        return "\n".join(lines)

    def __repr__(self) -> str:
        n = np.size(self.phi)
        return (f"PlanarKinematics({self.model!r}, {n} angle{'s' if n != 1 else ''}, {len(self.points)} points, "
                f"{len(self.links)} links, {len(self.sliders)} sliders)")


def _transfer_lines(d: dict, stroke: bool = False) -> list[str]:
    x, u = ("s", "m") if stroke else ("φ", "rad")
    lines = [f"transfer functions (derivatives with respect to the {'stroke s' if stroke else 'crank angle φ'})"]
    heads = (f"dx/d{x} [m]", f"dy/d{x} [m]", f"d²x/d{x}² [m]", f"d²y/d{x}² [m]", f"d³x/d{x}³ [m]", f"d³y/d{x}³ [m]")
    lines.append(f"{'point':<10}" + "".join(f"{h:>14}" for h in heads))
    for n, q in d["points"].items():
        lines.append(f"{n:<10}" + "".join(f"{x:>14.6g}" for x in q["d1"] + q["d2"] + q["d3"]))
    for kind, unit in (("links", f"rad/{u}"), ("sliders", f"m/{u}")):
        if d[kind]:
            lines.append(f"{kind[:-1]:<10}" + "".join(f"{h + ' [' + unit + ']':>18}" for h in (f"d/d{x}", f"d²/d{x}²",
                                                                                                f"d³/d{x}³")))
            for n, q in d[kind].items():
                lines.append(f"{n:<10}{q['d1']:>18.6g}{q['d2']:>18.6g}{q['d3']:>18.6g}")
    return lines


def kinematics(source, phi, omega=None, epsilon=None, *, on_singular: str = "raise") -> PlanarKinematics:
    """The planar family's ``kinematics`` stage: ``source`` a Mechanism or an Assembly, ``phi``
    [rad] scalar or (n,), ``omega``/``epsilon`` default the description's drive."""
    from linkgen.families.planar.assembly import Assembly, assemble
    from linkgen.families.planar.kinematics import solve

    asm = source if isinstance(source, Assembly) else assemble(source)
    scalar = np.ndim(phi) == 0
    phis = np.atleast_1d(np.asarray(phi, dtype=float))
    d = asm.mechanism.drive
    w = d.omega if omega is None else omega
    e = d.epsilon if epsilon is None else epsilon
    kin = solve(asm, phis, on_singular=on_singular)
    mo = kin.motion(w, e)
    n = phis.shape[0]

    def full(v):
        v = np.asarray(v, dtype=float)
        return shaped(np.broadcast_to(v, (n,) + v.shape[1:]) if v.shape[:1] in ((1,), (n,)) else
                      np.broadcast_to(v, (n,) + v.shape), scalar)

    def of(cls, triple, jerk, tf):
        return cls(*(full(x) for x in (*triple, jerk, tf.d1, tf.d2, tf.d3)))

    return PlanarKinematics(
        asm.mechanism.name, float(phis[0]) if scalar else phis, full(np.broadcast_to(mo.omega, (n,))),
        full(np.broadcast_to(mo.epsilon, (n,))),
        {k: of(PointMotion, v, mo.jerk["points"][k], kin.points[k]) for k, v in mo.points.items()},
        {k: of(AngleMotion, v, mo.jerk["links"][k], kin.links[k].angle) for k, v in mo.links.items()},
        {k: of(SlideMotion, v, mo.jerk["sliders"][k], kin.sliders[k]) for k, v in mo.sliders.items()},
        _followers(kin, full, w, e), bool(kin.singular[0]) if scalar else kin.singular, kin, asm.mechanism.slide_drive)


def _followers(kin, full, omega, epsilon) -> dict[str, FollowerMotion]:
    """Each cam pair's follower (``planar.cam_pair``): displacement from the program's lowest
    position with its time derivatives (ε constant), and the pressure angle."""
    from linkgen.families.planar.cam_pair import above_lowest, contact, lift, oscillating

    out = {}
    for cam in kin.assembly.mechanism.cams:
        theta = kin.phi - kin.assembly.sketch_phi
        _, d1, d2, d3 = lift(cam, theta)
        out[cam.follower] = FollowerMotion(
            cam.name, full(above_lowest(cam, theta)), full(d1 * omega), full(d2 * omega**2 + d1 * epsilon),
            full(d3 * omega**3 + 3 * d2 * omega * epsilon), full(contact(kin, cam)[2]),
            "rad" if oscillating(kin.assembly.mechanism, cam) else "m")
    return out


__all__ = ["FollowerMotion", "PlanarKinematics", "kinematics"]
