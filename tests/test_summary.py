"""The design summary against textbook formulas: the offset slider-crank's stroke, dead-centre
angles and time ratio; the crank-rocker's swing, limit angles and least transmission angle by
the law of cosines (on the bundled four-bar and on random Grashof crank-rockers); the Scotch
yoke's; a drag link whose output turns fully; and the command line."""

import json
import math
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from linkgen import assemble, load
from linkgen.model.reader import loads
from linkgen.planar.summary import SAMPLES, summarize
from linkgen.api import forces

ROOT = Path(__file__).resolve().parents[1]
SCRIPT = shutil.which("linkgen", path=str(Path(sys.executable).parent))
# Limit positions are refined by Brent's method to 1e-13 rad; the values there are the closed
# form's (1e-15 relative). 1e-10 leaves room for the conditioning of a flat extremum's angle.
ANGLE_TOL = 1e-10
VALUE_TOL = 1e-12
# Least transmission angle and the grid's peaks: on a grid of SAMPLES angles the minimum of a
# smooth curve is found within (Δφ)² of its curvature; μ is within 1e-5 rad there.
GRID_TOL = 1e-5


def _by_kind(output, kind):
    return next(x for x in output.limits if x.kind == kind)


def test_offset_slider_crank_stroke_dead_centres_and_time_ratio():
    s = summarize(assemble(load(ROOT / "models" / "slider_crank_offset.toml")))
    l1, l2, e = 0.02, 0.035, 0.005
    (o,) = s.outputs
    assert o.travel == pytest.approx(math.sqrt((l1 + l2) ** 2 - e**2) - math.sqrt((l2 - l1) ** 2 - e**2), abs=VALUE_TOL)
    far, near = _by_kind(o, "max"), _by_kind(o, "min")
    assert far.phi == pytest.approx(math.asin(e / (l1 + l2)), abs=ANGLE_TOL)  # crank and rod in line, extended
    assert near.phi == pytest.approx(math.pi + math.asin(e / (l2 - l1)), abs=ANGLE_TOL)  # folded
    theta = math.asin(e / (l2 - l1)) - math.asin(e / (l1 + l2))
    assert o.time_ratio == pytest.approx((math.pi + theta) / (math.pi - theta), abs=1e-10)
    (t,) = s.transmission  # least where the rod is steepest: crank at 270°, sin β = (l1 + e)/l2
    assert t.minimum == pytest.approx(math.pi / 2 - math.asin((l1 + e) / l2), abs=GRID_TOL)
    assert t.at == pytest.approx(1.5 * math.pi, abs=2 * math.pi / (SAMPLES - 1))


def _crank_rocker(a, b, c, d):
    """Crank a, coupler b, rocker c, ground d; sketch at φ = 90° with B above."""
    ax, ay = 0.0, a
    # B: |B - A| = b, |B - C| = c, C = (d, 0), upper intersection
    dx, dy = d - ax, -ay
    dist = math.hypot(dx, dy)
    along = (dist**2 + b**2 - c**2) / (2 * dist)
    h = math.sqrt(b**2 - along**2)
    bx = ax + along * dx / dist - h * dy / dist
    by = ay + along * dy / dist + h * dx / dist
    if by < 0:
        bx, by = ax + along * dx / dist + h * dy / dist, ay + along * dy / dist - h * dx / dist
    return loads(f"""
[mechanism]
name = "crank_rocker"
[points]
O = [0.0, 0.0]
A = [{ax!r}, {ay!r}]
B = [{bx!r}, {by!r}]
C = [{d!r}, 0.0]
[links.ground]
points = ["O", "C"]
[links.crank]
points = ["O", "A"]
length = {a!r}
[links.coupler]
points = ["A", "B"]
length = {b!r}
[links.rocker]
points = ["C", "B"]
length = {c!r}
[drive]
joint = "O"
omega = 1.0
""")


def _law_of_cosines(a, b, c, d):
    def rocker_angle(ob):  # angle of CB from +x, B above the ground line
        return math.pi - math.acos((d * d + c * c - ob * ob) / (2 * d * c))

    def crank_angle(ob, folded):
        at_o = math.acos((ob * ob + d * d - c * c) / (2 * ob * d))
        return at_o + (math.pi if folded else 0.0)

    mu_min = math.acos((b * b + c * c - (d - a) ** 2) / (2 * b * c))
    mu_at_pi = math.acos((b * b + c * c - (d + a) ** 2) / (2 * b * c))
    return {"min": (crank_angle(a + b, False), rocker_angle(a + b)),
            "max": (crank_angle(b - a, True), rocker_angle(b - a)),
            "mu": min(mu_min, math.pi - mu_at_pi)}


