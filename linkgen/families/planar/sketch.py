"""The exactly assembled sketch: the description's link lengths and guides, assembled by the
closed form at the sketch's crank angle (or another), the rough sketch only choosing each
group's assembly mode."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from linkgen.families.planar.description import GROUND, Mechanism
from linkgen.families.planar.assembly import assemble
from linkgen.families.planar.kinematics import solve

# A point already this close to its exact place (fraction of the sketch's size: a few roundings)
# keeps its coordinates as the user wrote them.
KEEP = 1e-12


@dataclass(frozen=True)
class Sketch:
    """Exact point coordinates [m] at crank angle ``phi`` [rad], and how far each moved from
    the given sketch [m] (ground points are exact already and do not move; a point within
    KEEP of the sketch's size keeps the coordinates as written)."""

    phi: float
    points: dict[str, tuple[float, float]]
    moved: dict[str, float]


def exact_sketch(mech: Mechanism, phi: float | None = None) -> Sketch:
    """Assemble ``mech`` from its lengths at crank angle φ [rad] (default: the sketch's own)."""
    asm = assemble(mech, sketch_tolerance=None)
    at = asm.sketch_phi if phi is None else float(phi)
    kin = solve(asm, np.array([at]))
    ground = set(mech.link(GROUND).points)
    xy_all = np.array(list(mech.points.values()))
    size = float(np.hypot(*np.ptp(xy_all, axis=0)))
    points, moved = {}, {}
    for name, xy in mech.points.items():
        new = tuple(map(float, xy)) if name in ground else tuple(map(float, kin.points[name].p[0]))
        d = float(np.hypot(new[0] - xy[0], new[1] - xy[1]))
        points[name], moved[name] = (new, d) if d > KEEP * size else (tuple(map(float, xy)), 0.0)
    return Sketch(at, points, moved)


__all__ = ["Sketch", "exact_sketch"]
