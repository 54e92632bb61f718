"""Cam laws against their definitions (boundary values, finite differences) and the disc cam's
geometry against independent constructions."""

import math

import numpy as np
import pytest

from linkgen.families.cam.laws import LAWS, Program, Segment, motion, rise
from linkgen.families.cam.profile import TranslatingCam, min_base_radius

# Central differences with step H on functions of order one: truncation ~H², rounding ~1e-16/H.
H = 1e-5
FD_TOL = 1e-7


def program(law="harmonic"):
    d = math.radians
    return Program((Segment("rise", d(120), law, 0.05), Segment("dwell", d(60)),
                    Segment("return", d(120), law, 0.05), Segment("dwell", d(60))))


@pytest.mark.parametrize("law", LAWS)
def test_a_unit_rise_starts_and_ends_at_rest(law):
    s, v, a, _ = rise(law, np.array([0.0, 1.0]))
    assert s.tolist() == pytest.approx([0.0, 1.0], abs=1e-15)
    assert v.tolist() == pytest.approx([0.0, 0.0], abs=1e-14)
    if law != "harmonic":  # the harmonic law's acceleration jumps at the ends, the others' does not
        assert a.tolist() == pytest.approx([0.0, 0.0], abs=1e-12)


@pytest.mark.parametrize("law", LAWS)
def test_derivatives_are_those_of_the_displacement(law):
    x = np.linspace(0.05, 0.95, 19)
    d = rise(law, x)
    for k in range(3):
        fd = (rise(law, x + H)[k] - rise(law, x - H)[k]) / (2 * H)
        assert np.abs(fd - d[k + 1]).max() <= FD_TOL * max(1.0, np.abs(d[k + 1]).max())


def test_program_displacement_and_time_derivatives():
    p = program("cycloidal")
    th = np.linspace(0.01, 2 * math.pi - 0.01, 500)
    s, v, a, j = motion(p, th, 3.0, 0.5)
    assert p.stroke == pytest.approx(0.05, abs=1e-9)
    assert s.min() >= -1e-15 and s[(th > math.radians(125)) & (th < math.radians(175))] == pytest.approx(0.05)
    # time derivatives along θ(t) = ½εt² + ωt: finite differences in time
    t = np.linspace(0.01, 1.0, 50)
    theta = lambda t: 3.0 * t + 0.25 * t * t  # noqa: E731
    hs = 1e-5
    s0 = lambda t: p.displacement(theta(t))[0]  # noqa: E731
    _, vv, aa, _ = motion(p, theta(t), 3.0 + 0.5 * t, 0.5)
    assert np.abs((s0(t + hs) - s0(t - hs)) / (2 * hs) - vv).max() <= 1e-7
    assert np.abs((s0(t + hs) - 2 * s0(t) + s0(t - hs)) / hs**2 - aa).max() <= 1e-3 * np.abs(aa).max()


def test_roller_centre_lies_on_the_pitch_curve_at_the_follower_position():
    cam = TranslatingCam(program(), 0.25, 0.04, 0.1)
    th = np.linspace(0, 2 * math.pi, 721)
    p, _, _ = cam.pitch_curve(th)
    s = cam.program.displacement(th)[0]
    # turning the pitch point back by +θ gives the follower's roller centre (e, d + s)
    c, sn = np.cos(th), np.sin(th)
    world = np.column_stack([p[:, 0] * c - p[:, 1] * sn, p[:, 0] * sn + p[:, 1] * c])
    assert np.abs(world[:, 0] - 0.1).max() < 1e-15 * 10
    assert np.abs(world[:, 1] - (math.sqrt(0.29**2 - 0.01) + s)).max() < 1e-14