def _grashof_crank_rockers(n: int, seed: int = 7) -> list[tuple[float, ...]]:
    """``n`` random crank-rockers (crank a the shortest, a + longest < sum of the other two, so
    the crank turns fully and the rocker rocks), by rejection."""
    rng, out = np.random.default_rng(seed), []
    while len(out) < n:
        a, b, c, d = rng.uniform([0.1, 0.5, 0.4, 0.5], [0.3, 1.3, 1.0, 1.2])
        if a < min(b, c, d) and a + max(b, c, d) < b + c + d - max(b, c, d) - 1e-3:
            out.append((float(a), float(b), float(c), float(d)))
    return out


@pytest.mark.parametrize("dims", [(0.3, 1.0, 0.7, 1.0)] + _grashof_crank_rockers(12))
def test_crank_rocker_swing_limits_and_transmission(dims):
    a, b, c, d = dims
    s = summarize(assemble(_crank_rocker(a, b, c, d)))
    (o,) = s.outputs
    ref = _law_of_cosines(a, b, c, d)
    for kind in ("min", "max"):
        lim = _by_kind(o, kind)
        assert lim.phi == pytest.approx(ref[kind][0], abs=1e-9)
        assert lim.value == pytest.approx(ref[kind][1], abs=1e-9)
    assert o.travel == pytest.approx(ref["max"][1] - ref["min"][1], abs=1e-9)
    (t,) = s.transmission
    assert t.minimum == pytest.approx(ref["mu"], abs=GRID_TOL)


def test_bundled_fourbar_matches_the_law_of_cosines():
    s = summarize(assemble(load(ROOT / "models" / "fourbar.toml")))
    ref = _law_of_cosines(0.3, 1.0, 0.7, 1.0)
    (o,) = s.outputs
    assert _by_kind(o, "min").phi == pytest.approx(ref["min"][0], abs=1e-9)
    assert o.time_ratio == pytest.approx((ref["max"][0] - ref["min"][0]) / (2 * math.pi - ref["max"][0] + ref["min"][0]))


def test_scotch_yoke_is_symmetric():
    s = summarize(assemble(load(ROOT / "models" / "scotch_yoke.toml")))
    for o in s.outputs:
        assert o.travel == pytest.approx(0.2, abs=VALUE_TOL) and o.time_ratio == pytest.approx(1.0, abs=1e-12)
    assert all(t.minimum == pytest.approx(math.pi / 2, abs=1e-12) for t in s.transmission)


def test_a_drag_link_output_turns_fully():
    mech = loads("""
[mechanism]
name = "drag_link"
[points]
O = [0.0, 0.0]
A = [0.0, 0.6]
B = [0.476782, 0.750594]
C = [0.2, 0.0]
[links.ground]
points = ["O", "C"]
[links.crank]
points = ["O", "A"]
length = 0.6
[links.coupler]
points = ["A", "B"]
length = 0.5
[links.follower]
points = ["C", "B"]
length = 0.8
[drive]
joint = "O"
omega = 2.0
""")
    (o,) = summarize(assemble(mech)).outputs
    assert o.travel is None and o.limits == () and o.time_ratio is None


def test_peaks_are_maxima():
    asm = assemble(load(ROOT / "models" / "press.toml"))
    s = summarize(asm)
    phi = np.random.default_rng(3).uniform(0, 2 * math.pi, 500)
    f = forces(asm, phi)
    assert s.torque.value >= np.max(np.abs(f.balancing_torque)) * (1 - 1e-3)
    for p in s.reactions:
        r = np.asarray(f.reactions[p.name])
        assert p.value >= np.max(np.hypot(r[:, 0], r[:, 1])) * (1 - 1e-3)
    at = forces(asm, s.torque.at)
    assert abs(at.balancing_torque) == pytest.approx(s.torque.value, rel=1e-12)


def test_summary_cli():
    p = subprocess.run([SCRIPT, "analyze", ROOT / "models" / "slider_crank_offset.toml", "--summary", "--json"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    d = json.loads(p.stdout)
    assert d["outputs"]["slider"]["time_ratio"] == pytest.approx(1.1720153, rel=1e-7)
    assert set(d) >= {"outputs", "transmission", "peak_balancing_torque", "peak_reactions", "units"}
    p = subprocess.run([SCRIPT, "analyze", ROOT / "models" / "fourbar.toml", "--summary"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and "time ratio K" in p.stdout and "transmission angle" in p.stdout
    p = subprocess.run([SCRIPT, "analyze", ROOT / "models" / "fourbar.toml", "--summary", "--samples", "10"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and "--summary" in p.stderr and "Traceback" not in p.stderr
