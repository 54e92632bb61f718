"""The loop gap's own dynamics in MuJoCo, its constraint rows coupled, along a closed-form motion.

With the loop force λ the closed form gives, MuJoCo's soft ``connect`` holds a gap r and a gap
velocity s = J·q̇ (each (rows,)) that obey (``mujoco.accuracy``'s docstring has the model)

    ṡ = g·(r_λ − r) − hd·s,   ṙ = s + u,   r_λ = −R·λ/(K·d),   g = Q·K·d,   hd = Q·B,

Q = A·(A + R)⁻¹ (rows × rows; d·I where A is diagonal: a critically damped loop of rate
d/(dmax·τ·ζ)), u the integrator's drift. ``gap_states`` gives r, s and the gap acceleration a1 = J·q̈ + J̇·q̇
MuJoCo computes at the sampled states, for the integrator's own steps (``step``): analytically
where every mode of the loop is fast beside the crank (its fixed point and lag per sample, and
the decay of a start with the loops closed), by following the dynamics where one is not.
"""

from __future__ import annotations

import math

import numpy as np

# Sub-steps per loop time constant 1/ω_n when the gap's dynamics are followed between samples
# (semi-implicit; its own error is then under 1 % of the lag it models).
FILTER_SUBSTEPS = 20
# Where a sample's span exceeds this many loop time constants 1/ω_n the followed gap is taken at
# its quasi-static value (its lag, ~2ζ/ω_n, is then under 4 % of the span).
QUASI_STATIC = 50.0
# The loop is "fast" where its slowest mode's rate is at least this many times the crank speed:
# the gap is then its fixed point plus a first-order lag (the next term, (ω/rate)², under
# 0.25 %), computed exactly; following it numerically would let the loop's stiffness amplify the
# following's own error.
FAST = 20.0


def impedance(solimp: tuple[float, ...], violation: np.ndarray) -> np.ndarray:
    """MuJoCo's impedance d at constraint violations ``violation`` [m] (solimp = dmin, dmax,
    width, midpoint, power; clamped as MuJoCo clamps them)."""
    lo, hi = (min(0.9999, max(1e-4, v)) for v in solimp[:2])
    width = max(0.0, solimp[2])
    mid = min(0.9999, max(1e-4, solimp[3])) if len(solimp) > 3 else 0.5
    p = max(1.0, solimp[4]) if len(solimp) > 4 else 2.0
    x = np.abs(np.asarray(violation, dtype=float))
    if lo == hi or width <= 1e-15:
        return np.full(x.shape, 0.5 * (lo + hi))
    x = np.minimum(x / width, 1.0)
    y = np.where(x <= mid, x**p / mid ** (p - 1), 1.0 - (1.0 - x) ** p / (1.0 - mid) ** (p - 1))
    return lo + y * (hi - lo)


def reference_gains(settings) -> tuple[float, float, tuple[float, ...]]:
    """MuJoCo's reference gains of a loop row at ``settings`` (``mujoco.options.Settings``):
    K = 1/(dmax²·τ²·ζ²) and B = 2/(dmax·τ), τ the solref time constant raised to 2·timestep (its
    refsafe clamp), and the solimp they come with."""
    solimp = tuple(float(x) for x in settings.solimp_text.split())
    dmax = min(0.9999, max(1e-4, solimp[1]))
    tau = max(settings.timeconst, 2.0 * settings.timestep)
    return 1.0 / (dmax * dmax * tau * tau * settings.dampratio**2), 2.0 / (dmax * tau), solimp


