"""The spatial four-bar family (``[mechanism] space = "spatial"``): its description and its
stages."""

from __future__ import annotations

from linkgen.families.spatial.description import SpatialMechanism, is_spatial, spatial_from_dict
from linkgen.pipeline.family import Family
from linkgen.pipeline.spatial_mujoco import STAGES as MUJOCO_STAGES

SPATIAL = Family(
    name="spatial", title="spatial four-bar", plural="spatial four-bars", doc="docs/spatial.md", description=SpatialMechanism,
    detects=is_spatial, from_dict=spatial_from_dict,
    commands=("structure", "analyze", "forces", "build", "validate", "draw", "animate", "render"),
    stages={**MUJOCO_STAGES})

__all__ = ["SPATIAL"]
