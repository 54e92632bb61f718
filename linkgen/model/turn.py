"""Where a one-degree-of-freedom chain assembles over one turn of its crank, for every family:
the turn is scanned every 0.1°, and each change between assembling and failing is bisected
to EDGE_TOL. A family gives its status function: crank angles (n,) [rad] → (fails, singular),
two (n,) bool masks — where the chain cannot be assembled, and where it is assembled but at or
too near a dead centre (its solver's singularity rule).

``assembles`` are the ranges where the chain can be put together (dead centres included: at
the edge of a range the chain is stretched or folded there); ``clean`` the ranges where it is
also regular — the ones a crank-angle range (planar ``drive.range``) can run over.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import numpy as np

# Crank angles over a turn at which the status is scanned (every 0.1°), and how finely [rad]
# each change is then bisected.
RANGE_SAMPLES = 3600
EDGE_TOL = 1e-12
# A suggested range is rounded inward to this step [°], so that its ends lie inside.
SUGGEST_STEP_DEG = 1e-3

Status = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]


@dataclass(frozen=True)
class TurnAssembly:
    """Ranges (lo, hi) [rad] over the turn [start, start + 2π): ``fails`` where the chain cannot
    be assembled, ``assembles`` the rest, ``clean`` where it is assembled and regular. A range
    that runs through the turn's start begins before it (e.g. −60°..60°)."""

    start: float
    fails: tuple[tuple[float, float], ...]
    assembles: tuple[tuple[float, float], ...]
    clean: tuple[tuple[float, float], ...]

    @property
    def full(self) -> bool:
        """True when the chain assembles at every crank angle: the crank can turn fully."""
        return not self.fails

    @property
    def regular(self) -> bool:
        """True when the chain is assembled and regular over the whole turn."""
        return len(self.clean) == 1 and self.clean[0][1] - self.clean[0][0] >= 2 * math.pi

    def suggestion(self) -> tuple[float, float] | None:
        """The widest clean range, its ends rounded inward to SUGGEST_STEP_DEG [°] (degrees),
        or None when there is none."""
        if not self.clean:
            return None
        lo, hi = max(self.clean, key=lambda r: r[1] - r[0])
        a = math.ceil(math.degrees(lo) / SUGGEST_STEP_DEG - 1e-9) * SUGGEST_STEP_DEG
        b = math.floor(math.degrees(hi) / SUGGEST_STEP_DEG + 1e-9) * SUGGEST_STEP_DEG
        return (a, b) if a < b else None


def degrees_text(ranges, digits: int = 6) -> str:
    """'a°..b°, c°..d°' for ranges [rad]."""
    return ", ".join(f"{math.degrees(lo):.{digits}f}°..{math.degrees(hi):.{digits}f}°" for lo, hi in ranges)


def drive_range_text(pair: tuple[float, float]) -> str:
    """The TOML a user pastes under [drive] for a range given in degrees."""
    return f'range = ["{pair[0]:.3f}deg", "{pair[1]:.3f}deg"]'


def _edge(good: Callable[[float], bool], ok: float, bad: float) -> float:
    """The angle [rad] between ``ok`` (good) and ``bad`` (not) where good ends, to EDGE_TOL."""
    while abs(bad - ok) > EDGE_TOL:
        mid = 0.5 * (ok + bad)
        if good(mid):
            ok = mid
        else:
            bad = mid
    return ok


def _runs(mask: np.ndarray, phi: np.ndarray, step: float, good: Callable[[float], bool]) -> tuple:
    """Cyclic runs of True in ``mask`` over the grid ``phi`` (uniform, one turn) with their ends
    bisected to where ``good`` changes."""
    n = mask.shape[0]
    if mask.all():
        return ((float(phi[0]), float(phi[0]) + 2 * math.pi),)
    if not mask.any():
        return ()
    starts = [i for i in range(n) if mask[i] and not mask[i - 1]]
    out = []
    for s in starts:
        e = s
        while mask[(e + 1) % n]:
            e += 1
        lo = _edge(good, float(phi[s]), float(phi[s]) - step)
        hi = _edge(good, float(phi[0]) + e * step, float(phi[0]) + (e + 1) * step)
        if hi > phi[0] + 2 * math.pi:  # through the turn's start: shown from before it (−76°..61°, not 284°..421°)
            lo, hi = lo - 2 * math.pi, hi - 2 * math.pi
        out.append((lo, hi))
    return tuple(sorted(out))


def turn_assembly(status: Status, start: float = 0.0, samples: int = RANGE_SAMPLES) -> TurnAssembly:
    """Scan one turn from ``start`` [rad] with ``status`` and bisect every change."""
    step = 2 * math.pi / samples
    phi = start + step * np.arange(samples)
    fails, singular = (np.asarray(m, dtype=bool) for m in status(phi))

    def assembles(x: float) -> bool:
        return not bool(status(np.array([x]))[0][0])

    def clean(x: float) -> bool:
        f, s = status(np.array([x]))
        return not (bool(f[0]) or bool(s[0]))

    return TurnAssembly(start, _runs(fails, phi, step, lambda x: not assembles(x)), _runs(~fails, phi, step, assembles),
                        _runs(~fails & ~singular, phi, step, clean))


__all__ = ["EDGE_TOL", "RANGE_SAMPLES", "SUGGEST_STEP_DEG", "TurnAssembly", "degrees_text", "drive_range_text",
           "turn_assembly"]


def full_turn(mech) -> bool:
    """True when the drive's range is a whole turn of a crank (a full turn leaves out its end, which
    repeats its start); never for a prismatic drive, whose range is a stroke [m]."""
    d = mech.drive
    return not getattr(mech, "slide_drive", False) and d.stop - d.start >= 2 * math.pi - 1e-12
