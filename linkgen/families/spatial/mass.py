"""The mass model of a spatial link, the same on both sides (closed form and MJCF): a uniform
rod over the link's first two points, or a small ball for a one-point link."""

from __future__ import annotations

import numpy as np

# The rod's radius and a one-point link's ball radius, as fractions of the mechanism's size:
# they give the inertia about the rod's own line (½·m·r²) and the ball's (0.4·m·r²), which keep
# MuJoCo's mass matrix well conditioned (a coupler on two ball joints spins on that inertia).
ROD_RADIUS = 0.012
POINT_RADIUS = 0.02
# Least principal moment of inertia [kg·m²]: MuJoCo's compiler rejects a fullinertia with an
# eigenvalue below mjEPS = 1e-14 ("inertia must have positive eigenvalues"; measured by
# bisection on mujoco 4.0: 1e-14 compiles, 9.99999e-15 does not), which a light or small link
# reaches (a 5e-10 kg crank of 0.25 mm: m·ℓ²/12 = 2.6e-18). Twice that, so that the
# eigen-decomposition's rounding stays above it. Part of the mass model on both sides (closed
# form and MJCF), so the two still describe the same bodies.
MIN_PRINCIPAL_INERTIA = 2e-14
# Largest rod radius as a fraction of the rod's length (see rod_inertia).
ROD_SLENDERNESS = 0.5


def rod_inertia(mass: float, x: np.ndarray, span2: np.ndarray, size: float) -> np.ndarray:
    """Inertia tensors (n, 3, 3) [kg·m²] about the COM of rods of ``mass`` along unit x (n, 3)
    with squared lengths span2 (n,): m·ℓ²/12 across the line, ½·m·r² along it, each at least
    MIN_PRINCIPAL_INERTIA; span2 = 0 gives the ball of a one-point link."""
    x = np.asarray(x, dtype=float)
    span2 = np.asarray(span2, dtype=float).reshape(-1)
    across = np.maximum(mass * span2 / 12.0, MIN_PRINCIPAL_INERTIA)
    # A rod's radius is at most half its length (ROD_SLENDERNESS): then ½·m·r² ≤ 2·m·ℓ²/12 and its
    # principal moments satisfy the triangle inequality MuJoCo checks (A + B ≥ C), which a short
    # link of a large chain broke with the chain-sized radius (a 0.2 m rocker in a 150 km RSSP).
    radius = np.minimum(ROD_RADIUS * size, ROD_SLENDERNESS * np.sqrt(span2))
    along = np.maximum(np.where(span2 > 0, 0.5 * mass * radius**2, 0.4 * mass * (POINT_RADIUS * size) ** 2),
                       MIN_PRINCIPAL_INERTIA)
    xx = np.einsum("ni,nj->nij", x, x)
    eye = np.eye(3)[None]
    ball = span2 == 0
    return np.where(ball[:, None, None], along[:, None, None] * eye,
                    across[:, None, None] * (eye - xx) + along[:, None, None] * xx)


def link_body(mech, motion, link: str):
    """The mass [kg], the COM's derivative jet (the midpoint of the rod's two points, or the one
    point) and the inertia tensors (n, 3, 3) [kg·m²] about the COM of ``link`` along ``motion``
    (a SpatialMotion of ``mech``)."""
    l = mech.link(link)
    n = motion.phi.shape[0]
    p0 = motion.at(link, l.points[0])
    if len(l.points) >= 2:
        p1 = motion.at(link, l.points[1])
        c = (p0 + p1) * 0.5
        r = (p1 - p0).d[0]
        span2 = np.einsum("ij,ij->i", r, r)
        x = r / np.sqrt(span2)[:, None]
    else:
        c, span2, x = p0, np.zeros(n), np.zeros((n, 3))
    return l.mass, c, rod_inertia(l.mass, x, span2, motion.chain.size)
