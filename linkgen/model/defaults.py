"""Mass properties a link gets when its description gives none."""

# Links without mass properties get these, on both sides (MJCF and closed form), so that
# MuJoCo has a positive mass everywhere: a uniform bar of DEFAULT_DENSITY over the link's
# two first points, or a small block for one-point links.
DEFAULT_DENSITY = 1.0  # kg/m
DEFAULT_BLOCK_MASS = 0.1  # kg
DEFAULT_BLOCK_INERTIA = 1e-4  # kg·m²
