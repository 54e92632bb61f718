"""The spatial four-bar family (``[mechanism] space = "spatial"``): its description and its
stages."""

from __future__ import annotations

from linkgen.families.spatial.description import SpatialMechanism, is_spatial, spatial_from_dict
from linkgen.pipeline.family import Family
from linkgen.pipeline.spatial_mujoco import STAGES as MUJOCO_STAGES

def _angles(desc, samples: int | None = None):
    """The default crank angle (0), or ``samples`` angles over one turn (its end excluded); for
    a prismatic input the range's start, or ``samples`` displacements over it (both ends)."""
    import math

    import numpy as np

    if desc.drive.slides:
        lo, hi = desc.drive.range
        return lo if samples is None else np.linspace(lo, hi, samples)
    return 0.0 if samples is None else np.linspace(0.0, 2 * math.pi, samples, endpoint=False)


def _structure(desc):
    from linkgen.families.spatial.texts import structure

    return structure(desc)


def _within_range(desc, phi) -> None:
    """A slider input's values [m] must lie in its [drive] range (where the chain is known to
    assemble): else an ArgumentError naming the range."""
    import numpy as np

    from linkgen.errors import ArgumentError

    if not desc.drive.slides:
        return
    lo, hi = desc.drive.range
    x = np.atleast_1d(np.asarray(phi, dtype=float))
    out = x[(x < lo) | (x > hi)]
    if out.size:
        raise ArgumentError(f"{desc.name}'s input is a slider: its displacement {float(out[0]):.6g} (the number given, "
                            f"in metres) is outside its [drive] range {lo:.6g}..{hi:.6g} m")


def _kinematics(desc, phi, omega=None, epsilon=None, *, on_singular: str = "raise"):
    from linkgen.families.spatial.results import kinematics

    _within_range(desc, phi)
    return kinematics(desc, phi, omega, epsilon, on_singular=on_singular)


def _forces(desc, phi, omega=None, epsilon=None, *, on_singular: str = "raise"):
    from linkgen.families.spatial.results import forces

    _within_range(desc, phi)
    return forces(desc, phi, omega, epsilon, on_singular=on_singular)


def _summary(desc, omega=None, epsilon=None):
    from linkgen.families.spatial.summary import summary

    return summary(desc, omega, epsilon)


SPATIAL = Family(
    name="spatial", title="spatial four-bar", plural="spatial four-bars", doc="docs/spatial.md", description=SpatialMechanism,
    detects=is_spatial, from_dict=spatial_from_dict,
    commands=("structure", "analyze", "forces", "build", "validate", "draw", "page", "animate", "render"),
    stages={"angles": _angles, "structure": _structure, "kinematics": _kinematics, "forces": _forces,
            "summary": _summary, **MUJOCO_STAGES},
    options=("--transfer", "--robot"))

__all__ = ["SPATIAL"]
