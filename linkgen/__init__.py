"""linkgen: planar linkages → MuJoCo MJCF, cross-checked against closed-form Assur-group solutions."""

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
    AssemblyError,
    DescriptionError,
    LinkgenError,
    SimulationError,
    SingularityError,
    StructureError,
    ValidationError,
)
from .kinematics import Assembly, Kinematics, Motion, assemble, solve
from .load import from_dict, load
from .structure import Group, GroupKind, Structure, analyze

__all__ = [
    "Drive", "Link", "LinkTorque", "MassProperties", "Mechanism", "PointForce", "Prismatic", "Revolute",
    "AssemblyError", "DescriptionError", "LinkgenError", "SimulationError", "SingularityError",
    "StructureError", "ValidationError", "Assembly", "Kinematics", "Motion", "assemble", "solve",
    "from_dict", "load", "Group", "GroupKind", "Structure", "analyze",
]
