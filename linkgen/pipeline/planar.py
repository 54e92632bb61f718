"""The planar linkage family (with cams and gears as higher pairs, and a ``[machine]`` table as
the machine layer over it): its description and its stages."""

from __future__ import annotations

from typing import Mapping

from linkgen.model.turn import full_turn
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


def _angles(desc, samples: int | None = None):
    """The default crank angle (the drive range's start), or ``samples`` angles over the drive
    range (a full turn excludes its end)."""
    import numpy as np

    d = (desc.mechanism if hasattr(desc, "structure") else desc).drive
    if samples is None:
        return d.start
    full = full_turn(desc.mechanism if hasattr(desc, "structure") else desc)
    return np.linspace(d.start, d.stop, samples, endpoint=not full)


def _structure(desc):
    from linkgen.families.planar.texts import structure

    return structure(desc)


def _input(desc, phi):
    """``phi`` if its unit suits the drive (an angle for a crank, a length for a prismatic drive)."""
    from linkgen.model.arguments import input_kind

    return input_kind(phi, (desc.mechanism if hasattr(desc, "structure") else desc).slide_drive, "angle")


def _kinematics(desc, phi, omega=None, epsilon=None, *, on_singular: str = "raise"):
    from linkgen.families.planar.motion_result import kinematics

    return kinematics(desc, _input(desc, phi), omega, epsilon, on_singular=on_singular)


def _forces(desc, phi, omega=None, epsilon=None, *, on_singular: str = "raise"):
    from linkgen.families.planar.forces_result import forces

    return forces(desc, _input(desc, phi), omega, epsilon, on_singular=on_singular)


def _summary(desc, omega=None, epsilon=None):
    from linkgen.families.planar.assembly import Assembly, assemble
    from linkgen.families.planar.summary import summarize

    return summarize(desc if isinstance(desc, Assembly) else assemble(desc), omega, epsilon)


def _check_settings(desc, settings, *, tolerance: float = 1e-3, search: bool = True, progress=None):
    """``linkgen check-settings`` (``crosscheck.check_settings``): linkages the Assur groups
    cover, their loops closed by revolute joints."""
    from linkgen.crosscheck.check_settings import check_settings
    from linkgen.families.planar.assembly import Assembly, assemble

    asm = desc if isinstance(desc, Assembly) else assemble(desc)
    return check_settings(asm, settings, tolerance=tolerance, search=search, progress=progress)


PLANAR = Family(
    name="planar", title="planar linkage", plural="planar linkages", doc="docs/format.md", description=Mechanism,
    detects=lambda data: True, from_dict=_from_dict,
    commands=("structure", "analyze", "forces", "assemble", "build", "simulate", "validate", "check-settings", "draw", "page",
              "animate", "render", "dynamics", "flywheel", "sweep", "optimize"),
    stages={"angles": _angles, "structure": _structure, "kinematics": _kinematics, "forces": _forces,
            "summary": _summary, "check_settings": _check_settings, **MUJOCO_STAGES},
    options=("--transfer", "--keep-singular", "--practical", "--robot"))

__all__ = ["PLANAR"]
