"""When a load acts: a description's ``stroke = [from, to]`` over the crank angle. Every family
and both sides (closed form and MuJoCo) read their loads' windows through ``stroke_active``."""

from __future__ import annotations

import math

import numpy as np


def stroke_active(force, phi) -> np.ndarray:
    """True where the load acts: everywhere without a stroke (``force.stroke is None``), else
    where the crank angle lies in [from, to] modulo one revolution. ``phi`` [rad], shape (n,) →
    (n,) bool."""
    phi = np.asarray(phi, dtype=float)
    if force.stroke is None:
        return np.ones(phi.shape, dtype=bool)
    lo, hi = force.stroke
    width = hi - lo
    if width >= 2 * math.pi:
        return np.ones(phi.shape, dtype=bool)
    return np.mod(phi - lo, 2 * math.pi) <= width


__all__ = ["stroke_active"]
