"""linkgen: planar linkages → MuJoCo MJCF, cross-checked against closed-form Assur-group solutions."""

from linkgen.planar.assembly import Assembly, assemble
from linkgen.model.description import (
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
from linkgen.planar.kinematics import Kinematics, solve, solve_motion
from linkgen.model.reader import from_dict, load
from linkgen.planar.motion import Motion
from linkgen.planar.structure import Group, GroupKind, Structure, analyze

__all__ = [
    "Drive", "Link", "LinkTorque", "MassProperties", "Mechanism", "PointForce", "Prismatic", "Revolute",
    "ArgumentError", "AssemblyError", "DescriptionError", "LinkgenError", "SimulationError", "SingularityError",
    "StructureError", "ValidationError", "BalanceError", "MagnitudeError", "Assembly", "Kinematics", "Motion", "assemble", "solve", "solve_motion",
    "from_dict", "load", "Group", "GroupKind", "Structure", "analyze",
]
