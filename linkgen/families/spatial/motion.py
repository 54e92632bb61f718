"""The closed form's answer for a spatial four-bar over its input values: ``SpatialMotion``."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from linkgen.families.spatial.chain import Chain
from linkgen.families.spatial.jets import Jet


@dataclass(frozen=True)
class SpatialMotion:
    """Positions and transfer functions over crank angles ``phi`` (n,) [rad].

    ``points[name]``: a vector Jet (4, n, 3) [m, m/rad, m/rad², m/rad³]; ``output``: a scalar
    Jet, the output's absolute angle about its axis [rad] or its travel from the sketch [m];
    ``turn``: the output's turn from its sketch (ψ or s) as a Jet; ``spin[link]``: the link's
    angular velocity and its derivative per unit crank rate, each (n, 3) [rad/rad, rad/rad²]
    (a coupler between two spherical pairs without spin about its own line); ``frames[link]``:
    rotation matrices (n, 3, 3) from the sketch pose; ``denominator``: normalised F_q (n,) (for
    Bennett, the closure's normalised denominator, see ``_bennett_turn``)."""

    chain: Chain
    phi: np.ndarray
    points: dict
    output: Jet
    turn: Jet
    spin: dict
    frames: dict
    denominator: np.ndarray
    own: dict = field(default_factory=dict)
    slides: dict = field(default_factory=dict)

    def at(self, link: str, point: str) -> Jet:
        """The point as ``link`` carries it: a cylindrical pair's point parts from the first
        link's (``points``) for the later link (``own``, RCCC)."""
        return self.own.get((link, point), self.points[point])

    def __repr__(self) -> str:
        return f"SpatialMotion({self.chain.kind}, {self.phi.shape[0]} angles, {len(self.points)} points)"


__all__ = ["SpatialMotion"]
