"""Where a planar linkage assembles over one turn of its crank (``linkgen.model.turn``, the
same scan and bisection as for spatial four-bars): the status of every Assur group at once,
from the block solver's own failure and dead-centre masks."""

from __future__ import annotations

import numpy as np

from linkgen.model.turn import TurnAssembly, turn_assembly
from linkgen.planar.assembly import Assembly


def status(asm: Assembly):
    """Crank angles (n,) [rad] → (fails, singular) masks: some group cannot be assembled; all
    are, but one is at or too near a dead centre (``SINGULAR_TOL``) or its values overflow."""
    from linkgen.planar.kinematics import solve_block

    def at(phi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        report: list = []
        with np.errstate(all="ignore"):  # failures come back as masks, not warnings
            solve_block(asm, np.asarray(phi, dtype=float), True, report)
        fails = np.zeros(phi.shape[0], dtype=bool)
        rough = np.zeros(phi.shape[0], dtype=bool)
        for _, fail, overflow, singular in report:
            fails |= fail
            rough |= overflow | singular
        return fails, rough & ~fails

    return at


def planar_turn(asm: Assembly) -> TurnAssembly:
    """The linkage's assembly over the turn [0, 2π) of its crank."""
    return turn_assembly(status(asm))


__all__ = ["planar_turn", "status"]
