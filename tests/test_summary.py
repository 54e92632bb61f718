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

import linkgen
from linkgen import assemble, load
from linkgen.pipeline.registry import loads
from linkgen.families.planar.summary import SAMPLES, summarize
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
    (o,) = s.outputs.values()
    assert o.travel == pytest.approx(math.sqrt((l1 + l2) ** 2 - e**2) - math.sqrt((l2 - l1) ** 2 - e**2), abs=VALUE_TOL)
    far, near = _by_kind(o, "max"), _by_kind(o, "min")
    assert far.phi == pytest.approx(math.asin(e / (l1 + l2)), abs=ANGLE_TOL)  # crank and rod in line, extended
    assert near.phi == pytest.approx(math.pi + math.asin(e / (l2 - l1)), abs=ANGLE_TOL)  # folded
    theta = math.asin(e / (l2 - l1)) - math.asin(e / (l1 + l2))
    assert o.time_ratio == pytest.approx((math.pi + theta) / (math.pi - theta), abs=1e-10)
    (t,) = s.min_transmission_angle.values()  # least where the rod is steepest: crank at 270°, sin β = (l1 + e)/l2
    assert t.value == pytest.approx(math.pi / 2 - math.asin((l1 + e) / l2), abs=GRID_TOL)
    assert t.phi == pytest.approx(1.5 * math.pi, abs=2 * math.pi / (SAMPLES - 1))


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
    (o,) = s.outputs.values()
    ref = _law_of_cosines(a, b, c, d)
    for kind in ("min", "max"):
        lim = _by_kind(o, kind)
        assert lim.phi == pytest.approx(ref[kind][0], abs=1e-9)
        assert lim.value == pytest.approx(ref[kind][1], abs=1e-9)
    assert o.travel == pytest.approx(ref["max"][1] - ref["min"][1], abs=1e-9)
    (t,) = s.min_transmission_angle.values()
    assert t.value == pytest.approx(ref["mu"], abs=GRID_TOL)


def test_bundled_fourbar_matches_the_law_of_cosines():
    s = summarize(assemble(load(ROOT / "models" / "fourbar.toml")))
    ref = _law_of_cosines(0.3, 1.0, 0.7, 1.0)
    (o,) = s.outputs.values()
    assert _by_kind(o, "min").phi == pytest.approx(ref["min"][0], abs=1e-9)
    assert o.time_ratio == pytest.approx((ref["max"][0] - ref["min"][0]) / (2 * math.pi - ref["max"][0] + ref["min"][0]))


def test_scotch_yoke_is_symmetric():
    s = summarize(assemble(load(ROOT / "models" / "scotch_yoke.toml")))
    for o in s.outputs.values():
        assert o.travel == pytest.approx(0.2, abs=VALUE_TOL) and o.time_ratio == pytest.approx(1.0, abs=1e-12)
    assert all(t.value == pytest.approx(math.pi / 2, abs=1e-12) for t in s.min_transmission_angle.values())


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
    (o,) = summarize(assemble(mech)).outputs.values()
    assert o.travel is None and o.limits == () and o.time_ratio is None


# ga32's sketch gives its points to 5 decimals: lengths taken from it are good to ~1e-5 m.
SKETCH_TOL = 1e-5


def test_a_slider_and_a_rocker_of_one_name_are_both_in_the_json():
    """ga32's block turns about B (a rocker, link "block") while the rod slides through it (a
    slider, prismatic pair "block"): the JSON keyed both "block", so the rocker hid the slider's
    stroke. Each is now under its name and kind; the stroke is the span of |AB| = |OB| ± the crank."""
    d = linkgen.summary(load(ROOT / "models" / "ga32.toml")).to_dict()
    assert {k: o["kind"] for k, o in d["outputs"].items()} == {"block (slider)": "slider", "block (rocker)": "rocker"}
    crank, ob = 0.3, math.hypot(0.44550, 0.22700)
    assert d["outputs"]["block (slider)"]["travel"] == pytest.approx((ob + crank) - (ob - crank), abs=SKETCH_TOL)


def test_peaks_are_maxima():
    asm = assemble(load(ROOT / "models" / "press.toml"))
    s = summarize(asm)
    phi = np.random.default_rng(3).uniform(0, 2 * math.pi, 500)
    f = forces(asm, phi)
    assert s.peak_balancing_torque.value >= np.max(np.abs(f.balancing_torque)) * (1 - 1e-3)
    for name, p in s.peak_reactions.items():
        r = np.asarray(f.reactions[name].force)
        assert p.value >= np.max(np.hypot(r[:, 0], r[:, 1])) * (1 - 1e-3)
    at = forces(asm, s.peak_balancing_torque.phi)
    assert abs(at.balancing_torque) == pytest.approx(s.peak_balancing_torque.value, rel=1e-12)


