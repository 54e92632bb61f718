"""The tolerances of the MuJoCo comparison, each relative to a scale that cannot vanish
(``linkgen.crosscheck.compare``)."""

# Every kinematic quantity within this fraction of its scale.
REL_TOL = 1e-6
# The loop gap, at every step of the compared part, within this fraction of the mechanism's size
# (1e-8 m on the metre-sized bundled models; a gap turns into position errors of gap/σ, σ the
# loop Jacobian's smallest singular value, see mujoco.settings).
GAP_TOL = 1e-8
# Forces: the forward run within this of the scale, like the kinematics it rests on; the inverse
# route (closed-form state, no integration) within this, a few hundred roundings.
FORCE_TOL = 1e-6
INVERSE_TOL = 1e-10
