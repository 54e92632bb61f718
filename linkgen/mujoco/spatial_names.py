"""Names and a length of the MJCF of an RCCC (``spatial_mjcf``), shared with its joint states
(``spatial_state``) and the validation (``crosscheck.spatial``): a cylindrical pair's slide joint,
the output's half that closes the loop by a weld, and the weld's lever."""

from __future__ import annotations

import numpy as np

from linkgen.families.spatial.chain import Chain
from linkgen.families.spatial.description import SpatialMechanism


def slide_joint(pair: str) -> str:
    """The slide joint of a cylindrical pair (its hinge takes the pair's own name)."""
    return f"{pair}:slide"


def weld_lever(mech: SpatialMechanism, chain: Chain) -> float:
    """The farthest point of an RCCC's output from the weld's anchor (the output's origin B0)
    [m]: a turn ε across the weld parts the two halves' copies of the output's points by up
    to ε times this."""
    return max(float(np.linalg.norm(mech.point(p) - chain.b0)) for p in mech.link(chain.output).points
               if p != chain.pair_b) if chain.kind == "RCCC" else 0.0


def closing_body(chain: Chain) -> str:
    """The RCCC output's half carried by the coupler on B's pair, welded to the other half (the
    weld takes its name too)."""
    return f"{chain.output}:{chain.pair_b}"

__all__ = ["closing_body", "slide_joint", "weld_lever"]
