"""``friction_table.FrictionTable.solve`` at a single state in plain floats: the ODE's right-hand
side and each MuJoCo step ask for one state at a time, where numpy's per-call overhead on arrays of
four or five numbers is most of the cost (the same Newton iteration, the same stopping rule and
checks; tests/test_machine_friction.py compares the two)."""

from __future__ import annotations

import math


def solve_one(tab, v: list, w: float, epsilon: float | None, free: float, inertia: float, s: float,
              guess: list | None, tol: float, iterations: int):
    """(f (list of K), ε, rel (list of K), ok) at one state from the table's columns ``v`` there
    (``FrictionTable.columns``' layout, as a list); the arguments as ``FrictionTable.solve``'s."""
    k, c = tab.k, tab.c
    a = [v[j * c:(j + 1) * c] for j in range(4)]
    g = [v[4 * c + j * c:4 * c + (j + 1) * c] for j in range(k)]  # g[j][comp]: pair j's unit friction
    rel = v[4 * c + c * k:4 * c + c * k + k]
    coef = [(math.copysign(1.0, w * r) if w * r != 0 else 0.0) * mu if abs(r) > still else 0.0
            for r, mu, still in zip(rel, tab.mu_r_list, tab.still_list)]
    joint = epsilon is None
    e0 = free / inertia if joint else epsilon
    base = [a0 + w * w * a2 + w * ac + e0 * ae for a0, a2, ae, ac in zip(*a)]  # rest, ω², ε, dampers
    if joint:  # ε = (free + s·rel·f)/J eliminated: Q = G + A_ε ⊗ s·rel/J
        q = [[gj[i] + a[2][i] * s * rel[j] / inertia for i in range(c)] for j, gj in enumerate(g)]
    else:
        q = g
    if guess is None:
        rho, _, _ = _rho(tab, base)
        f = [-cf * r for cf, r in zip(coef, rho)]
    else:
        f = list(guess)
    ok, jac = False, None
    for _ in range(iterations):
        r = [base[i] + sum(q[j][i] * f[j] for j in range(k)) for i in range(c)]
        rho, dx, dy = _rho(tab, r)
        jac = [[(1.0 if p == j else 0.0) + coef[p] * (dx[p] * q[j][2 * p] + dy[p] * q[j][2 * p + 1]) for j in range(k)]
               for p in range(k)]
        step, det = _linear(jac, [f[p] + coef[p] * rho[p] for p in range(k)])
        if step is None:
            break
        f = [fp - sp for fp, sp in zip(f, step)]
        if not all(math.isfinite(x) for x in step):
            break
        if all(abs(sp) <= tol * abs(fp) for sp, fp in zip(step, f)):
            ok = True
            break
    eps = (free + s * sum(rj * fj for rj, fj in zip(rel, f))) / inertia if joint else epsilon
    if ok:
        ok = det > 0
        if joint and ok:  # the friction's own fixed point (Q → G) must be one the closed form reaches too
            own = [[(1.0 if p == j else 0.0) + coef[p] * (dx[p] * g[j][2 * p] + dy[p] * g[j][2 * p + 1])
                    for j in range(k)] for p in range(k)]
            ok = _linear(own, [0.0] * k)[1] > 0
    return f, eps, rel, ok


def _rho(tab, r: list):
    """ρ_k and its derivatives by the pair's two components (``FrictionTable._rho``), as lists."""
    rho, dx, dy = [], [], []
    for p in range(tab.k):
        x, y = r[2 * p], r[2 * p + 1]
        if tab.revolute_list[p]:
            n = math.hypot(x, y)
            safe = n if n > 0 else 1.0
            rho.append(n)
            dx.append(x / safe)
            dy.append(y / safe)
            continue
        lever = tab.two_over_l_list[p] * abs(y)
        if abs(x) >= lever:
            rho.append(abs(x))
            dx.append(math.copysign(1.0, x) if x != 0 else 0.0)
            dy.append(0.0)
        else:
            rho.append(lever)
            dx.append(0.0)
            dy.append(tab.two_over_l_list[p] * (math.copysign(1.0, y) if y != 0 else 0.0))
    return rho, dx, dy


def _linear(m: list, b: list):
    """The solution of m·x = b (Gaussian elimination, partial pivoting) and det m; (None, 0.0)
    when m is singular."""
    n = len(b)
    m = [row[:] + [bi] for row, bi in zip(m, b)]
    det = 1.0
    for i in range(n):
        p = max(range(i, n), key=lambda r: abs(m[r][i]))
        if m[p][i] == 0.0:
            return None, 0.0
        if p != i:
            m[i], m[p] = m[p], m[i]
            det = -det
        piv = m[i][i]
        det *= piv
        for r in range(i + 1, n):
            factor = m[r][i] / piv
            if factor:
                row_r, row_i = m[r], m[i]
                for col in range(i, n + 1):
                    row_r[col] -= factor * row_i[col]
    x = [0.0] * n
    for i in range(n - 1, -1, -1):
        x[i] = (m[i][n] - sum(m[i][j] * x[j] for j in range(i + 1, n))) / m[i][i]
    return x, det


__all__ = ["solve_one"]
