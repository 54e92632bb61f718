"""A cam mechanism's design summary over a turn at a constant cam speed: the stroke, the largest
pressure angle, the least radius of curvature of the profile, the contact force's range, the
peak balancing torque on the cam, the leave speed and the smallest base circle for a 30° pressure angle. Every
extremum is found on SAMPLES cam angles and refined by Brent's method (``linkgen.extrema``),
round the wrap from 2π to 0 included."""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Mapping

import numpy as np

from linkgen.families.cam.description import CamMechanism
from linkgen.families.cam.kinetics import SAMPLES, leave_speed, state
from linkgen.extrema import peak, samples
from linkgen.model.summary import Extreme, Output, summary_dict

TURN = 2 * math.pi
# The follower's name: the output's key in the summary and in the kinematics' followers.
FOLLOWER = "follower"


def _extreme(fun, theta: np.ndarray, values: np.ndarray, kind: str = "max") -> tuple[float, float]:
    """(cam angle [rad], value) of the refined extreme of ``fun`` over the turn."""
    return peak(fun, theta, values, kind=kind, period=TURN)


@dataclass(frozen=True)
class CamSummary:
    """The keys every family's summary shares (``linkgen.model.summary``: the follower is the
    output "follower", kind "slider" for a translating follower [m] and "rocker" for an
    oscillating one [rad], its travel the stroke; the balancing torque is the torque the cam
    needs) and the cam's own: ``kind`` (the follower's: "translating" or "oscillating"),
    ``base_radius`` [m], ``max_pressure_angle`` (largest |α| [rad]),
    ``min_profile_curvature_radius`` [m], ``convex``, ``undercut``, ``peak_contact_force`` and
    ``min_contact_force`` [N], ``leave_speed`` [rad/s] (None: the follower never leaves the cam)
    and ``smallest_base_radius_for_30deg`` [m] (None for a flat face, whose pressure angle is 0).
    The follower's limit positions are its program's dwells (not located: ``limits`` None), so
    there is no time ratio; a cam has no pair reactions here, only its contact force."""

    model: str
    omega: float
    epsilon: float
    drive_range: tuple[float, float]
    kind: str
    outputs: Mapping[str, Output]
    peak_balancing_torque: Extreme
    base_radius: float
    max_pressure_angle: Extreme
    min_profile_curvature_radius: Extreme
    convex: bool
    undercut: bool
    peak_contact_force: Extreme
    min_contact_force: float
    leave_speed: float | None
    smallest_base_radius_for_30deg: float | None

    @property
    def units(self) -> dict[str, str]:
        return {"phi": "rad", "drive_range": "rad", "slider": "m", "rocker": "rad", "peak_balancing_torque": "N·m",
                "base_radius": "m", "max_pressure_angle": "rad", "min_profile_curvature_radius": "m",
                "peak_contact_force": "N", "min_contact_force": "N", "leave_speed": "rad/s",
                "smallest_base_radius_for_30deg": "m"}

    def to_dict(self) -> dict:
        return summary_dict(self)

    def text(self) -> str:
        (out,) = self.outputs.values()
        unit = "m" if out.kind == "slider" else "rad"
        deg = math.degrees
        a, r, t = self.max_pressure_angle, self.min_profile_curvature_radius, self.peak_balancing_torque
        shape = "convex" if self.convex else "concave in places"
        lines = [f"{self.model}: {self.kind} follower, base circle {self.base_radius:.6g} m, "
                 f"at ω = {self.omega:g} rad/s",
                 f"  stroke {out.travel:.6g} {unit}" + (f" ({deg(out.travel):.4g}°)" if unit == "rad" else ""),
                 f"  largest pressure angle {deg(a.value):.4g}° at φ = {deg(a.phi):.4g}°",
                 f"  profile {shape}; least radius of curvature {r.value:.6g} m at φ = {deg(r.phi):.4g}°"
                 + ("; UNDERCUT: the roller is larger than the pitch curve's radius there" if self.undercut else ""),
                 f"  contact force {self.min_contact_force:.6g}..{self.peak_contact_force.value:.6g} N; peak balancing "
                 f"torque {t.value:.6g} N·m at φ = {deg(t.phi):.4g}°"]
        if self.smallest_base_radius_for_30deg is not None:
            lines.append(f"  the smallest base circle keeping the pressure angle within 30°: "
                         f"{self.smallest_base_radius_for_30deg:.6g} m")
        lv = self.leave_speed
        lines.append("  the follower never leaves the cam" if lv is None else
                     f"  the follower leaves the cam above ω = {lv:.6g} rad/s" + (" — it does at this speed"
                                                                                  if self.omega > lv else ""))
        return "\n".join(lines)


def cam_summary(cm: CamMechanism, omega: float) -> CamSummary:
    """The cam's design figures over a turn at speed ω [rad/s] (SI units, radians): values and
    the cam angles φ where they occur."""
    theta = samples(0.0, TURN, SAMPLES, periodic=True)
    st = state(cm, theta, omega)
    f = cm.follower

    def of(name: str):
        return lambda th: getattr(state(cm, th, omega), name)

    _, top = _extreme(of("displacement"), theta, st.displacement)
    _, bottom = _extreme(of("displacement"), theta, st.displacement, "min")
    a_at, alpha = _extreme(lambda th: np.abs(f.pressure_angle(th)), theta, np.abs(st.pressure_angle))
    rho = f.profile_curvature_radius(theta)
    r_at, r_min = _extreme(f.profile_curvature_radius, theta, rho, "min")
    n_at, n_max = _extreme(of("contact_force"), theta, st.contact_force)
    _, n_min = _extreme(of("contact_force"), theta, st.contact_force, "min")
    t_at, t_max = _extreme(lambda th: np.abs(state(cm, th, omega).cam_torque), theta, np.abs(st.cam_torque))
    follower = Output("slider" if f.kind == "translating" else "rocker", float(top - bottom), None)
    leave = leave_speed(cm)
    return CamSummary(cm.name, omega, 0.0, (0.0, TURN), f.kind, {FOLLOWER: follower}, Extreme(t_max, t_at),
                      f.base_radius, Extreme(alpha, a_at), Extreme(r_min, r_at), bool(r_min > 0),
                      bool(np.any(f.undercut(theta))), Extreme(n_max, n_at), n_min,
                      None if math.isinf(leave) else leave, _smallest(f, math.radians(30.0)))


def _smallest(f, alpha: float) -> float | None:
    from linkgen.families.cam.follower import smallest_base_radius

    if f.flat:  # a flat face's pressure angle is 0 whatever the base circle
        return None
    try:
        return smallest_base_radius(f, alpha)
    except ValueError:
        return None


__all__ = ["CamSummary", "FOLLOWER", "cam_summary"]
