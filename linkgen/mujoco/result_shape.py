"""One shape for every family's validation result (``linkgen validate --json``, a result's
``to_dict()``): the same keys first, whatever the family —

    model, ok;
    settings: the MuJoCo settings of the run compared (None when no run compared anything);
    quantities: name → {relative_error, tolerance, ok, ...} (a linkage's also give max_abs_error,
        peak and scale);
    loop_gap: {relative, tolerance, ok, ...} (a linkage's also max_m and phi [rad], where it is
        largest), None where the mechanism has no closed loop in MuJoCo (a cam);
    diagnosis: [{quantity, ranges [[rad, rad]], relative_error, tolerance, cause, detail}];

then the family's own (steps, wall_s, a spatial chain's kind, a cam's windows, ...). Angles are
radians; the text prints degrees."""

from __future__ import annotations

COMMON = ("model", "ok", "settings", "quantities", "loop_gap", "diagnosis")


def quantity(relative_error: float, tolerance: float, **extra) -> dict:
    """One compared quantity: its error relative to its scale, its tolerance, and whether it holds."""
    return {"relative_error": float(relative_error), "tolerance": float(tolerance),
            "ok": bool(relative_error <= tolerance)} | extra


def loop_gap(relative: float, tolerance: float, **extra) -> dict:
    """The largest loop gap relative to the mechanism's size, its tolerance, and whether it holds."""
    return {"relative": float(relative), "tolerance": float(tolerance), "ok": bool(relative <= tolerance)} | extra


def validation(model: str, ok: bool, *, settings, quantities: dict, loop_gap, diagnosis, **extras) -> dict:
    """A validation result in the shape above: the common keys, then ``extras``."""
    return {"model": model, "ok": bool(ok), "settings": settings, "quantities": quantities, "loop_gap": loop_gap,
            "diagnosis": [f.to_json() for f in diagnosis]} | extras


__all__ = ["COMMON", "loop_gap", "quantity", "validation"]
