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


def _angles(desc, samples: int | None = None):
    """The default cam angle (0), or ``samples`` cam angles over one turn (its end excluded)."""
    import math

    import numpy as np

    return 0.0 if samples is None else np.linspace(0.0, 2 * math.pi, samples, endpoint=False)


def _kinematics(desc, phi, omega=None, epsilon=None, *, on_singular: str = "raise"):
    from linkgen.families.cam.results import kinematics

    return kinematics(desc, phi, omega, epsilon, on_singular=on_singular)


def _summary(desc, omega=None, epsilon=None):
    from linkgen.families.cam.results import summary

    return summary(desc, omega, epsilon)


def _profile(desc, points: int = 720):
    from linkgen.families.cam.results import profile

    return profile(desc, points)


CAM = Family(
    name="cam", title="stand-alone cam", plural="stand-alone cams", doc="docs/cams.md", description=CamMechanism,
    detects=is_cam_data, from_dict=_from_dict,
    commands=("analyze", "profile", "build", "validate", "draw", "page", "animate", "render"),
    stages={"angles": _angles, "kinematics": _kinematics, "summary": _summary, "profile": _profile, **MUJOCO_STAGES})

__all__ = ["CAM"]
