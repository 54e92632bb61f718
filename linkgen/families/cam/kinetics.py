"""The cam mechanism's motion and forces in closed form, at a constant cam speed ω.

The follower's coordinate q (s [m] for a translating follower, ψ − ψ_lowest [rad] for an
oscillating one) is q(θ) with θ = ω·t, so q̇ = q′·ω, q̈ = q″·ω², q⃛ = q‴·ω³. Frictionless contact:
the generalised force the cam must supply is Q = m·q̈ + F_spring(q) − m·g·u (translating; an
oscillating follower uses its inertia about the pivot and a spring torque, its weight taken at
the pivot), F_spring = preload + rate·q. The contact force N along the normal n follows from
N·(n·dC/dq) = Q, and the cam's driving torque from the power balance T·ω = Q·q̇, T = Q·q′ — the
same as the moment of N·n about the cam's axis (checked in the tests). The follower stays on the
cam while N ≥ 0: for Q to stay ≥ 0 at every θ, ω may not pass
ω_leave = min over q″ < 0 of √((F_spring − m·g·u)/(−m·q″))."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from linkgen.families.cam.description import CamMechanism
from linkgen.errors import SingularityError, angle_ranges

# Cam angles over a turn at which the leave speed and peaks are taken: one every 0.1°.
SAMPLES = 3600


@dataclass(frozen=True)
class CamState:
    """At cam angles θ (n,) [rad] and speed ω [rad/s]: the follower's displacement from its lowest
    position q, velocity, acceleration, jerk (m…, or rad… for an oscillating follower), the
    pressure angle α [rad], the contact force N [N], the cam's driving torque T [N·m] and the
    spring force [N, or N·m]."""

    theta: np.ndarray
    omega: float
    displacement: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    jerk: np.ndarray
    pressure_angle: np.ndarray
    contact_force: np.ndarray
    cam_torque: np.ndarray
    spring: np.ndarray


def _inertia(cm: CamMechanism) -> float:
    return cm.inertia if cm.follower.kind == "oscillating" else cm.mass


def _weight_along(cm: CamMechanism) -> float:
    """m·g·u: the weight's component along the translating follower's motion (+y) [N]."""
    return cm.mass * cm.gravity[1] if cm.follower.kind == "translating" else 0.0


def state(cm: CamMechanism, theta, omega: float | None = None) -> CamState:
    """The closed form at cam angles θ [rad] (scalar or (n,)) and speed ω (default the cam's)."""
    w = cm.omega if omega is None else float(omega)
    th = np.atleast_1d(np.asarray(theta, dtype=float))
    f = cm.follower
    q, q1, q2, q3 = f.output(th)
    c, _, _, u = f.centre(th)
    n = f.normal(th)
    dcdq = u * (f.arm_length if f.kind == "oscillating" else 1.0)
    spring = cm.spring_preload + cm.spring_rate * q
    big_q = _inertia(cm) * q2 * w * w + spring - _weight_along(cm)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        contact = big_q / np.sum(n * dcdq, axis=1)
    bad = ~np.isfinite(contact)
    if np.any(bad):  # never a silent inf: the follower's pivot on the cam's axis, say
        raise SingularityError("cam follower", angle_ranges(th, bad),
                               "the profile's normal is square to the follower's motion (pressure angle 90°), "
                               "so no finite contact force drives it; move the follower's pivot or guide off "
                               "the cam's axis")
    return CamState(th, w, q, q1 * w, q2 * w * w, q3 * w**3, f.pressure_angle(th), contact, big_q * q1, spring)


def leave_speed(cm: CamMechanism) -> float:
    """The cam speed [rad/s] above which the follower would leave the cam somewhere in the turn
    (inf if it never would; 0 if the spring cannot hold it even at rest). The least hold and
    the least hold/pull ratio are refined between samples (``linkgen.extrema``)."""
    from linkgen.extrema import peak, samples

    turn = 2 * math.pi
    m = _inertia(cm)

    def hold_pull(th):
        q, _, q2, _ = cm.follower.output(th)
        return cm.spring_preload + cm.spring_rate * q - _weight_along(cm), -m * q2

    def ratio(th):
        hold, pull = hold_pull(th)
        return np.where(pull > 0, hold / np.where(pull > 0, pull, 1.0), np.inf)

    th = samples(0.0, turn, SAMPLES, periodic=True)
    hold, pull = hold_pull(th)
    if peak(lambda x: hold_pull(x)[0], th, hold, kind="min", period=turn)[1] < 0:
        return 0.0
    if not np.any(pull > 0):
        return math.inf
    return float(np.sqrt(peak(ratio, th, ratio(th), kind="min", period=turn)[1]))


__all__ = ["CamState", "SAMPLES", "leave_speed", "state"]
