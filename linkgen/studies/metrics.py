"""The design metrics of one variant over its drive's range, reduced from the closed form's
values on a grid of crank angles; one reduction for every route (``general`` and ``fourbar``
hand it the same arrays), so the routes can differ only in the arrays.

Per output (a link pivoted on the ground other than the crank: ``swing.NAME [rad]``; a slider:
``stroke.NAME [m]``) the travel, the crank angles of its least and greatest value
(``limit_min.NAME``, ``limit_max.NAME`` [rad]) and over a full turn the time ratio (working
over return stroke, ``time_ratio.NAME [1]``; none for a link that turns fully round); the
least transmission angle of all groups (μ = arcsin|D|, ``linkgen.families.planar.summary``),
the peak |balancing torque|, each joint's peak |reaction|, and the least and greatest reduced
moment of inertia J(φ) of the linkage at the crank. Values are those of the grid's samples
(not refined between them: a sweep compares designs on one grid)."""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

# Crank angles per variant unless asked otherwise (one per degree over a full turn).
ANGLES = 360
FULL_TURN_TOL = 1e-12


@dataclass(frozen=True)
class Layout:
    """The metric columns of a study (the same for every variant: one topology).

    Attributes:
        outputs: (name, "rocker" | "slider") of each output.
        joints: the joints whose reactions are reported (revolutes and prismatic pairs).
    """

    outputs: tuple[tuple[str, str], ...]
    joints: tuple[str, ...]

    @property
    def columns(self) -> tuple[str, ...]:
        out: list[str] = []
        for name, kind in self.outputs:
            out += [f"swing.{name} [rad]" if kind == "rocker" else f"stroke.{name} [m]",
                    f"limit_min.{name} [rad]", f"limit_max.{name} [rad]", f"time_ratio.{name} [1]"]
        out += ["min_transmission_angle [rad]", "peak_balancing_torque [N·m]"]
        out += [f"peak_reaction.{j} [N]" for j in self.joints]
        return tuple(out + ["J_min [kg·m²]", "J_max [kg·m²]"])


def angles(start: float, stop: float, n: int = ANGLES) -> tuple[np.ndarray, bool]:
    """``n`` crank angles over the drive's range [rad] (a full turn without its repeated end)
    and whether the range is a full turn."""
    full = stop - start >= 2 * math.pi - FULL_TURN_TOL
    return np.linspace(start, stop, n, endpoint=not full), full


def _output(kind: str, v: np.ndarray, phi: np.ndarray, full: bool) -> list[np.ndarray]:
    """Travel, φ of the least and greatest value, time ratio: four (V,) columns."""
    rows = v.shape[0]
    if kind == "rocker":
        v = np.unwrap(v, axis=1)
    lo, hi = np.argmin(v, axis=1), np.argmax(v, axis=1)
    take = np.arange(rows)
    travel = v[take, hi] - v[take, lo]
    ratio = np.full(rows, np.nan)
    if full:
        out = np.mod(phi[hi] - phi[lo], 2 * math.pi)
        with np.errstate(divide="ignore", invalid="ignore"):
            ratio = np.maximum(out, 2 * math.pi - out) / np.minimum(out, 2 * math.pi - out)
        if kind == "rocker":  # a link that turns fully round has no swing, no limits
            closing = np.remainder(v[:, 0] - v[:, -1] + math.pi, 2 * math.pi) - math.pi
            turns = np.abs(v[:, -1] - v[:, 0] + closing) > math.pi
            travel = np.where(turns, np.nan, travel)
            ratio = np.where(turns, np.nan, ratio)
            return [travel, np.where(turns, np.nan, phi[lo]), np.where(turns, np.nan, phi[hi]), ratio]
    return [travel, phi[lo], phi[hi], ratio]


def reduce(layout: Layout, phi: np.ndarray, full: bool, outputs: dict[str, np.ndarray], least_d: np.ndarray,
           torque: np.ndarray, reactions: dict[str, np.ndarray], inertia: np.ndarray) -> dict[str, np.ndarray]:
    """The metric columns (V,) of V variants from their values on the grid ``phi`` (N,):
    ``outputs`` name → rocker angle [rad] or slider displacement [m] (V, N); ``least_d`` the
    least |D| over the groups (V, N); ``torque`` the balancing torque [N·m] (V, N);
    ``reactions`` joint → |reaction| [N] (V, N); ``inertia`` J [kg·m²] (V, N)."""
    cols: list[np.ndarray] = []
    for name, kind in layout.outputs:
        cols += _output(kind, outputs[name], phi, full)
    cols.append(np.arcsin(np.clip(np.min(least_d, axis=1), 0.0, 1.0)))
    cols.append(np.max(np.abs(torque), axis=1))
    cols += [np.max(reactions[j], axis=1) for j in layout.joints]
    cols += [np.min(inertia, axis=1), np.max(inertia, axis=1)]
    return dict(zip(layout.columns, cols))


__all__ = ["ANGLES", "Layout", "angles", "reduce"]
