"""linkgen: planar linkages → MuJoCo MJCF, cross-checked against closed-form Assur-group solutions.

    import linkgen
    mech = linkgen.load("models/fourbar.toml")
    linkgen.kinematics(mech, 0.5).points["B"].velocity      # (2,) [m/s]
    linkgen.forces(mech, 0.5).balancing_torque              # [N·m]
    linkgen.validate(mech).ok                               # MuJoCo against the closed form
"""

from linkgen.families.planar.assembly import Assembly, assemble
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
    DescriptionError,
    LinkgenError,
    MagnitudeError,
    SimulationError,
    SingularityError,
    StructureError,
    ValidationError,
)
from linkgen.families.planar.kinematics import Kinematics, solve, solve_motion
from linkgen.pipeline.registry import from_dict, load
from linkgen.families.planar.motion import Motion
from linkgen.families.planar.structure import Group, GroupKind, Structure, analyze
from linkgen.api import (ForcesResult, KinematicsResult, forces, kinematics, simulate, structure, summary, validate,
                         write_mjcf)

__all__ = [
    "Drive", "Link", "LinkTorque", "MassProperties", "Mechanism", "PointForce", "Prismatic", "Revolute",
    "ArgumentError", "AssemblyError", "DescriptionError", "LinkgenError", "SimulationError", "SingularityError",
    "StructureError", "ValidationError", "BalanceError", "MagnitudeError", "Assembly", "Kinematics", "Motion", "assemble", "solve", "solve_motion",
    "from_dict", "load", "Group", "GroupKind", "Structure", "analyze",
    "ForcesResult", "KinematicsResult", "forces", "kinematics", "simulate", "structure", "summary", "validate",
    "write_mjcf",
]