def test_pitch_derivatives_and_profile_distance():
    cam = TranslatingCam(program("poly345"), 0.25, 0.04, 0.1)
    th = np.linspace(0.1, 6.0, 60)
    p, d1, d2 = cam.pitch_curve(th)
    fd1 = (cam.pitch_curve(th + H)[0] - cam.pitch_curve(th - H)[0]) / (2 * H)
    fd2 = (cam.pitch_curve(th + H)[1] - cam.pitch_curve(th - H)[1]) / (2 * H)
    assert np.abs(fd1 - d1).max() < 1e-8 and np.abs(fd2 - d2).max() < 1e-7
    prof = cam.profile(th)
    assert np.hypot(*(prof - p).T) == pytest.approx(0.04, abs=1e-15)
    assert (np.hypot(*prof.T) < np.hypot(*p.T)).all()  # inside the pitch curve


def test_pressure_angle_is_the_angle_between_the_normal_and_the_follower():
    cam = TranslatingCam(program(), 0.25, 0.04, 0.1)
    th = np.linspace(0.05, 6.2, 100)
    _, d1, _ = cam.pitch_curve(th)
    c, sn = np.cos(th), np.sin(th)
    tw = np.column_stack([d1[:, 0] * c - d1[:, 1] * sn, d1[:, 0] * sn + d1[:, 1] * c])  # world tangent
    # the normal's angle from the follower's +y direction equals the tangent's from +x
    alpha = np.arctan2(tw[:, 1], tw[:, 0])
    alpha = (alpha + math.pi / 2) % math.pi - math.pi / 2
    assert np.abs(np.abs(alpha) - np.abs(cam.pressure_angle(th))).max() < 1e-12


def test_curvature_of_the_base_circle_and_undercutting():
    cam = TranslatingCam(program(), 0.25, 0.04, 0.0)
    dwell = np.array([math.radians(330)])
    assert cam.pitch_curvature_radius(dwell)[0] == pytest.approx(0.29, rel=1e-12)
    # against the circle through three neighbouring pitch points (an independent construction)
    th = np.linspace(0.05, 6.2, 200)
    hh = 1e-4
    a, b, c = (cam.pitch_curve(th + k * hh)[0] for k in (-1, 0, 1))
    ab, bc, ca = (np.hypot(*(u - v).T) for u, v in ((a, b), (b, c), (c, a)))
    area2 = np.abs((b - a)[:, 0] * (c - a)[:, 1] - (b - a)[:, 1] * (c - a)[:, 0])
    circum = ab * bc * ca / (2 * area2)
    assert np.abs(np.abs(cam.pitch_curvature_radius(th)) - circum).max() < 1e-5 * circum.max()
    d = math.radians
    sharp = Program((Segment("rise", d(40), "cycloidal", 0.05), Segment("dwell", d(140)),
                     Segment("return", d(40), "cycloidal", 0.05), Segment("dwell", d(140))))
    small = TranslatingCam(sharp, 0.02, 0.04, 0.0)
    grid = np.linspace(0, 2 * math.pi, 3600)
    rho = small.pitch_curvature_radius(grid)
    assert ((rho > 0) & (rho < 0.04)).any() and small.undercut(grid).any()
    assert not cam.undercut(grid).any()


def test_min_base_radius_meets_the_pressure_angle_limit():
    limit = math.radians(30)
    rb = min_base_radius(program(), limit, 0.04, 0.0)
    th = np.linspace(0, 2 * math.pi, 4096, endpoint=False)
    assert np.abs(TranslatingCam(program(), rb, 0.04).pressure_angle(th)).max() <= limit + 1e-12
    assert np.abs(TranslatingCam(program(), rb * 0.999, 0.04).pressure_angle(th)).max() > limit
    # centred harmonic rise: tan α = (π·h/2β)·sin πx / (d + h/2·(1 − cos πx)); the d at which
    # its largest value over x is tan 30°, by bisection on these formulas alone
    h, beta = 0.05, math.radians(120)
    x = np.linspace(0, 1, 200001)

    def over(d):
        return (math.pi * h / (2 * beta) * np.sin(math.pi * x) / (d + h / 2 * (1 - np.cos(math.pi * x)))).max()

    lo, hi = 1e-6, 1.0
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if over(mid) > math.tan(limit) else (lo, mid)
    assert rb + 0.04 == pytest.approx(hi, rel=1e-6)
