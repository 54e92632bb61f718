"""The stand-alone cam's closed-form stages as results (``linkgen analyze|profile``,
``linkgen.kinematics|summary``): ``to_dict()`` (JSON), ``columns()`` (CSV) and ``text()``, one
name per quantity in all three (``linkgen.model.results``). The drive angle is the cam angle θ
(``phi`` in JSON as well); the follower is named ``follower``."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, Mapping

import numpy as np

from linkgen.errors import ArgumentError
from linkgen.families.cam.summary import FOLLOWER
from linkgen.model.results import Record, column, per_sample, plain, shaped

UNITS = {"theta": "rad", "omega": "rad/s", "translating": "m, m/s, m/s², m/s³",
         "oscillating": "rad, rad/s, rad/s², rad/s³", "pressure_angle": "rad", "contact_force": "N", "cam_torque": "N·m"}


@dataclass(frozen=True, repr=False)
class CamFollowerMotion(Record):
    """The follower: displacement from its lowest position (m translating, rad oscillating), its
    velocity, acceleration and jerk, the pressure angle [rad], the contact force [N] and the
    torque [N·m] the cam needs."""

    displacement: np.ndarray | float
    velocity: np.ndarray | float
    acceleration: np.ndarray | float
    jerk: np.ndarray | float
    pressure_angle: np.ndarray | float
    contact_force: np.ndarray | float
    cam_torque: np.ndarray | float
    unit: str = "m"
    UNIT: ClassVar[str] = "m"

    def to_dict(self, transfer: bool = True) -> dict:
        return {k: v for k, v in super().to_dict().items() if k != "unit"}

    def columns(self, name: str, quantities=None, transfer: bool = True) -> dict[str, np.ndarray]:
        u = self.unit
        units = {"displacement": u, "velocity": f"{u}/s", "acceleration": f"{u}/s²", "jerk": f"{u}/s³",
                 "pressure_angle": "rad", "contact_force": "N", "cam_torque": "N·m"}
        return {f"{name}.{q} [{un}]": column(getattr(self, q)) for q, un in units.items()}


@dataclass(frozen=True, repr=False)
class CamKinematics:
    """The follower's motion and loads at the cam angles ``theta`` [rad] (= ``phi``), speed
    ``omega`` [rad/s] (constant)."""

    model: str
    kind: str
    theta: np.ndarray | float
    omega: float
    followers: Mapping[str, CamFollowerMotion]
    ROWS: ClassVar[str] = "cam angles"
    NO_TRANSFER: ClassVar[str] = "--transfer and --keep-singular are for linkages; a cam's derivatives come with --json"

    @property
    def phi(self):
        """The drive angle: the cam angle θ [rad]."""
        return self.theta

    def to_dict(self, transfer: bool = True) -> dict:
        return {"model": self.model, "theta": plain(self.theta), "phi": plain(self.theta), "omega": self.omega,
                "units": UNITS, "followers": {n: f.to_dict() for n, f in self.followers.items()}}

    def columns(self, transfer: bool = True) -> dict[str, np.ndarray]:
        cols = {"theta [rad]": column(self.theta)}
        for n, f in self.followers.items():
            cols |= f.columns(n)
        return cols

    def singular_lines(self) -> list[str]:
        return []

    @per_sample
    def text(self, transfer: bool = False) -> str:
        f = self.followers[FOLLOWER]
        theta = float(self.theta)
        unit = f.unit
        return "\n".join([
            f"{self.model}: {self.kind} follower at cam angle θ = {math.degrees(theta):.6g}°, ω = {self.omega:g} rad/s",
            f"  displacement {float(f.displacement):.6g} {unit} (from the lowest position), velocity "
            f"{float(f.velocity):.6g} {unit}/s, acceleration {float(f.acceleration):.6g} {unit}/s², jerk "
            f"{float(f.jerk):.6g} {unit}/s³",
            f"  pressure angle {math.degrees(float(f.pressure_angle)):.6g}°, contact force {float(f.contact_force):.6g} N, "
            f"cam torque {float(f.cam_torque):.6g} N·m"])

    def __repr__(self) -> str:
        return f"CamKinematics({self.model!r}, {np.size(self.theta)} cam angles)"


def _speed(cm, omega, epsilon) -> float:
    if epsilon not in (None, 0.0):
        raise ArgumentError(f"epsilon: a cam turns at a constant speed here; epsilon must be 0 or left out, "
                            f"got {epsilon!r} rad/s²")
    w = cm.omega if omega is None else float(omega)
    if not w > 0:
        raise ArgumentError(f"omega must be > 0 (the cam turns counter-clockwise), got {w:g} rad/s")
    return w


def kinematics(cm, phi, omega=None, epsilon=None, *, on_singular: str = "raise") -> CamKinematics:
    """The cam family's ``kinematics`` stage at cam angles ``phi`` [rad] (scalar or (n,))."""
    from linkgen.families.cam.kinetics import state

    w = _speed(cm, omega, epsilon)
    scalar = np.ndim(phi) == 0
    theta = np.atleast_1d(np.asarray(phi, dtype=float))
    st = state(cm, theta, w)
    unit = "m" if cm.follower.kind == "translating" else "rad"
    f = CamFollowerMotion(*(shaped(getattr(st, q), scalar) for q in ("displacement", "velocity", "acceleration", "jerk",
                                                                      "pressure_angle", "contact_force", "cam_torque")),
                          unit=unit)
    return CamKinematics(cm.name, cm.follower.kind, float(theta[0]) if scalar else theta, w, {FOLLOWER: f})


def summary(cm, omega=None, epsilon=None):
    """The cam family's ``summary`` stage over one turn at ω (default the description's): a
    ``families.cam.summary.CamSummary``."""
    from linkgen.families.cam.summary import cam_summary

    return cam_summary(cm, _speed(cm, omega, epsilon))


@dataclass(frozen=True, repr=False)
class CamProfile:
    """The cam's profile and pitch curve [m] (n, 2) at the cam angles ``theta`` [rad]."""

    model: str
    theta: np.ndarray
    profile: np.ndarray
    pitch: np.ndarray

    def to_dict(self) -> dict:
        return {"model": self.model, "theta": plain(self.theta), "profile": plain(self.profile),
                "pitch": plain(self.pitch), "units": {"theta": "rad", "profile": "m", "pitch": "m"}}

    def columns(self) -> dict[str, np.ndarray]:
        return {"theta [rad]": self.theta, "profile.x [m]": self.profile[:, 0], "profile.y [m]": self.profile[:, 1],
                "pitch.x [m]": self.pitch[:, 0], "pitch.y [m]": self.pitch[:, 1]}

    def __repr__(self) -> str:
        return f"CamProfile({self.model!r}, {self.theta.shape[0]} points)"


def profile(cm, points: int = 720) -> CamProfile:
    """The cam family's ``profile`` stage: ``points`` cam angles over the turn."""
    theta = np.linspace(0.0, 2 * math.pi, points, endpoint=False)
    return CamProfile(cm.name, theta, cm.follower.profile(theta), cm.follower.pitch_curve(theta)[0])


__all__ = ["CamFollowerMotion", "CamKinematics", "CamProfile", "kinematics", "profile", "summary"]
