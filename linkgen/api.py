"""The Python API, one function per CLI command, each taking a ``Mechanism`` (or an already
assembled one) and returning named frozen results:

    mech = linkgen.load("models/fourbar.toml")
    k = linkgen.kinematics(mech, 0.5)            # φ = 0.5 rad: k.points["B"].position has shape (2,)
    f = linkgen.forces(mech, np.linspace(0, 1, 50), omega=10.0)
    f.columns()                                  # {"phi [rad]": (50,), "balancing_torque [N·m]": …}
    linkgen.write_mjcf(mech); linkgen.validate(mech).ok

Angles in rad, speeds in rad/s, SI throughout. A scalar φ gives scalar-shaped results (a point
(2,), an angle a float); an array φ (n,) gives (n, 2) and (n,). ``to_dict()`` gives JSON-ready
nested dicts with a ``units`` entry, ``columns()`` flat name → 1-D array columns (pandas-ready).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

import numpy as np

from linkgen.families.planar.description import Mechanism
from linkgen.families.planar.assembly import Assembly, assemble
from linkgen.families.planar.kinematics import solve
from linkgen.families.planar.kinetostatics import forces as _forces
from linkgen.families.planar.structure import Structure, analyze

UNITS = {"phi": "rad", "omega": "rad/s", "epsilon": "rad/s²", "position": "m", "velocity": "m/s",
         "acceleration": "m/s²", "angle": "rad", "angular_velocity": "rad/s", "angular_acceleration": "rad/s²",
         "jerk": "m/s³", "angular_jerk": "rad/s³", "displacement": "m", "d1": "per rad (m/rad or rad/rad)",
         "d2": "per rad²", "d3": "per rad³", "force": "N", "torque": "N·m", "moment": "N·m", "inertia": "kg·m²"}


def _assembly(source: Mechanism | Assembly) -> Assembly:
    return source if isinstance(source, Assembly) else assemble(source)


def _mech(source: Mechanism | Assembly) -> Mechanism:
    return source if isinstance(source, Mechanism) else source.mechanism


def _shape(x, scalar: bool):
    x = np.asarray(x)
    return (float(x[0]) if x.ndim == 1 else x[0].copy()) if scalar else x


def _plain(x):
    return float(x) if np.ndim(x) == 0 else np.asarray(x).tolist()


def _spatial(source) -> bool:
    from linkgen.families.spatial.description import SpatialMechanism

    return isinstance(source, SpatialMechanism)


@dataclass(frozen=True, repr=False)
class Quantity:
    """One point, link or slider: value (position [m], angle [rad] or displacement [m]), its
    velocity, acceleration, jerk (ε taken constant in time), and the transfer functions d/dφ,
    d²/dφ², d³/dφ³. Iterating gives (value, velocity, acceleration)."""

    value: np.ndarray | float
    velocity: np.ndarray | float
    acceleration: np.ndarray | float
    d1: np.ndarray | float
    d2: np.ndarray | float
    jerk: np.ndarray | float
    d3: np.ndarray | float

    def __iter__(self):
        return iter((self.value, self.velocity, self.acceleration))

    @property
    def position(self):
        """A point's position [m] (the value)."""
        return self.value

    @property
    def angle(self):
        """A link's angle [rad] (the value)."""
        return self.value

    @property
    def displacement(self):
        """A slider's displacement [m] (the value)."""
        return self.value

    def to_dict(self) -> dict:
        return {k: _plain(getattr(self, k)) for k in ("value", "velocity", "acceleration", "jerk", "d1", "d2", "d3")}

    def __repr__(self) -> str:
        return f"Quantity(shape {np.shape(self.value)})"


