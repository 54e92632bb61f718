"""A cam mechanism's design summary over a turn at a constant cam speed: the stroke, the largest
pressure angle, the least radius of curvature of the profile, the contact force's range, the
peak cam torque, the leave speed and the smallest base circle for a 30° pressure angle. Every
extremum is found on SAMPLES cam angles and refined by Brent's method (``linkgen.extrema``),
round the wrap from 2π to 0 included."""

from __future__ import annotations

import math

import numpy as np

from linkgen.families.cam.description import CamMechanism
from linkgen.families.cam.kinetics import SAMPLES, leave_speed, state
from linkgen.extrema import peak, samples

TURN = 2 * math.pi


def _extreme(fun, theta: np.ndarray, values: np.ndarray, kind: str = "max") -> tuple[float, float]:
    """(cam angle [rad], value) of the refined extreme of ``fun`` over the turn."""
    return peak(fun, theta, values, kind=kind, period=TURN)


def cam_summary(cm: CamMechanism, omega: float) -> dict:
    """The cam's design figures over a turn at speed ω [rad/s] (SI units, radians): values and
    the cam angles ("at") where they occur."""
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
    return {"model": cm.name, "omega": omega, "kind": f.kind, "base_radius": f.base_radius,
            "stroke": float(top - bottom),
            "max_pressure_angle": {"value": alpha, "at": a_at},
            "min_profile_curvature_radius": {"value": r_min, "at": r_at},
            "convex": bool(r_min > 0), "undercut": bool(np.any(f.undercut(theta))),
            "peak_contact_force": {"value": n_max, "at": n_at},
            "min_contact_force": n_min,
            "peak_cam_torque": {"value": t_max, "at": t_at},
            "leave_speed": leave_speed(cm),
            "smallest_base_radius_for_30deg": _smallest(f, math.radians(30.0))}


def _smallest(f, alpha: float) -> float | None:
    from linkgen.families.cam.follower import smallest_base_radius

    if f.flat:  # a flat face's pressure angle is 0 whatever the base circle
        return None
    try:
        return smallest_base_radius(f, alpha)
    except ValueError:
        return None


__all__ = ["cam_summary"]
