"""linkgen: planar linkages → MuJoCo MJCF, cross-checked against closed-form Assur-group solutions."""

from .assembly import Assembly, assemble
from .description import (
    Drive,
    Link,
    LinkTorque,
    MassProperties,
    Mechanism,
    PointForce,
    Prismatic,
    Revolute,
)
from .errors import (
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
from .kinematics import Kinematics, solve, solve_motion
from .load import from_dict, load
from .motion import Motion
from .structure import Group, GroupKind, Structure, analyze

__all__ = [
    "Drive", "Link", "LinkTorque", "MassProperties", "Mechanism", "PointForce", "Prismatic", "Revolute",
    "ArgumentError", "AssemblyError", "DescriptionError", "LinkgenError", "SimulationError", "SingularityError",
    "StructureError", "ValidationError", "BalanceError", "MagnitudeError", "Assembly", "Kinematics", "Motion", "assemble", "solve", "solve_motion",
    "from_dict", "load", "Group", "GroupKind", "Structure", "analyze",
]
