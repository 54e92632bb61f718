"""A plan's vertices. An RCCC chain's velocity and acceleration plans pass through its cylindrical pairs: the later
link's copy of a pair's point is reached from the first link's point by the first link's point
under it and the pair's slide (Coriolis included), and every chain closes on the closed form's
vertex. Drawn without the slides, the RCCC plan missed its vertices by 0.82 of its size. A point
named P (Andrews' squeezer's crank pin) took the velocity pole's name p: its vertex replaced the
pole's and the drawing showed "p" away from the pole; the pole is now p₀ there."""

import math

import numpy as np
import pytest

from conftest import ROOT
from linkgen.pipeline.registry import load

# A chain's end against its vertex, a fraction of the plan's size: about ten vectors of the plan's
# size summed in double precision miss by ~1e-15; 1e-9 leaves room and still fails a lost slide
# (0.1..1 of the size).
CLOSES = 1e-9
ANGLES_DEG = (0.0, 40.0, 130.0, 250.0)


@pytest.mark.parametrize("kind", ["velocity", "acceleration"])
def test_rccc_plans_close_through_the_cylindrical_pairs(kind):
    from linkgen.families.spatial.kinematics import assembled_chain, solve
    from linkgen.families.spatial.plans import spatial_plan

    mech = load(ROOT / "models" / "rccc.toml")
    chain = assembled_chain(mech)
    w, e = float(mech.drive.omega), float(mech.drive.epsilon)
    for deg in ANGLES_DEG:
        phi = math.radians(deg)
        plan = spatial_plan(mech, phi, kind)
        assert plan.closure() <= CLOSES, (deg, plan.closure())
        # the coupler's copy of A (a2) on its way: the closed form's own point, not the crank's
        mo = solve(mech, np.array([phi]), chain)
        a2 = mo.at(chain.coupler, "A")
        want = a2.d[1][0] * w if kind == "velocity" else a2.d[2][0] * w * w + a2.d[1][0] * e
        coupler = next(c for c in plan.chains if c.link == chain.coupler)
        got = coupler.xy[list(coupler.names).index("a2")]
        assert np.linalg.norm(got - want) <= CLOSES * plan.size, deg
        assert "sliding" in coupler.kinds and (kind == "velocity" or "coriolis" in coupler.kinds)


@pytest.mark.parametrize("kind", ["velocity", "acceleration"])
def test_a_point_named_like_the_pole_keeps_its_own_vertex(kind):
    from linkgen.families.planar.assembly import assemble
    from linkgen.families.planar.kinematics import solve_motion
    from linkgen.families.planar.vector_plan import vector_plan

    asm = assemble(load(ROOT / "models" / "andrews_squeezer.toml"))  # its crank pin is P
    phi = math.radians(45.0)
    plan = vector_plan(asm, phi, kind)
    assert plan.pole not in {p.lower() for p in asm.mechanism.points}
    assert not np.any(plan.vertices[plan.pole])
    mech = asm.mechanism
    mo = solve_motion(asm, [phi], mech.drive.omega, mech.drive.epsilon)
    want = np.asarray(mo.points["P"][1 if kind == "velocity" else 2][0], dtype=float)
    np.testing.assert_allclose(plan.vertices["p"], want, rtol=0.0, atol=CLOSES * plan.size)
    assert np.linalg.norm(want) > 0.1 * plan.size  # the crank pin moves: its vertex is far from the pole
