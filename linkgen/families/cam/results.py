"""The stand-alone cam's closed-form stages as results (``linkgen analyze|profile``,
``linkgen.kinematics|summary``): ``to_dict()`` (JSON), ``columns()`` (CSV) and ``text()``, one
name per quantity in all three (``linkgen.model.results``). The drive angle is the cam angle φ;
the follower is named ``follower``, the cam ``cam``."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, Mapping

import numpy as np

from linkgen.errors import ArgumentError
from linkgen.families.cam.summary import FOLLOWER
from linkgen.model.results import AngleMotion, ContactForce, SlideMotion, column, per_sample, plain, shaped

# The stand-alone cam's one pair: the cam (the driven link) and the follower.
CAM = "cam"

UNITS = {"phi": "rad", "omega": "rad/s", "epsilon": "rad/s²", "displacement": "m", "velocity": "m/s",
         "acceleration": "m/s²", "jerk": "m/s³", "angle": "rad", "angular_velocity": "rad/s",
         "angular_acceleration": "rad/s²", "angular_jerk": "rad/s³", "pressure_angle": "rad", "normal_force": "N",
         "balancing_torque": "N·m"}


@dataclass(frozen=True, repr=False)
class SlidingFollower(SlideMotion):
    """A translating follower: its displacement [m] from the lowest position, velocity,
    acceleration, jerk (as a planar slider) and the pressure angle [rad]."""

    pressure_angle: np.ndarray | float | None = None
    UNITS: ClassVar[dict[str, str]] = SlideMotion.UNITS | {"pressure_angle": "rad"}


@dataclass(frozen=True, repr=False)
class RockingFollower(AngleMotion):
    """An oscillating follower: its angle ψ − ψ0 [rad] from the lowest position, angular velocity,
    acceleration, jerk (as a planar rocker) and the pressure angle [rad]."""

    pressure_angle: np.ndarray | float | None = None
    UNITS: ClassVar[dict[str, str]] = AngleMotion.UNITS | {"pressure_angle": "rad"}


@dataclass(frozen=True, repr=False)
class CamKinematics:
    """The follower's motion at the cam angles ``phi`` [rad] (φ = 0 where the first segment
    starts), speed ``omega`` [rad/s] (constant: ``epsilon`` 0), with the loads that come with
    it: the ``contact`` force on the follower by the cam (along the profile's normal,
    ``normal_force`` [N], as a planar cam pair's) and the ``balancing_torque`` [N·m] the cam
    needs (as a planar crank's)."""

    model: str
    kind: str
    phi: np.ndarray | float
    omega: float
    epsilon: float
    followers: Mapping[str, SlidingFollower | RockingFollower]
    contact: Mapping[str, ContactForce]
    balancing_torque: np.ndarray | float
    ROWS: ClassVar[str] = "cam angles"

    def to_dict(self, transfer: bool = True) -> dict:
        return {"model": self.model, "kind": self.kind, "phi": plain(self.phi), "omega": self.omega,
                "epsilon": self.epsilon, "units": UNITS,
                "followers": {n: f.to_dict() for n, f in self.followers.items()},
                "contact": {n: c.to_dict() for n, c in self.contact.items()},
                "balancing_torque": plain(self.balancing_torque)}

    def columns(self, transfer: bool = True) -> dict[str, np.ndarray]:
        cols = {"phi [rad]": column(self.phi)}
        for table in (self.followers, self.contact):
            for n, q in table.items():
                cols |= q.columns(n)
        return cols | {"balancing_torque [N·m]": column(self.balancing_torque)}

    def singular_lines(self) -> list[str]:
        return []

    @per_sample
    def text(self, transfer: bool = False) -> str:
        f, c = self.followers[FOLLOWER], self.contact[CAM]
        names = f.names(transfer=False)[:4]
        return "\n".join([
            f"{self.model}: {self.kind} follower at cam angle φ = {math.degrees(float(self.phi)):.6g}°, "
            f"ω = {self.omega:g} rad/s",
            "  " + ", ".join(f"{q.replace('_', ' ')} {float(getattr(f, q)):.6g} {f.unit(q)}" for q in names)
            + " (from the lowest position)",
            f"  pressure angle {math.degrees(float(f.pressure_angle)):.6g}°, contact force {float(c.normal_force):.6g} N, "
            f"balancing torque on the cam {float(self.balancing_torque):.6g} N·m"])

    def __repr__(self) -> str:
        return f"CamKinematics({self.model!r}, {np.size(self.phi)} cam angles)"


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
    cls = SlidingFollower if cm.follower.kind == "translating" else RockingFollower
    f = cls(*(shaped(getattr(st, q), scalar) for q in ("displacement", "velocity", "acceleration", "jerk")),
            pressure_angle=shaped(st.pressure_angle, scalar))
    return CamKinematics(cm.name, cm.follower.kind, float(theta[0]) if scalar else theta, w, 0.0, {FOLLOWER: f},
                         {CAM: ContactForce(shaped(st.contact_force, scalar), FOLLOWER, CAM)},
                         shaped(st.cam_torque, scalar))


def summary(cm, omega=None, epsilon=None):
    """The cam family's ``summary`` stage over one turn at ω (default the description's): a
    ``families.cam.summary.CamSummary``."""
    from linkgen.families.cam.summary import cam_summary

    return cam_summary(cm, _speed(cm, omega, epsilon))


@dataclass(frozen=True, repr=False)
class CamProfile:
    """The cam's profile and pitch curve [m] (n, 2) at the cam angles ``phi`` [rad]."""

    model: str
    phi: np.ndarray
    profile: np.ndarray
    pitch: np.ndarray

    def to_dict(self) -> dict:
        return {"model": self.model, "phi": plain(self.phi), "profile": plain(self.profile),
                "pitch": plain(self.pitch), "units": {"phi": "rad", "profile": "m", "pitch": "m"}}

    def columns(self) -> dict[str, np.ndarray]:
        return {"phi [rad]": self.phi, "profile.x [m]": self.profile[:, 0], "profile.y [m]": self.profile[:, 1],
                "pitch.x [m]": self.pitch[:, 0], "pitch.y [m]": self.pitch[:, 1]}

    def __repr__(self) -> str:
        return f"CamProfile({self.model!r}, {self.phi.shape[0]} points)"


def profile(cm, points: int = 720) -> CamProfile:
    """The cam family's ``profile`` stage: ``points`` cam angles over the turn."""
    theta = np.linspace(0.0, 2 * math.pi, points, endpoint=False)
    return CamProfile(cm.name, theta, cm.follower.profile(theta), cm.follower.pitch_curve(theta)[0])


__all__ = ["CAM", "CamKinematics", "RockingFollower", "SlidingFollower", "CamProfile", "kinematics", "profile", "summary"]
