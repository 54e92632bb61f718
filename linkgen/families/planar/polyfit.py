"""A joint coordinate as a polynomial of the crank angle, the form MuJoCo's joint equality takes
(``polycoef``: y − y0 = c0 + c1·(x − x0) + … + c4·(x − x0)⁴, x0 and y0 the joints' reference
values), fitted over the drive range.

The fit is minimax (the least largest error over the samples), not least squares: the figure a
coupled model is judged by, and states, is its largest position error over the range, and that is
exactly what minimax makes least (least squares leaves it 2.1–2.5× larger on the bundled models
over ranges where the minimax quartic just holds, ``validation/coupling_study.py``). It is a small linear programme (degree + 2 unknowns) solved by
HiGHS in the scaled variable t = (x − x0)/h ∈ [−1, 1], h the range's half-width, so that the
columns are of one size whatever the range; the coefficients are then scaled back to x − x0.
The error is measured afresh on a grid CHECK_FACTOR times finer than the one fitted.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# MuJoCo's joint equality takes a quartic (``polycoef``: five coefficients).
DEGREE = 4
# Samples fitted over the range, and how much finer the grid is on which the error is measured.
FIT_SAMPLES = 1201
CHECK_FACTOR = 8


@dataclass(frozen=True)
class PolyFit:
    """``coef`` (DEGREE + 1,) of y − y0 in powers of x − x0 (MuJoCo's ``polycoef`` order), the
    largest error |fit − y| over the range and the sample where it occurs, and the travel of y
    over the range (max − min), in y's unit."""

    coef: tuple[float, ...]
    max_error: float
    at: int
    travel: float

    @property
    def relative(self) -> float:
        """The largest error as a fraction of the travel (inf for a coordinate that does not move
        while the fit errs; 0 for one that neither moves nor errs)."""
        if self.travel > 0.0:
            return self.max_error / self.travel
        return 0.0 if self.max_error == 0.0 else float("inf")

    def __call__(self, dx) -> np.ndarray:
        """y − y0 at x − x0 = ``dx``."""
        return np.polyval(self.coef[::-1], np.asarray(dx, dtype=float))


def minimax(dx: np.ndarray, dy: np.ndarray, degree: int = DEGREE) -> np.ndarray:
    """Coefficients (degree + 1,) in powers of ``dx`` minimising max |poly(dx) − dy| over the
    samples (dx, dy) (n,), by linear programming."""
    from scipy.optimize import linprog

    h = float(np.max(np.abs(dx))) or 1.0
    t = dx / h
    scale = float(np.max(np.abs(dy))) or 1.0
    y = dy / scale
    v = np.vander(t, degree + 1, increasing=True)
    ones = np.ones((t.shape[0], 1))
    # minimise e subject to  V c − y ≤ e  and  y − V c ≤ e
    a = np.vstack([np.hstack([v, -ones]), np.hstack([-v, -ones])])
    b = np.concatenate([y, -y])
    cost = np.zeros(degree + 2)
    cost[-1] = 1.0
    res = linprog(cost, A_ub=a, b_ub=b, bounds=[(None, None)] * (degree + 1) + [(0, None)], method="highs")
    if not res.success:  # a bounded LP with a feasible point: HiGHS does not fail on it
        raise RuntimeError(f"minimax fit failed: {res.message}")
    c = res.x[:degree + 1] * scale
    return c / h ** np.arange(degree + 1)


def least_squares(dx: np.ndarray, dy: np.ndarray, degree: int = DEGREE) -> np.ndarray:
    """Coefficients (degree + 1,) in powers of ``dx`` minimising Σ (poly(dx) − dy)² (for the
    comparison in ``validation/coupling_study.py``)."""
    h = float(np.max(np.abs(dx))) or 1.0
    c = np.polynomial.polynomial.polyfit(dx / h, dy, degree)
    return c / h ** np.arange(degree + 1)


def grid(start: float, stop: float) -> np.ndarray:
    """The crank angles a fit is measured on (n,): CHECK_FACTOR·(FIT_SAMPLES − 1) + 1 over
    [start, stop], ends included; its middle sample (``MIDDLE``) is the reference x0."""
    return np.linspace(start, stop, CHECK_FACTOR * (FIT_SAMPLES - 1) + 1)


MIDDLE = CHECK_FACTOR * (FIT_SAMPLES - 1) // 2


def fit(x: np.ndarray, y: np.ndarray, x0: float, y0: float, method=minimax) -> PolyFit:
    """Fit y − y0 by a polynomial of x − x0 on every CHECK_FACTOR-th sample of ``x`` and ``y``
    (n,) (``grid``; y continuous: an angle unwrapped); the error is measured on every sample."""
    dx, dy = x - x0, y - y0
    coef = method(dx[::CHECK_FACTOR], dy[::CHECK_FACTOR])
    err = np.abs(np.polyval(coef[::-1], dx) - dy)
    k = int(np.argmax(err))
    return PolyFit(tuple(float(c) for c in coef), float(err[k]), k, float(np.ptp(y)))


__all__ = ["CHECK_FACTOR", "DEGREE", "FIT_SAMPLES", "MIDDLE", "PolyFit", "fit", "grid", "least_squares", "minimax"]
