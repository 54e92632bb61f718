"""A prismatic pair's guide as every MJCF draws it: a bar along the slider's stroke.

The stroke's ends come from the family's closed form over the drive's range (the planar
``Positions.travel``, the spatial ``slide_travel``), the same that ``linkgen draw`` uses; the bar
runs beyond each end by half the slider's block, so the block stays on it, and by GUIDE_OVERHANG
of the block's length. Guides are drawings only (the writers' geoms collide with nothing).
"""

from __future__ import annotations

# Fractions of the mechanism's size: a guide's least half-length (a slider that hardly moves
# still shows its guide) and its half-thickness.
GUIDE_SIZE = (0.1, 0.004)
# How far a guide runs past the block at each end of the stroke, as a fraction of the block's length.
GUIDE_OVERHANG = 0.25


def guide_span(lo: float, hi: float, block_half: float, size: float) -> tuple[float, float]:
    """The guide's centre and half-length [m] along its line, for a slider whose point runs from
    ``lo`` to ``hi`` [m] on that line, with a block ``block_half`` [m] long on each side of its
    point, in a mechanism of size ``size`` [m]."""
    half = max(0.5 * (hi - lo) + (1.0 + 2.0 * GUIDE_OVERHANG) * block_half, GUIDE_SIZE[0] * size)
    return 0.5 * (lo + hi), half


__all__ = ["GUIDE_OVERHANG", "GUIDE_SIZE", "guide_span"]
