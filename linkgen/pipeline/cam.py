"""The stand-alone cam family (a disc cam and its follower; ``[cam]`` without ``[links]``): its
description and its stages."""

from __future__ import annotations

from typing import Mapping

from linkgen.families.cam.description import CamMechanism, is_cam_data
from linkgen.pipeline.family import Family
from linkgen.pipeline.cam_mujoco import STAGES as MUJOCO_STAGES


def _from_dict(data: Mapping, source: str | None = None) -> CamMechanism:
    from linkgen.errors import DescriptionError
    from linkgen.families.cam.description import cam_from_dict

    try:
        return cam_from_dict(data)
    except DescriptionError as exc:
        raise (exc.in_file(source) if source else exc) from None


CAM = Family(
    name="cam", title="stand-alone cam", plural="stand-alone cams", doc="docs/cams.md", description=CamMechanism,
    detects=is_cam_data, from_dict=_from_dict,
    commands=("analyze", "profile", "build", "validate", "draw", "animate", "render"),
    stages={**MUJOCO_STAGES})

__all__ = ["CAM"]
