"""Andrews' squeezing mechanism integrated here in the benchmark's own seven coordinates, without
linkgen: an independent referee for models/andrews_squeezer.toml (tests/test_benchmarks.py).

The data and coordinates are Hairer & Wanner's (II §VII.7) as the IVP test set gives them: β the
crank's angle, Θ the coupler's relative to it, γ body 3's, Φ and δ bodies 4 and 5's, Ω and ε
bodies 6 and 7's (module ``validation/benchmarks.py`` maps linkgen's link angles onto them). Every
centre of mass, the hinge E reached along each of the four chains and the spring's point D are
written as a constant plus terms r·(cos(a·q + c), sin(a·q + c)), so that their Jacobians and the
velocity-squared terms are exact. The equations of motion with Lagrange multipliers, index 1:

    [M  Gᵀ] [q̈]   [Q − Σ m·J_Sᵀ·(J̇_S·q̇)]
    [G  0 ] [λ] = [−Ġ·q̇               ]

(M = Σ m·J_Sᵀ·J_S + I·aᵀ·a, G the Jacobian of the three closure conditions E₁ = E₃ = E₄ = E₆,
Q the crank's torque and the spring's force through ∂D/∂q), integrated by DOP853; the closure
drifts by less than 1e-14 m over 0.03 s at rtol 1e-12."""

from __future__ import annotations

import math

import numpy as np
from scipy.integrate import solve_ivp

MASS = (.04325, .00365, .02373, .00706, .07050, .00706, .05498)  # kg
INERTIA = (2.194e-6, 4.410e-7, 5.255e-6, 5.667e-7, 1.169e-5, 5.667e-7, 1.912e-5)  # kg·m² about the centres
XA, YA, XB, YB, XC, YC = -.06934, -.00227, -.03635, .03273, .014, .072  # m
D, DA, E, EA, RR, RA = 28e-3, 115e-4, 2e-2, 1421e-5, 7e-3, 92e-5
SS, SA, SB, SC, SD = 35e-3, 1874e-5, 1043e-5, 18e-3, 2e-2
TA, TB, U, UA, UB = 2308e-5, 916e-5, 4e-2, 1228e-5, 449e-5
ZF, ZT, FA = 2e-2, 4e-2, 1421e-5
TORQUE, STIFFNESS, REST = 0.033, 4530.0, 0.07785  # N·m, N/m, m
START = (-0.0617138900142764496358948458001, 0.0, 0.455279819163070380255912382449,
         0.222668390165885884674473185609, 0.487364979543842550225598953530,
         -0.222668390165885884674473185609, 1.23054744454982119249735015568)  # rad, consistent

BETA, THETA, GAMMA, PHI, DELTA, OMEGA, EPS = range(7)
_Q = math.pi / 2


def _a(*coords: int) -> np.ndarray:
    a = np.zeros(7)
    a[list(coords)] = 1.0
    return a


# (constant [m], ((r [m], a, c [rad]), ...)): the point const + Σ r·(cos(a·q + c), sin(a·q + c)).
CENTRES = (((0, 0), ((RA, _a(BETA), 0),)),
           ((0, 0), ((RR, _a(BETA), 0), (-DA, _a(BETA, THETA), 0))),
           ((XB, YB), ((SA, _a(GAMMA), -_Q), (SB, _a(GAMMA), 0))),
           ((XA, YA), ((ZT, _a(DELTA), 0), (E - EA, _a(PHI, DELTA), -_Q))),
           ((XA, YA), ((TA, _a(DELTA), 0), (TB, _a(DELTA), _Q))),
           ((XA, YA), ((U, _a(EPS), -_Q), (ZF - FA, _a(OMEGA, EPS), 0))),
           ((XA, YA), ((UA, _a(EPS), -_Q), (-UB, _a(EPS), 0))))
ANGLES = (_a(BETA), _a(BETA, THETA), _a(GAMMA), _a(PHI, DELTA), _a(DELTA), _a(OMEGA, EPS), _a(EPS))
HINGE_E = (((0, 0), ((RR, _a(BETA), 0), (-D, _a(BETA, THETA), 0))),  # along the crank and the coupler
           ((XB, YB), ((SS, _a(GAMMA), -_Q),)),  # along body 3
           ((XA, YA), ((ZT, _a(DELTA), 0), (E, _a(PHI, DELTA), -_Q))),  # along bodies 5 and 4
           ((XA, YA), ((U, _a(EPS), -_Q), (ZF, _a(OMEGA, EPS), 0))))  # along bodies 7 and 6
SPRING_D = ((XB, YB), ((SD, _a(GAMMA), 0), (SC, _a(GAMMA), -_Q)))


def _point(p, q: np.ndarray, qd: np.ndarray):
    """Position (2,), Jacobian (2, 7) and J̇·q̇ (2,) of a point at coordinates q, rates q̇."""
    const, terms = p
    x, jac, acc = np.array(const, dtype=float), np.zeros((2, 7)), np.zeros(2)
    for r, a, c in terms:
        t, w = a @ q + c, a @ qd
        cs, sn = math.cos(t), math.sin(t)
        x += r * np.array([cs, sn])
        jac += r * np.outer([-sn, cs], a)
        acc -= r * np.array([cs, sn]) * w * w
    return x, jac, acc


def rate(t: float, y: np.ndarray) -> np.ndarray:
    """d/dt of the state y = (q, q̇) (14,)."""
    q, qd = y[:7], y[7:]
    mass, force = np.zeros((7, 7)), np.zeros(7)
    for m, i, centre, a in zip(MASS, INERTIA, CENTRES, ANGLES):
        _, jac, acc = _point(centre, q, qd)
        mass += m * jac.T @ jac + i * np.outer(a, a)
        force -= m * jac.T @ acc
    force[BETA] += TORQUE
    d, jd, _ = _point(SPRING_D, q, qd)
    length = math.hypot(d[0] - XC, d[1] - YC)
    force += jd.T @ (-STIFFNESS * (length - REST) / length * (d - np.array([XC, YC])))
    first = _point(HINGE_E[0], q, qd)
    others = [_point(p, q, qd) for p in HINGE_E[1:]]
    g = np.vstack([first[1] - o[1] for o in others])
    gamma = np.concatenate([o[2] - first[2] for o in others])
    lhs = np.block([[mass, g.T], [g, np.zeros((6, 6))]])
    return np.concatenate([qd, np.linalg.solve(lhs, np.concatenate([force, gamma]))[:7]])


def solve(t_end: float, rtol: float = 1e-12) -> tuple[np.ndarray, np.ndarray, float]:
    """(q, q̇) at ``t_end`` [s] from the benchmark's start at rest, and the closure's drift [m] there."""
    sol = solve_ivp(rate, (0.0, t_end), np.concatenate([START, np.zeros(7)]), method="DOP853", rtol=rtol, atol=1e-14)
    q, qd = sol.y[:7, -1], sol.y[7:, -1]
    e = [_point(p, q, qd)[0] for p in HINGE_E]
    return q, qd, float(max(np.abs(e[0] - x).max() for x in e[1:]))