def quasi_static_gap(lam, diag, u, k_ref, b_ref, solimp) -> tuple[np.ndarray, np.ndarray]:
    """Per row r = (B·u − R·λ)/(K·d) with d = d(|r|) per closure (solved by bisection on |r|:
    |r| falls as d rises), and the smallest d."""
    n = lam.shape[0] // 2

    def gap(d):
        dd = np.repeat(d, 2)
        return (b_ref * u - ((1.0 - dd) / dd) * diag * lam) / (k_ref * dd)

    lo = np.zeros(n)
    hi = np.linalg.norm(gap(impedance(solimp, np.zeros(n))).reshape(n, 2), axis=1)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        too_big = np.linalg.norm(gap(impedance(solimp, mid)).reshape(n, 2), axis=1) < mid
        hi = np.where(too_big, mid, hi)
        lo = np.where(too_big, lo, mid)
    d = impedance(solimp, 0.5 * (lo + hi))
    return gap(d), np.repeat(d, 2)


def _mv(m: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Per sample, matrix (samples, n, n) times vector (samples, n)."""
    return np.einsum("kij,kj->ki", m, x)


def gap_states(integrator: str, r_lam: np.ndarray, jdv: np.ndarray, s_extra: np.ndarray, g: np.ndarray, hd: np.ndarray,
               h: float, t: np.ndarray, omega: float, full: bool, cold: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """r, s and a1 (each (samples, rows)) at the samples' times t [s] for steps of h [s] with
    ``integrator``; r_λ, J̇·q̇ and ``step``'s s_extra (samples, rows); the loop's stiffness g and
    damping hd (samples, rows, rows): ṡ = g·(r_λ − r) − hd·s. ``cold``: the run starts at t = 0
    with its loops closed and still (r = s = 0)."""
    u = -0.5 * h * jdv if integrator != "RK4" else np.zeros_like(jdv)
    n = r_lam.shape[1]
    if n == 0:  # no loop
        return r_lam.copy(), r_lam.copy(), r_lam.copy()
    if _slowest_rate(g, hd) >= FAST * abs(omega):
        x, m = _fixed_point_and_lag(integrator, r_lam, jdv, s_extra, g, hd, h, t, full)
        # The gap is the part r_λ drives plus the integrator's own offset (its step's forcing by
        # the motion's curvature, J̇·q̇ and s_extra: the map is linear, the parts add). The
        # offset's acceleration is the constraint model's at it, −g·r − hd·s. The driven part's
        # is its velocity's rate, not g·(r_λ − r) − hd·s: there the two first-order terms cancel
        # to the (ω/rate)² term the lag leaves out, and the loop's stiffness g makes that
        # remainder larger than the acceleration itself (measured: 14× the run's, stiff RK4 loop).
        own = _fixed_point_and_lag(integrator, np.zeros_like(r_lam), jdv, s_extra, g, hd, h, t, full)[0]
        a1 = rate(x[:, n:] - own[:, n:], t, full) - _mv(g, own[:, :n]) - _mv(hd, own[:, n:])
        if cold:  # the start's transient (the run starts at t = 0): the homogeneous steps from −x(0)
            x0 = -x[0]
            for k in range(t.shape[0]):
                xh = np.linalg.matrix_power(m[0], int(round(t[k] / h))) @ x0
                x[k] += xh
                a1[k] += -g[k] @ xh[:n] - hd[k] @ xh[n:]
        return x[:, :n], x[:, n:], a1
    else:
        r, s = follow(r_lam, u, t, g, hd, full, cold)
        off = discrete_offset(integrator, r_lam, jdv, s_extra, g, hd, h, t, full)
        r, s = r + off[:, :n], s + off[:, n:]
    return r, s, _mv(g, r_lam - r) - _mv(hd, s)


def _slowest_rate(g: np.ndarray, hd: np.ndarray) -> float:
    """The slowest rate [1/s] (smallest |eigenvalue|) of the loop's modes over the samples."""
    n = g.shape[1]
    a = np.zeros((g.shape[0], 2 * n, 2 * n))
    a[:, :n, n:] = np.eye(n)
    a[:, n:, :n], a[:, n:, n:] = -g, -hd
    return float(np.abs(np.linalg.eigvals(a)).min())


def _map(integrator, r_lam, jdv, s_extra, g, hd, h):
    """The step map x ↦ M·x + c of x = (r, s), (samples, 2n): M (samples, 2n, 2n) and c."""
    zero = np.zeros_like(r_lam)
    n = r_lam.shape[1]
    c = np.concatenate(step(integrator, zero, zero, r_lam, jdv, s_extra, g, hd, h), axis=1)
    cols = []
    for j in range(2 * n):
        e = np.zeros((r_lam.shape[0], 2 * n))
        e[:, j] = 1.0
        cols.append(np.concatenate(step(integrator, e[:, :n], e[:, n:], zero, zero, zero, g, hd, h), axis=1))
    return np.stack(cols, axis=2), c


def _fixed_point_and_lag(integrator, r_lam, jdv, s_extra, g, hd, h, t, full):
    """Per sample, the step map's fixed point plus its lag, x (samples, 2n), and the map M."""
    m, c = _map(integrator, r_lam, jdv, s_extra, g, hd, h)
    i_m = np.eye(m.shape[1]) - m
    x_d = np.linalg.solve(i_m, c[..., None])[..., 0]
    return x_d - h * np.linalg.solve(i_m, rate(x_d, t, full)[..., None])[..., 0], m


def step(integrator: str, r, v, r_lam, jdv, s_extra, g, hd, h: float):
    """One MuJoCo step of the loop's gap (r, s = J·q̇), each (samples, rows), with r_λ and J̇·q̇ held.

    Euler (and implicitfast: no joint damping here) updates s, then moves the positions with the
    new velocity: the gap then opens by −½·h²·J̇·q̇ unseen by s, and s = J(q)·q̇ read at the
    step's end moves by h·a1 + h²·``s_extra`` (a1 read at the step's start; s_extra = 2·H(q̇, q̈)
    + ½·T(q̇, q̇, q̇) from J's change along the step, H and T J's second and third derivatives
    along the motion). RK4 moves each stage along the previous stage's velocity: the gap a stage
    sees is off the linear model by the motion's curvature, +h²·J̇·q̇/8 at the second stage and
    −h²·J̇·q̇/8 at the third (none at the fourth and after the step, where Σ bᵢ·cᵢ = ½ cancels it)."""
    def acc(rr, vv):
        return _mv(g, r_lam - rr) - _mv(hd, vv)

    if integrator != "RK4":
        v1 = v + h * acc(r, v) + h * h * s_extra
        return r + h * v1 - 0.5 * h * h * jdv, v1
    a1 = acc(r, v)
    r2, v2 = r + 0.5 * h * v + h * h * jdv / 8.0, v + 0.5 * h * a1
    a2 = acc(r2, v2)
    r3, v3 = r + 0.5 * h * v2 - h * h * jdv / 8.0, v + 0.5 * h * a2
    a3 = acc(r3, v3)
    r4, v4 = r + h * v3, v + h * a3
    a4 = acc(r4, v4)
    return r + h / 6.0 * (v + 2 * v2 + 2 * v3 + v4), v + h / 6.0 * (a1 + 2 * a2 + 2 * a3 + a4)


def discrete_offset(integrator: str, r_lam: np.ndarray, jdv: np.ndarray, s_extra: np.ndarray, g: np.ndarray,
                    hd: np.ndarray, h: float, t: np.ndarray, full: bool) -> np.ndarray:
    """What MuJoCo's steps at h add to the continuous gap dynamics, (samples, 2n): the step map
    x ↦ M·x + c (``step``) has its fixed point x_d = (I − M)⁻¹·c and, for a slowly moving one, a
    lag −(I − M)⁻¹·h·ẋ_d; the continuous dynamics ẋ = A·x + b have x_c and A⁻¹·ẋ_c. The
    difference of the two (fixed point and lag) is added to the followed gap: it grows as
    (ω_n·h)⁴ for RK4 (MuJoCo's refsafe keeps ω_n·h ≤ ½)."""
    n = r_lam.shape[1]
    x_d = _fixed_point_and_lag(integrator, r_lam, jdv, s_extra, g, hd, h, t, full)[0]
    u = -0.5 * h * jdv if integrator != "RK4" else np.zeros_like(r_lam)
    x_c = np.concatenate([r_lam + np.linalg.solve(g, _mv(hd, u)[..., None])[..., 0], -u], axis=1)
    a = np.zeros((r_lam.shape[0], 2 * n, 2 * n))
    a[:, :n, n:] = np.eye(n)
    a[:, n:, :n], a[:, n:, n:] = -g, -hd
    return x_d - x_c - np.linalg.solve(a, rate(x_c, t, full)[..., None])[..., 0]


def rate(x: np.ndarray, t: np.ndarray, full: bool) -> np.ndarray:
    """d x/dt along the samples' first axis (central differences; a full turn wraps around)."""
    if x.shape[0] < 3:
        return np.zeros_like(x)
    if not full:
        return np.gradient(x, t, axis=0, edge_order=2 if x.shape[0] > 2 else 1)  # second order at the range's ends too
    return (np.roll(x, -1, axis=0) - np.roll(x, 1, axis=0)) / (2.0 * (t[1] - t[0]))


def follow(r_lam: np.ndarray, u: np.ndarray, t: np.ndarray, g: np.ndarray, hd: np.ndarray, full: bool,
           cold: bool) -> tuple[np.ndarray, np.ndarray]:
    """The gap along the samples through the loop's own dynamics, ṡ = g·(r_λ − r) − hd·s (s = J·q̇
    the gap velocity MuJoCo sees) and ṙ = s + u (u the integrator's drift), r_λ linear between
    samples; from a closed loop at rest (``cold``) or from the quasi-static state (s = −u, r = r_λ
    + g⁻¹·hd·u). A full turn is followed twice and the second turn kept (periodic). Returns r and
    s, each (samples, rows)."""
    n = r_lam.shape[0]
    passes = 2 if full else 1
    period = (t[-1] - t[0]) * n / (n - 1) if full and n > 1 else 0.0
    if cold:
        r, v = np.zeros_like(r_lam[0]), np.zeros_like(r_lam[0])
    else:
        r, v = r_lam[0] + np.linalg.solve(g[0], hd[0] @ u[0]), -u[0]
    if cold and t[0] > 0:  # the run starts at t = 0; its first sample comes later
        r, v = _advance(r, v, r_lam[0], r_lam[0], u[0], g[0], hd[0], t[0])
    out, out_v = np.zeros_like(r_lam), np.zeros_like(r_lam)
    for p in range(passes):
        for k in range(n):
            out[k], out_v[k] = r, v
            if k + 1 < n:
                r, v = _advance(r, v, r_lam[k], r_lam[k + 1], u[k], g[k], hd[k], t[k + 1] - t[k])
            elif full:
                r, v = _advance(r, v, r_lam[k], r_lam[0], u[k], g[k], hd[k], t[0] + period - t[k])
    return out, out_v


def _advance(r, v, a, b, u, g, hd, span: float):
    """The gap (r, s) ``span`` [s] later, r_λ going from a to b linearly."""
    rates = np.abs(np.linalg.eigvals(np.block([[np.zeros_like(g), np.eye(g.shape[0])], [-g, -hd]])))
    if span * rates.min() > QUASI_STATIC:  # every mode answers within a small part of the span
        return b + np.linalg.solve(g, hd @ u), -u
    m = max(1, int(math.ceil(span * rates.max() * FILTER_SUBSTEPS)))
    h = span / m
    lhs = np.eye(g.shape[0]) + h * hd
    for i in range(m):
        target = a + (b - a) * (i + 1) / m
        v = np.linalg.solve(lhs, v + h * g @ (target - r))
        r = r + h * (v + u)
    return r, v


__all__ = ["FAST", "discrete_offset", "follow", "gap_states", "impedance", "quasi_static_gap", "rate", "reference_gains",
           "step"]