@dataclass(frozen=True, repr=False)
class KinematicsResult:
    """Points, links and sliders of a mechanism at crank angles φ, speed ω, acceleration ε."""

    model: str
    phi: np.ndarray | float
    omega: np.ndarray | float
    epsilon: np.ndarray | float
    points: Mapping[str, Quantity]
    links: Mapping[str, Quantity]
    sliders: Mapping[str, Quantity]

    def to_dict(self) -> dict:
        return {"model": self.model, "phi": _plain(self.phi), "omega": _plain(self.omega),
                "epsilon": _plain(self.epsilon), "units": UNITS,
                **{kind: {n: q.to_dict() for n, q in getattr(self, kind).items()} for kind in ("points", "links", "sliders")}}

    def columns(self) -> dict[str, np.ndarray]:
        cols = {"phi [rad]": np.atleast_1d(self.phi)}
        names = {"points": ("position", "m"), "links": ("angle", "rad"), "sliders": ("displacement", "m")}
        for kind, (value, unit) in names.items():
            for n, q in getattr(self, kind).items():
                for label, x, u in ((value, q.value, unit), ("velocity", q.velocity, f"{unit}/s"),
                                    ("acceleration", q.acceleration, f"{unit}/s²"), ("jerk", q.jerk, f"{unit}/s³"),
                                    ("d1", q.d1, f"{unit}/rad"), ("d2", q.d2, f"{unit}/rad²"),
                                    ("d3", q.d3, f"{unit}/rad³")):
                    x = np.asarray(x)
                    if kind == "points":
                        x = x.reshape(-1, 2)
                        cols[f"{n}.{label}.x [{u}]"], cols[f"{n}.{label}.y [{u}]"] = x[:, 0], x[:, 1]
                    else:
                        cols[f"{n}.{label} [{u}]"] = np.atleast_1d(x)
        return cols

    def __repr__(self) -> str:
        n = np.size(self.phi)
        return (f"KinematicsResult({self.model!r}, {n} angle{'s' if n != 1 else ''}, {len(self.points)} points, "
                f"{len(self.links)} links, {len(self.sliders)} sliders)")


def structure(source: Mechanism | Assembly) -> Structure:
    """Mobility, the Assur groups and the structure formula (``linkgen structure``)."""
    return analyze(_mech(source))


def _rates(mech: Mechanism, omega, epsilon):
    return (mech.drive.omega if omega is None else omega, mech.drive.epsilon if epsilon is None else epsilon)


def kinematics(source: Mechanism | Assembly, phi, omega=None, epsilon=None) -> KinematicsResult:
    """Positions, velocities, accelerations, jerks and transfer functions at crank angles φ [rad]
    (scalar or (n,)), speed ω [rad/s] and acceleration ε [rad/s²] (default the description's;
    the jerk takes ε constant in time: x‴ω³ + 3x″ωε)."""
    if _spatial(source):  # a spatial four-bar: points (3,) per angle, its output under links or sliders
        return _spatial_kinematics(source, phi, omega, epsilon)
    asm = _assembly(source)
    scalar = np.ndim(phi) == 0
    phis = np.atleast_1d(np.asarray(phi, dtype=float))
    w, e = _rates(asm.mechanism, omega, epsilon)
    kin = solve(asm, phis)
    mo = kin.motion(w, e)
    n = phis.shape[0]

    def q(vals, jerk, tf):
        return Quantity(*(_shape(np.broadcast_to(v, (n,) + np.shape(v)[1:]), scalar)
                          for v in (*vals, tf.d1, tf.d2, jerk, tf.d3)))

    return KinematicsResult(
        asm.mechanism.name, float(phis[0]) if scalar else phis,
        _shape(np.broadcast_to(mo.omega, (n,)), scalar), _shape(np.broadcast_to(mo.epsilon, (n,)), scalar),
        {k: q(v, mo.jerk["points"][k], kin.points[k]) for k, v in mo.points.items()},
        {k: q(v, mo.jerk["links"][k], kin.links[k].angle) for k, v in mo.links.items()},
        {k: q(v, mo.jerk["sliders"][k], kin.sliders[k]) for k, v in mo.sliders.items()})


def _spatial_kinematics(mech, phi, omega, epsilon) -> KinematicsResult:
    """``kinematics`` of a spatial four-bar: every point, and the output (a rocker's turn from its
    sketch under ``links``, a slider's travel under ``sliders``, named by its pair)."""
    from linkgen.families.spatial.jets import motion as jet_motion
    from linkgen.families.spatial.kinematics import solve as solve3

    scalar = np.ndim(phi) == 0
    phis = np.atleast_1d(np.asarray(phi, dtype=float))
    w = float(mech.drive.omega if omega is None else omega)
    e = float(mech.drive.epsilon if epsilon is None else epsilon)
    k = solve3(mech, phis)
    n = phis.shape[0]

    def q(jet):
        pos, vel, acc, jerk = jet_motion(jet, w, e)
        return Quantity(*(_shape(x, scalar) for x in (pos, vel, acc, jet.d[1], jet.d[2], jerk, jet.d[3])))

    out = {k.chain.pair_out: q(k.turn)}
    return KinematicsResult(mech.name, float(phis[0]) if scalar else phis, _shape(np.full(n, w), scalar),
                            _shape(np.full(n, e), scalar), {p: q(j) for p, j in k.points.items()},
                            {} if k.chain.output_slides else out, out if k.chain.output_slides else {})


