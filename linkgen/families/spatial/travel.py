"""Where a spatial four-bar's points go over a turn of its crank, and how far its slider runs:
what the drawing traces and what the MJCF's guide spans (``linkgen.mujoco.guides``)."""

from __future__ import annotations

import contextlib

import numpy as np

from linkgen.errors import LinkgenError
from linkgen.families.spatial.chain import Chain
from linkgen.families.spatial.description import SpatialMechanism
from linkgen.families.spatial.kinematics import solve

# Crank angles of the turn traced: every 1° from 0 to 2π, both ends included (a prismatic
# input's range in as many steps).
TURN = 361


def full_turn(mech: SpatialMechanism, chain: Chain) -> dict[str, np.ndarray]:
    """Every point over a full revolution (a prismatic input: over its range), (TURN, 3) [m]: at
    once, else angle by angle with NaN where the chain cannot be assembled."""
    phi, gap = np.linspace(*chain.input_range, TURN), {p: np.full((1, 3), np.nan) for p in mech.points}

    def at(part):
        with contextlib.suppress(LinkgenError):
            return {p: j.d[0] for p, j in solve(mech, phi[part], chain).points.items()}
    parts = [whole] if (whole := at(slice(None))) else [at(slice(i, i + 1)) or gap for i in range(TURN)]
    return {p: np.concatenate([q[p] for q in parts]) for p in mech.points}


def slide_displacement(mech: SpatialMechanism, turn: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
    """Each prismatic pair's slider point along its line from the point's sketch position [m],
    (TURN,) (NaN where the chain cannot be assembled), over ``full_turn``'s positions."""
    return {sl.name: (turn[sl.point] - mech.point(sl.point)) @ np.array(sl.direction) for sl in mech.slides}


def slide_travel(mech: SpatialMechanism, turn: dict[str, np.ndarray]) -> dict[str, tuple[float, float]]:
    """The least and greatest of ``slide_displacement`` [m]: the stroke's ends on each slider's line."""
    return {k: (float(np.nanmin(t)), float(np.nanmax(t))) for k, t in slide_displacement(mech, turn).items()}


__all__ = ["TURN", "full_turn", "slide_displacement", "slide_travel"]
