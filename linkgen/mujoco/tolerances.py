"""The tolerances of the MuJoCo comparison, each relative to a scale that cannot vanish
(``linkgen.crosscheck.compare``)."""

# Every kinematic quantity within this fraction of its scale.
REL_TOL = 1e-6
# The loop gap of a run without the closed form's scan (no σ_min known: ``gap_tolerance`` derives
# the planar linkages' from the positions' tolerance), and of the spatial chains: within this
# fraction of the mechanism's size (a gap turns into position errors of gap/σ, σ the loop
# Jacobian's smallest singular value, see mujoco.settings; 1e-8 is REL_TOL at σ = 0.01).
GAP_TOL = 1e-8
# Forces: the forward run within this of the scale, like the kinematics it rests on; the inverse
# route (closed-form state, no integration) within this, a few hundred roundings.
FORCE_TOL = 1e-6
INVERSE_TOL = 1e-10


def gap_tolerance(sigma_min: float) -> float:
    """The loop gap's tolerance relative to the size, derived from the positions' it protects: a
    gap r moves the joints by up to r/σ_min (σ_min the loop Jacobian's smallest singular value over
    the non-driven joints, columns made dimensionless by the size; ``mujoco.settings.sigma_min``),
    so r ≤ REL_TOL·min(σ_min, 1)·size keeps every position within REL_TOL of the size. σ_min is
    capped at 1: a gap larger than the position tolerance is never accepted, however well the
    loops are conditioned. A mechanism without the scan (no closed form) keeps GAP_TOL."""
    if not (sigma_min > 0.0 and sigma_min == sigma_min):
        return GAP_TOL
    return REL_TOL * min(float(sigma_min), 1.0)
