"""Physical limits of a description: the magnitudes float64 carries through the whole pipeline
(closed form, kinetostatics, MuJoCo) with full precision and finite results.

Measured with ``validation/limits_scan.py``: every bundled model (sizes 0.3-1.5 m) rescaled in
length by s, in mass by mu and in time, and checked against the unscaled model by the scaling
laws of mechanics. Kinematics and forces hold to 7e-13 of their peaks for s from 1e-102 to 1e16;
below 1e-104 products of three lengths leave float64's normal range (2.2e-308) and answers go
wrong (ZeroDivisionError at 1e-170 and below); above 1e16 the crank's equilibrium equations
(forces in N, moments in N·m in one system) lose all precision (0.3 relative error at 1e18),
and from 1e110 squares of lengths overflow. Masses and rates scale linearly and hold over
1e-300..1e300 and 1e-150..1e150 on their own, so their bounds come from the products below.

The bounds keep every output (forces up to mass·ω²·size, torques and reduced moments up to
mass·ω²·size², reduced inertia mass·size²) below 1e120, so that squares and sums of squares of
outputs (norms, comparisons) stay finite too.
"""

from __future__ import annotations

# Largest |coordinate|, link length, guide offset, centre of mass or extent of a mechanism [m]:
# 1e4 below the measured 1e16 where the crank's equilibrium system loses precision.
MAX_LENGTH = 1e12

# Smallest extent of a mechanism (largest distance between two of its points) and smallest
# distance between a moving link's first two points (its x axis) [m]: 1e12 above the measured
# 1e-102 where products of three lengths leave float64's normal range.
MIN_LENGTH = 1e-90

# Smallest mass of a moving link [kg]: MuJoCo's compiler rejects a moving body lighter than
# mjMINVAL = 1e-15 ("mass and inertia of moving bodies must be larger than mjMINVAL");
# measured with MuJoCo 3.x: 1e-15 compiles, 9.9e-16 does not.
MIN_MASS = 1e-15

# Largest mass of a link [kg]; with MAX_LENGTH and MAX_OMEGA the largest inertia torque is
# MAX_MASS·MAX_OMEGA²·MAX_LENGTH² = 1e114 N·m < 1e120.
MAX_MASS = 1e30

# Largest moment of inertia about the centre of mass [kg·m²]: a body of MAX_MASS spread over
# MAX_LENGTH.
MAX_INERTIA = 1e54  # = MAX_MASS·MAX_LENGTH²

# Largest |ω| [rad/s]: ω² enters every acceleration; ω² = 1e60.
MAX_OMEGA = 1e30

# Smallest ω of a stand-alone cam, which must turn [rad/s]: 1/MAX_OMEGA, so that ω² (1e-60) stays
# in float64's normal range and a turn (2π/ω) and the cam shaft's inertia (∝ 1/ω²) stay finite.
MIN_CAM_OMEGA = 1e-30  # = 1/MAX_OMEGA

# Largest |ε| [rad/s²]: MAX_OMEGA², so that ε and ω² terms share one range.
MAX_EPSILON = 1e60  # = MAX_OMEGA²

# Largest |gravity| component [m/s²]: the largest centripetal acceleration MAX_OMEGA²·MAX_LENGTH,
# so that weights and inertia forces share one range.
MAX_GRAVITY = 1e72  # = MAX_OMEGA²·MAX_LENGTH

# Largest |point force| component [N]: MAX_MASS times the largest acceleration MAX_GRAVITY,
# so that given loads and inertia forces share one range (1e102 N).
MAX_FORCE = 1e102  # = MAX_MASS·MAX_GRAVITY

# Largest |link torque| [N·m]: MAX_FORCE on an arm of MAX_LENGTH.
MAX_TORQUE = 1e114  # = MAX_FORCE·MAX_LENGTH

# Largest |angle| [rad] (guide angles, drive range, load strokes, --angle): about 1600 turns,
# where float64's spacing is still 1.8e-12 rad, so a crank angle keeps 12 digits.
MAX_ANGLE = 1e4

# Most teeth of a gear: 2**53, the largest count float64 carries exactly, so that radii and
# ratios computed from tooth counts are exact; a gear's pitch radius m·z/2 must also stay within
# MAX_LENGTH (checked with the module).
MAX_TEETH = 2**53

# Shortest bar MuJoCo draws [m]: the MJCF shows a link as capsules from its first point to each
# other point, and MuJoCo's compiler rejects a capsule whose half-length is below mjEPS = 1e-6
# ("fromto points too close in geom"; measured: the four-bar builds at scale 1e-6, not 1e-7).
# Not a limit of the description: only ``linkgen build`` and the MuJoCo commands need it.
MJCF_MIN_BAR = 2e-6

# Most crank angles one call evaluates (the CLI's --samples, the API's samples and points): the
# benchmark's size; the solution's arrays then take some 0.3 GB and the CSV about 1 GB.
MAX_SAMPLES = 10**6


__all__ = ["MAX_SAMPLES", 
    "MAX_LENGTH", "MIN_LENGTH", "MIN_MASS", "MAX_MASS", "MAX_INERTIA", "MAX_OMEGA", "MIN_CAM_OMEGA", "MAX_EPSILON",
    "MAX_GRAVITY", "MAX_FORCE", "MAX_TORQUE", "MAX_ANGLE", "MAX_TEETH", "MJCF_MIN_BAR",
]
