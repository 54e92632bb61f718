"""Generated mechanisms through MuJoCo (the full corpus is validation/mujoco_corpus.py): every
one validates, or fails with a diagnosis that names the quantity, the angles and the cause —
never a traceback, never "ok" over a tolerance, never NaN in the JSON."""

import json

import numpy as np
import pytest

from linkgen import assemble, from_dict
from linkgen.families.planar.corpus import random_description
from linkgen.crosscheck.run import crosscheck

# A small step budget keeps each run under a few seconds; what needs more is reported as a
# "time budget" failure, which the test accepts as explained.
BUDGET = 150_000
SEEDS = range(100, 112)
CAUSES = {"near-singular", "load switch", "loop gap", "time budget", "integration error", "run failed"}


@pytest.mark.parametrize("seed", SEEDS)
def test_generated_mechanism_validates_or_is_explained(seed):
    desc = random_description(np.random.default_rng(seed), max_groups=3)
    cc = crosscheck(assemble(from_dict(desc)), practical=False, nthread=1, max_steps=BUDGET)
    out = json.loads(json.dumps(cc.to_json(), allow_nan=False))
    if cc.ok:
        c = cc.comparison
        assert all(q.relative_error <= q.tolerance for q in c.quantities.values())
        assert out["loop_gap"]["relative"] <= out["loop_gap"]["tolerance"] and out["diagnosis"] == []
    else:
        assert out["diagnosis"], out["attempts"]
        for d in out["diagnosis"]:
            assert d["cause"] in CAUSES
            if d["quantity"] == "run":  # the run itself stopped: the message says where and why
                assert d["detail"] and d["cause"] in ("run failed", "time budget")
            else:
                assert d["relative_error"] > d["tolerance"] and d["ranges"]
                lo, hi = (float(x) for x in (cc.comparison.run.samples.crank[0].min(),
                                             cc.comparison.run.samples.crank[0].max()))
                assert all(lo - 1e-8 <= a <= b <= hi + 1e-8 for a, b in d["ranges"])


def test_a_run_its_budget_cannot_hold_is_refused_before_it_starts_and_would_have_missed():
    """Seed 101 needs ~5e6 steps to hold its loops; at a budget of 150 000 the gap is predicted
    at 1.5e-6 of the size, so the run is refused at once, naming the stiff loop. Running it
    anyway at the coarsened settings shows the refusal was right (an independent route: the
    measured gap, not the prediction)."""
    from dataclasses import replace

    from linkgen.mujoco.tolerances import GAP_TOL
    from linkgen.mujoco.loops import mechanism_size
    from linkgen.mujoco.simulate import simulate

    asm = assemble(from_dict(random_description(np.random.default_rng(101), max_groups=3)))
    cc = crosscheck(asm, practical=False, nthread=1, max_steps=BUDGET)
    assert not cc.ok and cc.attempts[0].steps == 0
    (finding,) = cc.diagnosis
    assert finding.cause == "time budget"
    assert finding.detail.startswith("not run: the loops need a time constant of") and "joint 'P2'" in finding.detail
    forced = replace(cc.attempts[0].settings, label="as coarsened, run anyway")
    run = simulate(asm, settings=forced, nthread=1)
    assert run.gap_max > GAP_TOL * mechanism_size(asm)
