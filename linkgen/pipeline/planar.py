"""The planar linkage family (with cams and gears as higher pairs, and a ``[machine]`` table as
the machine layer over it): its description and its stages."""

from __future__ import annotations

from typing import Mapping

from linkgen.families.planar.description import Mechanism
from linkgen.pipeline.family import Family
from linkgen.pipeline.planar_mujoco import STAGES as MUJOCO_STAGES


def _from_dict(data: Mapping, source: str | None = None) -> Mechanism:
    from linkgen.errors import DescriptionError
    from linkgen.families.planar.reader import from_dict
    from linkgen.model.machine import machine_from_dict

    try:
        mech = from_dict(data)
        machine_from_dict(data)  # checked with the rest; linkgen.machine reads it
        return mech
    except DescriptionError as exc:
        raise (exc.in_file(source) if source else exc) from None


PLANAR = Family(
    name="planar", title="planar linkage", plural="planar linkages", doc="docs/format.md", description=Mechanism,
    detects=lambda data: True, from_dict=_from_dict,
    commands=("structure", "analyze", "forces", "assemble", "build", "simulate", "validate", "draw", "animate",
              "render", "dynamics", "flywheel"),
    stages={**MUJOCO_STAGES})

__all__ = ["PLANAR"]
