"""linkgen: mechanisms → MuJoCo MJCF, cross-checked against their closed form — planar linkages
(with cams and gears as higher pairs, and machines: motors, flywheel, elastic shaft) solved by
their Assur groups, stand-alone cams, spatial four-bars.

    import linkgen
    mech = linkgen.load("models/fourbar.toml")
    linkgen.kinematics(mech, 0.5).points["B"].velocity      # (2,) [m/s]
    linkgen.forces(mech, 0.5).balancing_torque              # [N·m]
    linkgen.validate(mech).ok                               # MuJoCo against the closed form

``load`` opens every family's description; ``structure``, ``kinematics``, ``forces``, ``summary``,
``profile``, ``write_mjcf``, ``simulate`` and ``validate`` take any of them (``linkgen.api``).
``referee`` judges a solver's results against them (docs/referee.md).
``assemble``, ``decompose``, ``solve``, ``solve_motion`` and the description types are the planar
family's own (another family is refused with UnsupportedError).
"""

from linkgen.families.planar.assembly import Assembly
from linkgen.families.planar.description import (
    Drive,
    Link,
    LinkTorque,
    MassProperties,
    Mechanism,
    PointForce,
    Prismatic,
    Revolute,
)
from linkgen.errors import (
    ArgumentError,
    AssemblyError,
    BalanceError,
    CouplingError,
    DescriptionError,
    FrictionError,
    LinkgenError,
    MagnitudeError,
    RenderError,
    SimulationError,
    SingularityError,
    StructureError,
    UnsupportedError,
    ValidationError,
)
from linkgen.families.planar.kinematics import Kinematics
from linkgen.pipeline.registry import from_dict, load
from linkgen.families.planar.motion import Motion
from linkgen.families.planar.structure import Group, GroupKind, Structure
from linkgen.api import (ForcesResult, KinematicsResult, assemble, decompose, forces, kinematics, profile, referee,
                         simulate, solve, solve_motion, structure, summary, validate, write_mjcf)

__all__ = [
    "Drive", "Link", "LinkTorque", "MassProperties", "Mechanism", "PointForce", "Prismatic", "Revolute",
    "ArgumentError", "AssemblyError", "DescriptionError", "LinkgenError", "SimulationError", "SingularityError",
    "StructureError", "UnsupportedError", "ValidationError", "BalanceError", "FrictionError", "MagnitudeError", "RenderError",
    "CouplingError",
    "Assembly", "Kinematics", "Motion", "assemble", "solve", "solve_motion", "from_dict", "load", "Group", "GroupKind",
    "Structure", "decompose",
    "ForcesResult", "KinematicsResult", "forces", "kinematics", "profile", "simulate", "structure", "summary",
    "validate", "write_mjcf", "referee",
]

# Names the top level no longer has, and what took their place.
_RENAMED = {"analyze": "linkgen.analyze is now linkgen.decompose (a planar linkage's Assur groups); the CLI's "
                       "`linkgen analyze` is linkgen.kinematics (and linkgen.summary for --summary)"}


def __getattr__(name: str):
    if name in _RENAMED:
        raise AttributeError(_RENAMED[name])
    raise AttributeError(f"module 'linkgen' has no attribute {name!r}")
