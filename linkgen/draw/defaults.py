"""The angle a single picture shows when none is given: a pose a student reads without doubt — no
group nearly in line, the crank not in line with a link on its pin, no output at a limit position
(where the velocities vanish and points stack on one line)."""

from __future__ import annotations

import math

import numpy as np

from linkgen.families.planar.description import GROUND


def default_angle(mech) -> float:
    """The angle a single drawing shows by default: the first crank angle of the range, in steps
    of DEFAULT_STEP_DEG, where no group is nearly in line (transmission angle ≥
    DEFAULT_LEAST_GAMMA_DEG), the crank is not in line with a link on its pin (a dead centre,
    where points stack on one line) and every point off the crank moves at DEFAULT_MOVING of its
    top speed or more (no output at a limit position, where its velocity vanishes); without the
    last where no angle meets all three; the range's start if none meets the first two."""
    from linkgen.families.planar.assembly import assemble
    from linkgen.families.planar.positions import positions
    from linkgen.families.planar.summary import transmission_angles

    from linkgen.errors import StructureError

    d = mech.drive
    try:
        asm = assemble(mech)
    except StructureError:  # a group of class III or higher: no closed form to look at
        return d.start
    grid = np.arange(d.start, d.stop + 1e-12, math.radians(DEFAULT_STEP_DEG))
    ok = np.ones(grid.shape, bool)
    for g in transmission_angles(asm, grid).values():
        ok &= g >= math.radians(DEFAULT_LEAST_GAMMA_DEG)
    pos = positions(mech, grid)
    pivot, pin = mech.link(mech.crank).points[:2] if len(mech.link(mech.crank).points) > 1 else (None, None)
    if pin is not None:
        u = pos.points[pin] - pos.points[pivot]
        for link in mech.links:
            if link.name in (GROUND, mech.crank) or pin not in link.points:
                continue
            for q in link.points:
                if q != pin:
                    v = pos.points[q] - pos.points[pin]
                    sin = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) / np.maximum(
                        np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1), 1e-300)
                    ok &= sin >= math.sin(math.radians(DEFAULT_LEAST_GAMMA_DEG))
    from linkgen.families.planar.kinematics import solve_motion

    moving = np.ones(grid.shape, bool)  # and no point off the crank near a limit position (at rest)
    mo = solve_motion(asm, grid, 1.0, 0.0, on_singular="mark")
    crank_points = set(mech.link(mech.crank).points) | set(mech.link(GROUND).points)
    for name, (_, v, _) in mo.points.items():
        if name not in crank_points:
            speed = np.linalg.norm(v, axis=1)
            moving &= speed >= DEFAULT_MOVING * float(speed.max())
    pick = np.flatnonzero(ok & moving)
    if not pick.size:
        pick = np.flatnonzero(ok)
    return float(grid[pick[0]]) if pick.size else d.start


# A default drawing avoids poses with a group nearly in line: transmission angle at least this,
# looked for on this grid of crank angles from the range's start.
DEFAULT_LEAST_GAMMA_DEG = 30.0
DEFAULT_STEP_DEG = 15.0
DEFAULT_MOVING = 0.2

__all__ = ["default_angle"]