def test_summary_cli():
    p = subprocess.run([SCRIPT, "analyze", ROOT / "models" / "slider_crank_offset.toml", "--summary", "--json"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    d = json.loads(p.stdout)
    assert d["outputs"]["slider"]["time_ratio"] == pytest.approx(1.1720153, rel=1e-7)
    assert set(d) >= {"outputs", "min_transmission_angle", "peak_balancing_torque", "peak_reactions", "units"}
    p = subprocess.run([SCRIPT, "analyze", ROOT / "models" / "fourbar.toml", "--summary"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0 and "time ratio K" in p.stdout and "transmission angle" in p.stdout
    p = subprocess.run([SCRIPT, "analyze", ROOT / "models" / "fourbar.toml", "--summary", "--samples", "10"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and "--summary" in p.stderr and "Traceback" not in p.stderr


# ---------------------------------------------------------------------------------------------
# Every extremum of the summary against a dense independent scan of the closed form: 200 000
# crank angles, limit positions refined by Newton's method on the analytic second transfer
# function, peaks by zooming in with denser scans — neither uses the summary's search or its Brent refinement.

from conftest import MODELS, every_model  # noqa: E402  (the planar linkages)

from linkgen.families.planar.description import GROUND  # noqa: E402
from linkgen.families.planar.kinematics import solve  # noqa: E402
from linkgen.families.planar.summary import transmission_angles  # noqa: E402
from independent_checks import zoomed_peak as _dense_peak  # noqa: E402

DENSE = 200_000
# Limit positions: Newton's method on d/dφ with the analytic d²/dφ² converges to a few ulps of
# the crank angle; both sides then agree to the conditioning of d/dφ = 0 (1e-15/d²), well
# inside 1e-9 rad for every bundled output; the values there to 1e-12 of the output's size.
DENSE_ANGLE_TOL = 1e-9
DENSE_VALUE_TOL = 1e-12
# Peaks (forces, torques): both refinements end at a flat top, where the value is exact to a few
# ulps; 1e-10 of the peak leaves room for that, and is 1000× below a 0.1° grid's error (1e-7).
PEAK_REL_TOL = 1e-10
# The least transmission angle μ = arcsin|D|: near 90° the arcsine turns a rounding of D into
# √(2·1e-16) ≈ 1.5e-8 rad; elsewhere both refinements agree to a few ulps.
MU_TOL = 5e-8
# A full turn is a period when the closed form repeats itself to this after it (it does to ~1e-15).
REPEAT_TOL = 1e-9


def _outputs(asm):
    """(name, kind, pick) of every slider and ground-pivoted link but the crank, pick(kin) →
    (value, d/dφ, d²/dφ²)."""
    mech = asm.mechanism
    out = [(n, "slider", lambda k, n=n: (k.sliders[n].v, k.sliders[n].d1, k.sliders[n].d2)) for n in asm.guides]
    pivoted = {p for r in mech.revolutes if GROUND in r.links for p in r.links if p != GROUND}
    out += [(l.name, "rocker", lambda k, n=l.name: (k.links[n].angle.v, k.links[n].angle.d1, k.links[n].angle.d2))
            for l in mech.links if l.name in pivoted and l.name != mech.crank]
    return out


def _dense_limits(asm, kin, pick, full: bool):
    """Reference limit positions [(φ, value, kind)] from the dense solution ``kin``, whether the
    output repeats over the turn, and its values at the range's ends."""
    d = asm.mechanism.drive
    phi = kin.phi
    v, d1, _ = pick(kin)
    v = np.unwrap(v)
    periodic = full and abs(v[-1] - v[0]) <= REPEAT_TOL * max(1.0, float(np.abs(v).max()))
    s = np.sign(d1[:-1] if periodic else d1)
    nxt = np.roll(s, -1) if periodic else s[1:]
    roots = []
    for k in np.flatnonzero((s if periodic else s[:-1]) != nxt):
        x = float(phi[k])
        for _ in range(30):  # Newton on d/dφ with the analytic d²/dφ²
            _, g1, g2 = pick(solve(asm, [x], on_singular="mark"))
            step = g1[0] / g2[0]
            x -= step
            if abs(step) < 1e-16:
                break
        x = d.start + (x - d.start) % (2 * math.pi) if periodic else x
        if periodic and 2 * math.pi - (x - d.start) < 1e-12:
            x = d.start
        if not periodic and not (d.start < x < d.stop):
            continue
        if any(abs(x - y) < 1e-9 for y, _, _ in roots):
            continue
        val, _, g2 = pick(solve(asm, [x], on_singular="mark"))
        if g2[0] == 0.0:
            continue  # an inflection with a horizontal tangent: no extremum
        roots.append((x, float(val[0]), "max" if g2[0] < 0 else "min"))
    return sorted(roots), periodic, (float(v[0]), float(v[-1]))


@pytest.mark.every_model
@pytest.mark.parametrize("path", every_model(MODELS), ids=lambda p: p.stem)
def test_summary_extrema_agree_with_a_dense_independent_scan(path):
    """The summary's extrema against a dense scan of the closed form. On one model per family and feature
    (conftest.REPRESENTATIVE); on every bundled model in `make every-model`, which `make demo` runs."""
    asm = assemble(load(path))
    s = summarize(asm)
    d = asm.mechanism.drive
    full = abs(d.stop - d.start - 2 * math.pi) <= 1e-12
    outputs = {(key.removesuffix(f" ({o.kind})"), o.kind): o for key, o in s.outputs.items()}
    phi = np.linspace(d.start, d.stop, DENSE + 1)
    kin = solve(asm, phi, on_singular="mark")
    for name, kind, pick in _outputs(asm):
        o = outputs[name, kind]
        if o.travel is None:  # a link that turns fully round
            continue
        ref, periodic, ends = _dense_limits(asm, kin, pick, full)
        assert [x.kind for x in o.limits] == [k for _, _, k in ref], (name, o.limits, ref)
        scale = max(1.0, max(abs(v) for _, v, _ in ref)) if ref else 1.0
        for lim, (x, v, _) in zip(o.limits, ref):
            gap = abs(lim.phi - x)
            assert min(gap, 2 * math.pi - gap) <= DENSE_ANGLE_TOL, (name, lim, x)
            if kind == "rocker":  # the same angle up to whole turns
                v = v + 2 * math.pi * round((lim.value - v) / (2 * math.pi))
            assert abs(lim.value - v) <= DENSE_VALUE_TOL * scale, (name, lim, v)
        values = [v for _, v, _ in ref]
        if not periodic:
            values += list(ends)
        if values and kind == "slider":
            assert o.travel == pytest.approx(max(values) - min(values), abs=DENSE_VALUE_TOL * scale)
        if periodic and len(ref) == 2:
            lo = next(x for x, _, k in ref if k == "min")
            hi = next(x for x, _, k in ref if k == "max")
            work = (hi - lo) % (2 * math.pi)
            assert o.time_ratio == pytest.approx(max(work, 2 * math.pi - work) / min(work, 2 * math.pi - work),
                                                 abs=1e-8)
        else:
            assert o.time_ratio is None
    for group, t in s.min_transmission_angle.items():
        mu = transmission_angles(asm, phi)[group]
        least = -_dense_peak(lambda p, g=group: -transmission_angles(asm, p)[g], phi, -mu)
        assert abs(t.value - least) <= MU_TOL, (t, least)
        assert transmission_angles(asm, np.array([t.phi]))[group][0] == pytest.approx(t.value, abs=1e-15)
    if s.peak_balancing_torque is None:
        return
    w, e = s.omega, s.epsilon
    from linkgen.families.planar.kinetostatics import forces as closed_forces

    f = closed_forces(asm, phi, w, e)
    ref = _dense_peak(lambda p: np.abs(closed_forces(asm, p, w, e).balancing_torque), phi, np.abs(f.balancing_torque))
    assert s.peak_balancing_torque.value == pytest.approx(ref, rel=PEAK_REL_TOL)
    assert abs(closed_forces(asm, np.array([s.peak_balancing_torque.phi]), w, e).balancing_torque[0]) == pytest.approx(
        s.peak_balancing_torque.value, rel=1e-14)
    for name, p in s.peak_reactions.items():
        def mag(x, n=name):
            r = np.asarray(closed_forces(asm, x, w, e).reactions[n])
            return np.hypot(r[:, 0], r[:, 1])
        r = np.asarray(f.reactions[name])
        ref = _dense_peak(mag, phi, np.hypot(r[:, 0], r[:, 1]))
        assert p.value == pytest.approx(ref, rel=PEAK_REL_TOL), name
        assert mag(np.array([p.phi]))[0] == pytest.approx(p.value, rel=1e-14)


# ---------------------------------------------------------------------------------------------
# Mechanisms sketched exactly at a dead centre (φ = 0 is a limit position): both limit positions
# and the time ratio, against geometry.

def test_press_lists_both_dead_centres_and_its_time_ratio():
    (o,) = summarize(assemble(load(ROOT / "models" / "press.toml"))).outputs.values()
    assert [(x.kind, x.phi, x.value) for x in o.limits] == [
        ("max", pytest.approx(0.0, abs=ANGLE_TOL), pytest.approx(0.5, abs=VALUE_TOL)),  # crank 0.1 + rod 0.4
        ("min", pytest.approx(math.pi, abs=ANGLE_TOL), pytest.approx(0.3, abs=VALUE_TOL))]  # rod − crank
    assert o.travel == pytest.approx(0.2, abs=VALUE_TOL)
    assert o.strokes == pytest.approx((math.pi, math.pi), abs=ANGLE_TOL) and o.time_ratio == pytest.approx(1.0, abs=1e-10)


def _offset_slider_crank_at_dead_centre(a: float, b: float, e: float):
    """Crank a, rod b, the guide offset e (to its left) and turned by −asin(e/(a + b)) so that
    crank and rod lie in line along +x at φ = 0: the sketch is the outer dead centre."""
    psi = -math.asin(e / (a + b))
    return loads(f"""
[mechanism]
name = "offset_at_dead_centre"
[points]
O = [0.0, 0.0]
A = [{a!r}, 0.0]
B = [{a + b!r}, 0.0]
[links.ground]
points = ["O"]
[links.crank]
points = ["O", "A"]
length = {a!r}
[links.rod]
points = ["A", "B"]
length = {b!r}
[links.slider]
points = ["B"]
[prismatic.slider]
slider = "slider"
guide = "ground"
point = "B"
through = "O"
angle = {psi!r}
offset = {e!r}
[drive]
joint = "O"
omega = 1.0
"""), psi


@pytest.mark.parametrize("a,b,e", [(0.02, 0.035, 0.0), (0.02, 0.035, 0.005), (0.1, 0.25, -0.04), (0.1, 0.3, 0.02)])
def test_a_slider_crank_sketched_at_its_dead_centre(a, b, e):
    mech, psi = _offset_slider_crank_at_dead_centre(a, b, e)
    (o,) = summarize(assemble(mech)).outputs.values()
    far, near = _by_kind(o, "max"), _by_kind(o, "min")
    assert len(o.limits) == 2
    assert min(far.phi, 2 * math.pi - far.phi) == pytest.approx(0.0, abs=ANGLE_TOL)
    assert far.value == pytest.approx(math.sqrt((a + b) ** 2 - e * e), abs=VALUE_TOL)
    s = math.sqrt((b - a) ** 2 - e * e)  # folded: B on the guide at b − a from O, the crank opposite
    bx, by = s * math.cos(psi) - e * math.sin(psi), s * math.sin(psi) + e * math.cos(psi)
    folded = (math.atan2(by, bx) + math.pi) % (2 * math.pi)
    assert near.phi == pytest.approx(folded, abs=ANGLE_TOL) and near.value == pytest.approx(s, abs=VALUE_TOL)
    work = 2 * math.pi - folded  # min → max: from the folded dead centre on to φ = 2π ≡ 0
    assert o.strokes == pytest.approx((work, folded), abs=ANGLE_TOL)
    assert o.time_ratio == pytest.approx(max(work, folded) / min(work, folded), abs=1e-9)


def _crank_rocker_at_dead_centre(a, b, c, d):
    """Crank a, coupler b, rocker c, ground d, sketched with crank and coupler in line along +x
    (φ = 0, the extended dead centre) and the rocker's pivot C below the x axis."""
    L = a + b
    cx = (d * d - c * c + L * L) / (2 * L)
    cy = -math.sqrt(d * d - cx * cx)
    mech = loads(f"""
[mechanism]
name = "crank_rocker_at_dead_centre"
[points]
O = [0.0, 0.0]
A = [{a!r}, 0.0]
B = [{L!r}, 0.0]
C = [{cx!r}, {cy!r}]
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
    return mech, (cx, cy)


@pytest.mark.parametrize("dims", [(0.3, 1.0, 0.7, 1.0), (0.2, 0.9, 0.6, 0.8)])
def test_a_crank_rocker_sketched_at_its_dead_centre(dims):
    a, b, c, d = dims
    mech, (cx, cy) = _crank_rocker_at_dead_centre(a, b, c, d)
    (o,) = summarize(assemble(mech)).outputs.values()
    assert len(o.limits) == 2
    # extended at φ = 0: B = (a + b, 0); folded: |OB| = b − a, B on the same side of OC as sketched
    theta_c = math.atan2(cy, cx)
    beta = theta_c + math.acos(((b - a) ** 2 + d * d - c * c) / (2 * (b - a) * d))
    folded = (beta + math.pi) % (2 * math.pi)
    rocker = {0.0: math.atan2(-cy, a + b - cx),
              folded: math.atan2((b - a) * math.sin(beta) - cy, (b - a) * math.cos(beta) - cx)}
    ext_kind = "max" if rocker[0.0] > rocker[folded] else "min"
    ext = _by_kind(o, ext_kind)
    fold = _by_kind(o, "min" if ext_kind == "max" else "max")
    assert min(ext.phi, 2 * math.pi - ext.phi) == pytest.approx(0.0, abs=ANGLE_TOL)
    assert fold.phi == pytest.approx(folded, abs=ANGLE_TOL)
    for lim, phi in ((ext, 0.0), (fold, folded)):
        assert math.remainder(lim.value - rocker[phi], 2 * math.pi) == pytest.approx(0.0, abs=1e-12)
    assert o.travel == pytest.approx(abs(rocker[0.0] - rocker[folded]), abs=1e-12)
    k = folded / (2 * math.pi - folded)
    assert o.time_ratio == pytest.approx(max(k, 1 / k), abs=1e-9)


def test_a_planetary_slider_keeps_its_global_maximum_at_phi_0():
    """The planetary lever (ring 60, satellite 20: B = (cos φ + 0.55·cos 2φ, sin φ − 0.55·sin 2φ))
    with a 3 m rod from B to a slider D on the x axis: D is farthest, 1 + 0.55 + 3 m, at φ = 0."""
    text = (ROOT / "models" / "planetary_lever.toml").read_text(encoding="utf-8")
    text = text.replace('B = [1.55, 0.0]\n', 'B = [1.55, 0.0]\nD = [4.55, 0.0]\n').replace("[gear.mesh]", """
[links.rod]
points = ["B", "D"]
length = 3.0

[links.slider]
points = ["D"]

[prismatic.slider]
slider = "slider"
guide = "ground"
point = "D"
through = "O"
angle = 0.0

[gear.mesh]""")
    (o,) = summarize(assemble(loads(text))).outputs.values()
    top = max(o.limits, key=lambda x: x.value)
    assert top.kind == "max" and min(top.phi, 2 * math.pi - top.phi) == pytest.approx(0.0, abs=ANGLE_TOL)
    assert top.value == pytest.approx(4.55, abs=VALUE_TOL)
    phi = np.linspace(0.0, 2 * math.pi, DENSE, endpoint=False)
    xb, yb = np.cos(phi) + 0.55 * np.cos(2 * phi), np.sin(phi) - 0.55 * np.sin(2 * phi)
    xd = xb + np.sqrt(9.0 - yb * yb)
    assert o.travel == pytest.approx(4.55 - xd.min(), abs=1e-9)  # DENSE samples: (Δφ)²·|x″|/8 < 1e-9 m
    steps = np.sign(np.diff(np.append(xd, xd[0])))
    assert len(o.limits) == int(np.count_nonzero(steps != np.roll(steps, 1)))


# ---------------------------------------------------------------------------------------------
# The stand-alone cams' summaries against the same dense independent scan.

from conftest import CAM_MODELS  # noqa: E402

from linkgen.families.cam.kinetics import state as cam_state  # noqa: E402
from linkgen.families.cam.summary import cam_summary  # noqa: E402


@pytest.mark.parametrize("path", CAM_MODELS, ids=[p.stem for p in CAM_MODELS])
def test_cam_summary_extrema_agree_with_a_dense_independent_scan(path):
    cm = load(path)
    w = cm.omega
    s = cam_summary(cm, w).to_dict()
    th = np.linspace(0.0, 2 * math.pi, DENSE, endpoint=False)
    st = cam_state(cm, th, w)

    def top(fun, values):  # the largest value, dense and zoomed
        return _dense_peak(fun, th, values)

    def quantity(name, sign=1.0, absolute=False):
        def fun(x):
            v = sign * getattr(cam_state(cm, x, w), name)
            return np.abs(v) if absolute else v
        return fun, fun(th)

    stroke = top(*quantity("displacement")) + top(*quantity("displacement", -1.0))
    assert s["outputs"]["follower"]["travel"] == pytest.approx(stroke, rel=PEAK_REL_TOL)
    alpha = top(*quantity("pressure_angle", absolute=True))
    assert s["max_pressure_angle"]["value"] == pytest.approx(alpha, rel=PEAK_REL_TOL, abs=1e-15)
    rho = cm.follower.profile_curvature_radius
    assert s["min_profile_curvature_radius"]["value"] == pytest.approx(-top(lambda x: -rho(x), -rho(th)),
                                                                      rel=PEAK_REL_TOL)
    assert s["peak_contact_force"]["value"] == pytest.approx(top(*quantity("contact_force")), rel=PEAK_REL_TOL)
    assert s["min_contact_force"] == pytest.approx(-top(*quantity("contact_force", -1.0)), rel=PEAK_REL_TOL)
    assert s["peak_balancing_torque"]["value"] == pytest.approx(top(*quantity("cam_torque", absolute=True)),
                                                          rel=PEAK_REL_TOL)
    for key in ("max_pressure_angle", "peak_contact_force", "peak_balancing_torque"):  # the value is the one at "phi"
        name = {"max_pressure_angle": "pressure_angle", "peak_contact_force": "contact_force",
                "peak_balancing_torque": "cam_torque"}[key]
        at = getattr(cam_state(cm, [s[key]["phi"]], w), name)[0]
        assert abs(at) == pytest.approx(s[key]["value"], rel=1e-14, abs=1e-15)
    # leave speed: ω² = least of (spring − weight)/(−m·q″) where q″ < 0 (st.spring is the spring force)
    mass = cm.inertia if cm.follower.kind == "oscillating" else cm.mass
    weight = cm.mass * cm.gravity[1] if cm.follower.kind == "translating" else 0.0

    def ratio(x):
        q2 = cm.follower.output(x)[2]
        hold = cam_state(cm, x, w).spring - weight
        return np.where(q2 < 0, -hold / np.where(q2 < 0, -mass * q2, 1.0), -np.inf)

    assert s["leave_speed"] == pytest.approx(math.sqrt(-top(ratio, ratio(th))), rel=PEAK_REL_TOL)


# ---------------------------------------------------------------------------------------------
# The machines' peak forces over the steady cycle against a dense scan of the same cycle. The
# bundled machines whose integration to a steady cycle takes seconds, not tens of seconds.

MACHINE_DENSE = 20_000  # times over the cycle; each then zoomed in three rounds of 1001
# The press's peak balancing torque sits at its stroke switch, where ε follows the reduced
# moment's piecewise-linear table across the switch: |τ| falls ~1e5 N·m/s there, so a time
# 1e-12 s from the sup (the refinement's tolerance) is 1e-7 N·m (4e-10) below it.
MACHINE_PEAK_REL_TOL = 1e-9


@pytest.mark.parametrize("name,duration", [("machine_press", 2.5), ("motor_startup", 5.0), ("dc_motor_startup", 5.0)])
def test_machine_cycle_peaks_agree_with_a_dense_scan(name, duration):
    from linkgen.machine.machine import run_machine
    from linkgen.machine.reduced import reduce
    from linkgen.machine.study import cycle_forces, load_machine
    from linkgen.families.planar.kinetostatics import forces as closed_forces

    asm, machine = load_machine(ROOT / "models" / f"{name}.toml")
    run = run_machine(machine, reduce(asm, machine.process_load), samples=50, duration=duration)
    cf = cycle_forces(asm, run)
    s = run.steady
    t = s.t_start + s.period * np.arange(MACHINE_DENSE) / MACHINE_DENSE

    def along(tt):  # the mechanism's forces at the machine's state at times tt, ε the ODE's own
        y = run.solution(tt)
        eps = np.array([run.rate(tk, y[:, k])[1] for k, tk in enumerate(tt)])
        return closed_forces(asm, y[0], y[1], eps)

    f = along(t)
    scale = float(np.abs(f.balancing_torque).max())
    ref = _dense_peak(lambda x: np.abs(along(x).balancing_torque), t, np.abs(f.balancing_torque))
    assert cf.peak_balancing_torque.value == pytest.approx(ref, rel=MACHINE_PEAK_REL_TOL, abs=1e-12 * scale)
    for n, r in f.reactions.items():
        ref = _dense_peak(lambda x, n=n: np.linalg.norm(along(x).reactions[n], axis=1), t, np.linalg.norm(r, axis=1))
        assert cf.peak_reactions[n].value == pytest.approx(ref, rel=MACHINE_PEAK_REL_TOL), n
    # the cycle's speed range (δ): ω of the dense output, dense and zoomed
    w = run.solution(t)[1]
    top = _dense_peak(lambda x: run.solution(x)[1], t, w)
    bottom = -_dense_peak(lambda x: -run.solution(x)[1], t, -w)
    assert (s.omega_min, s.omega_max) == pytest.approx((bottom, top), rel=PEAK_REL_TOL)


# ---------------------------------------------------------------------------------------------
# The spatial four-bars' summaries against the same dense independent scan.

from conftest import SPATIAL_MODELS  # noqa: E402

# A spatial force solution costs ~0.15 ms an angle: 5000 angles (every 0.072°), then zoomed.
SPATIAL_DENSE = 5_000


@pytest.mark.every_model
@pytest.mark.parametrize("path", every_model(SPATIAL_MODELS), ids=lambda p: p.stem)
def test_spatial_summary_extrema_agree_with_a_dense_independent_scan(path):
    """A spatial summary's extrema against a dense scan of the closed form. On one model per family and feature
    (conftest.REPRESENTATIVE); on every bundled model in `make every-model`, which `make demo` runs."""
    from linkgen.families.spatial.forces import forces as spatial_forces
    from linkgen.families.spatial.kinematics import solve as spatial_solve
    from linkgen.families.spatial.summary import summarize as spatial_summarize

    mech = load(path)
    s = spatial_summarize(mech)
    slides = mech.drive.slides  # a slider's range: its ends are limit positions too, nothing wraps
    phi = (np.linspace(*mech.drive.range, SPATIAL_DENSE) if slides
           else np.linspace(0.0, 2 * math.pi, SPATIAL_DENSE, endpoint=False))
    k = spatial_solve(mech, phi)
    d1 = k.output.d[1]
    ref = []
    if slides:
        for i, rising in ((0, d1[0] < 0), (-1, d1[-1] > 0)):
            ref.append(("max" if rising else "min", float(phi[i]), float(k.output.d[0][i])))
    turns = np.flatnonzero(np.sign(d1) != np.sign(np.roll(d1, -1)))
    for i in (turns[turns < phi.shape[0] - 1] if slides else turns):
        x = float(phi[i])
        for _ in range(30):  # Newton on dq/dφ with the analytic d²q/dφ²
            t = spatial_solve(mech, [x]).output
            step = t.d[1][0] / t.d[2][0]
            x -= step
            if abs(step) < 1e-16:
                break
        x = x if slides else x % (2 * math.pi)
        if all(min(abs(x - y), 2 * math.pi - abs(x - y)) > 1e-9 for _, y, _ in ref):
            t = spatial_solve(mech, [x]).output  # the joint variable analyze gives
            ref.append(("max" if t.d[2][0] < 0 else "min", x, float(t.d[0][0])))
    ref.sort(key=lambda r: r[1])
    (out,) = s.outputs.values()
    assert [lim.kind for lim in out.limits] == [kind for kind, _, _ in ref]
    for (a, v, _), (_, x, w) in zip(((x.phi, x.value, x.kind) for x in out.limits), ref):
        assert min(abs(a - x), 2 * math.pi - abs(a - x)) <= DENSE_ANGLE_TOL
        assert v == pytest.approx(w, abs=DENSE_VALUE_TOL)
    w, e = mech.drive.omega, mech.drive.epsilon
    f = spatial_forces(mech, phi, w, e, motion=k)
    top = _dense_peak(lambda x: np.abs(spatial_forces(mech, x, w, e).balancing_torque), phi, np.abs(f.balancing_torque))
    t = s.peak_balancing_torque
    assert t.value == pytest.approx(top, rel=PEAK_REL_TOL)  # a magnitude, as planar peaks
    assert abs(spatial_forces(mech, [t.phi], w, e).balancing_torque[0]) == pytest.approx(t.value, rel=1e-14)
    for n, value in ((n, p.value) for n, p in s.peak_reactions.items()):
        def mag(x, n=n):
            return np.linalg.norm(spatial_forces(mech, x, w, e).reactions[n].force, axis=1)
        dense = np.linalg.norm(f.reactions[n].force, axis=1)
        assert value == pytest.approx(_dense_peak(mag, phi, dense), rel=PEAK_REL_TOL), n


# ---------------------------------------------------------------------------------------------
# The extremum finder itself on curves whose extrema are known in closed form.

from linkgen.extrema import peak, samples, stationary  # noqa: E402

TURN = 2 * math.pi
# Brent's bounded minimiser stops within √eps·u (u ≤ two sample steps, 3.5e-3 rad here) of the
# best point: at a kink of slope 1 that is the value's error too, ≤ 5e-11.
KINK_TOL = 1e-10


def test_stationary_points_on_samples_and_at_the_wrap():
    # cos: d = −sin is exactly 0 at the samples 0 and π; both extremes, each once
    x = samples(0.0, TURN, 360, periodic=True)
    found = stationary(lambda p: -np.sin(p), x, -np.sin(x), period=TURN)
    assert [(e.kind, e.x) for e in found] == [("max", 0.0), ("min", pytest.approx(math.pi, abs=1e-15))]
    # a maximum between the last sample and 2π (cos(φ − a), a just below 2π), found round the wrap
    a = TURN - 0.3 * TURN / 360
    found = stationary(lambda p: -np.sin(p - a), x, -np.sin(x - a), period=TURN)
    assert [e.kind for e in found] == ["min", "max"]
    assert found[1].x == pytest.approx(a, abs=1e-12) and found[0].x == pytest.approx(a - math.pi, abs=1e-12)
    # the same from a range that starts at −90°
    x = samples(-0.5 * math.pi, 1.5 * math.pi, 360, periodic=True)
    found = stationary(lambda p: -np.sin(p - a), x, -np.sin(x - a), period=TURN)
    assert sorted(e.x for e in found) == pytest.approx([a - TURN, a - math.pi], abs=1e-12)


def test_stationary_on_a_partial_range_reports_its_ends():
    x = samples(0.2, 2.0, 101, periodic=False)  # sin rises to its maximum at π/2, then falls
    found = stationary(np.cos, x, np.cos(x))
    assert [(e.kind, e.end) for e in found] == [("min", True), ("max", False), ("min", True)]
    assert found[1].x == pytest.approx(math.pi / 2, abs=1e-13)
    assert (found[0].x, found[2].x) == (0.2, 2.0)


def test_stationary_across_a_dwell():
    # a rise, a dwell at the top (d = 0 over a run of samples), a return: one maximum, one minimum
    def d(p):
        p = np.mod(p, TURN)
        return np.where(p < 2.0, np.sin(p * math.pi / 2.0), np.where(p < 3.0, 0.0, -np.sin((p - 3.0) * math.pi / (TURN - 3.0))))
    x = samples(0.0, TURN, 720, periodic=True)
    found = stationary(d, x, d(x), period=TURN)
    assert [e.kind for e in found] == ["min", "max"]
    assert 2.0 <= found[1].x <= 3.0 and found[0].x in (0.0, pytest.approx(0.0, abs=1e-12))


def test_peak_of_a_kink_a_jump_and_round_the_wrap():
    x = samples(0.0, TURN, 3600, periodic=True)
    # |sin(φ − c)| has kinks at its zeros: its least value 0 at c (between samples)
    c = 1.0 + 0.37 * TURN / 3600

    def kink(p):
        return np.abs(np.sin(p - c))
    at, least = peak(kink, x, kink(x), kind="min", period=TURN)
    assert least <= KINK_TOL and at == pytest.approx(c, abs=KINK_TOL)

    # a jump: 1 + φ/10 up to c, 0 after: the sup is at c
    def jump(p):
        return np.where(np.mod(p, TURN) <= c, 1.0 + np.mod(p, TURN) / 10, 0.0)
    at, top = peak(jump, x, jump(x), period=TURN)
    assert top == pytest.approx(1.0 + c / 10, abs=KINK_TOL) and top <= 1.0 + c / 10

    # cos(φ − a), its maximum between the last sample and 2π
    a = TURN - 0.3 * TURN / 3600
    at, top = peak(lambda p: np.cos(p - a), x, np.cos(x - a), period=TURN)
    assert top == pytest.approx(1.0, abs=1e-15) and at == pytest.approx(a, abs=1e-7)
    # a plateau (a constant) keeps its value and is not refined sample by sample
    calls = []
    at, top = peak(lambda p: calls.append(p) or np.full(len(p), 2.0), x, np.full(len(x), 2.0), period=TURN)
    assert top == 2.0 and not calls


def test_a_turn_that_does_not_repeat_keeps_its_ends():
    """Ring 50, satellite 20 (ratio 2.5): after a turn of the crank the satellite has turned −1.5
    turns, so the slider on B does not come back; its extremes over the turn include the range's
    ends, and there is no wrap to search and no time ratio."""
    text = (ROOT / "models" / "planetary_lever.toml").read_text(encoding="utf-8")
    text = (text.replace("C = [1.0, 0.0]", "C = [0.75, 0.0]").replace("B = [1.55, 0.0]\n", "B = [1.3, 0.0]\nD = [4.3, 0.0]\n")
            .replace("length = 1.0\n", "length = 0.75\n").replace("teeth = [60, 20]", "teeth = [50, 20]")
            .replace("[gear.mesh]", """
[links.rod]
points = ["B", "D"]
length = 3.0

[links.slider]
points = ["D"]

[prismatic.slider]
slider = "slider"
guide = "ground"
point = "D"
through = "O"
angle = 0.0

[gear.mesh]"""))
    (o,) = summarize(assemble(loads(text))).outputs.values()
    phi = np.linspace(0.0, 2 * math.pi, DENSE + 1)
    xb, yb = 0.75 * np.cos(phi) + 0.55 * np.cos(1.5 * phi), 0.75 * np.sin(phi) - 0.55 * np.sin(1.5 * phi)
    xd = xb + np.sqrt(9.0 - yb * yb)
    assert xd[-1] != pytest.approx(xd[0], abs=0.1)
    assert o.travel == pytest.approx(xd.max() - xd.min(), abs=1e-9)  # DENSE samples: (Δφ)²·|x″|/8 < 1e-9 m
    steps = np.sign(np.diff(xd))
    assert len(o.limits) == int(np.count_nonzero(steps[1:] != steps[:-1])) and o.time_ratio is None