@dataclass(frozen=True, repr=False)
class ForcesResult:
    """Balancing torque [N·m], revolute reactions [N] (2 components), prismatic normal forces
    [N] and moments [N·m], and the reduced inertia J [kg·m²] at crank angles φ."""

    model: str
    phi: np.ndarray | float
    balancing_torque: np.ndarray | float
    reactions: Mapping[str, np.ndarray]
    normal_force: Mapping[str, np.ndarray | float]
    moment: Mapping[str, np.ndarray | float]
    reduced_inertia: np.ndarray | float

    def to_dict(self) -> dict:
        return {"model": self.model, "phi": _plain(self.phi), "units": UNITS,
                "balancing_torque": _plain(self.balancing_torque),
                "reactions": {k: _plain(v) for k, v in self.reactions.items()},
                "normal_force": {k: _plain(v) for k, v in self.normal_force.items()},
                "moment": {k: _plain(v) for k, v in self.moment.items()},
                "reduced_inertia": _plain(self.reduced_inertia)}

    def columns(self) -> dict[str, np.ndarray]:
        cols = {"phi [rad]": np.atleast_1d(self.phi), "balancing_torque [N·m]": np.atleast_1d(self.balancing_torque),
                "reduced_inertia [kg·m²]": np.atleast_1d(self.reduced_inertia)}
        for k, r in self.reactions.items():
            r = np.asarray(r).reshape(-1, 2)
            cols[f"{k}.force.x [N]"], cols[f"{k}.force.y [N]"] = r[:, 0], r[:, 1]
        for k in self.normal_force:
            cols[f"{k}.normal_force [N]"] = np.atleast_1d(self.normal_force[k])
            cols[f"{k}.moment [N·m]"] = np.atleast_1d(self.moment[k])
        return cols

    def __repr__(self) -> str:
        n = np.size(self.phi)
        return (f"ForcesResult({self.model!r}, {n} angle{'s' if n != 1 else ''}, {len(self.reactions)} reactions, "
                f"{len(self.normal_force)} prismatic pairs)")


def forces(source: Mechanism | Assembly, phi, omega=None, epsilon=None) -> ForcesResult:
    """Kinetostatics (``linkgen forces``) at crank angles φ [rad], speed ω, acceleration ε."""
    if _spatial(source):  # a spatial four-bar: SpatialForces (3-D reactions, balancing torque)
        from linkgen.families.spatial.forces import forces as _forces3

        return _forces3(source, np.atleast_1d(np.asarray(phi, dtype=float)), omega, epsilon)
    asm = _assembly(source)
    scalar = np.ndim(phi) == 0
    phis = np.atleast_1d(np.asarray(phi, dtype=float))
    w, e = _rates(asm.mechanism, omega, epsilon)
    f = _forces(asm, phis, w, e)
    return ForcesResult(asm.mechanism.name, float(phis[0]) if scalar else phis, _shape(f.balancing_torque, scalar),
                        {k: _shape(v, scalar) for k, v in f.reactions.items()},
                        {k: _shape(v, scalar) for k, v in f.normal_force.items()},
                        {k: _shape(v, scalar) for k, v in f.moment.items()}, _shape(f.reduced.inertia, scalar))


def _stage(source, name: str):
    """The stage ``name`` of the family of ``source`` (any description ``linkgen.load`` returns,
    or an assembled planar mechanism); UnsupportedError names the families that have it."""
    from linkgen.pipeline.registry import stage

    return stage(source, name)


def write_mjcf(source, settings=None) -> str:
    """The MJCF text (``linkgen build``) of any description: a planar linkage of any structure
    class, a stand-alone cam or a spatial four-bar; ``settings`` (default: derived from the
    mechanism, as ``validate`` runs it)."""
    return _stage(source, "mjcf")(source, settings)


def simulate(source, **options):
    """A MuJoCo run over the drive range (``linkgen simulate``); options as
    ``linkgen.mujoco.simulate.simulate``."""
    return _stage(source, "simulate")(source, **options)


def validate(source, **options):
    """MuJoCo against the closed form (``linkgen validate``), for every family: a result with
    ``.ok``, ``.summary()`` (the line the CLI prints), ``.to_dict()`` (its JSON) and
    ``.diagnosis`` — a ``CrossCheck`` (``linkgen.crosscheck.run``; options as its ``crosscheck``),
    a ``CamLinkageCheck`` for a crank carrying a cam, a ``CamCheck`` (``linkgen.crosscheck.cam``)
    for a stand-alone cam, a ``SpatialCheck`` (``linkgen.crosscheck.spatial``) for a spatial
    four-bar."""
    return _stage(source, "validate")(source, **options)


__all__ = ["ForcesResult", "KinematicsResult", "Quantity", "forces", "kinematics", "simulate", "structure",
           "validate", "write_mjcf"]
