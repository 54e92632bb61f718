"""The mass model of a spatial link, the same on both sides (closed form and MJCF): a uniform
rod over the link's first two points, or a small ball for a one-point link."""

from __future__ import annotations

import numpy as np

# The rod's radius and a one-point link's ball radius, as fractions of the mechanism's size:
# they give the inertia about the rod's own line (½·m·r²) and the ball's (0.4·m·r²), which keep
# MuJoCo's mass matrix well conditioned (a coupler on two ball joints spins on that inertia).
ROD_RADIUS = 0.012
POINT_RADIUS = 0.02


def rod_inertia(mass: float, x: np.ndarray, span2: np.ndarray, size: float) -> np.ndarray:
    """Inertia tensors (n, 3, 3) [kg·m²] about the COM of rods of ``mass`` along unit x (n, 3)
    with squared lengths span2 (n,): m·ℓ²/12 across the line, ½·m·r² along it; span2 = 0 gives
    the ball of a one-point link."""
    x = np.asarray(x, dtype=float)
    span2 = np.asarray(span2, dtype=float).reshape(-1)
    across = mass * span2 / 12.0
    along = np.where(span2 > 0, 0.5 * mass * (ROD_RADIUS * size) ** 2, 0.4 * mass * (POINT_RADIUS * size) ** 2)
    xx = np.einsum("ni,nj->nij", x, x)
    eye = np.eye(3)[None]
    ball = span2 == 0
    return np.where(ball[:, None, None], along[:, None, None] * eye,
                    across[:, None, None] * (eye - xx) + along[:, None, None] * xx)
