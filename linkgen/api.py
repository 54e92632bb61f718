"""The Python API, one function per CLI command, each taking any description ``linkgen.load``
returns (a planar ``Mechanism`` or an assembled one, a ``CamMechanism``, a ``SpatialMechanism``)
and returning its family's frozen result, through the registry of families:

    mech = linkgen.load("models/fourbar.toml")
    k = linkgen.kinematics(mech, "30deg")        # k.points["B"].position has shape (2,)
    f = linkgen.forces(mech, np.linspace(0, 1, 50), omega="120rpm")
    f.reactions["B"].force                       # (50, 2) [N]; JSON reactions.B.force, CSV B.force.x
    f.columns()                                  # {"phi [rad]": (50,), "balancing_torque [N·m]": …}
    linkgen.summary(mech).text(); linkgen.write_mjcf(mech); linkgen.validate(mech).ok

Angles and rates: SI numbers (rad, rad/s, rad/s²) or strings with their unit as the CLI takes
them ("30deg", "0.5rad", "120rpm", "10rad/s", "60rpm/s"), or arrays/lists of them; a bad one
raises ArgumentError naming the argument, the value and what is allowed. A scalar φ gives
scalar-shaped results (a point (2,), an angle a float); an array φ (n,) gives (n, 2) and (n,).
``to_dict()`` gives JSON-ready nested dicts with the same keys as the attributes, ``columns()``
flat "name.quantity[.x|.y] [unit]" → 1-D array columns (pandas-ready), ``text()`` what the CLI
prints.
"""

from __future__ import annotations

from linkgen.families.planar.assembly import Assembly, assemble
from linkgen.families.planar.description import Mechanism
from linkgen.families.planar.forces_result import PlanarForces
from linkgen.families.planar.motion_result import PlanarKinematics
from linkgen.model.arguments import angle_argument, rate_argument

# The planar results under their former names.
KinematicsResult = PlanarKinematics
ForcesResult = PlanarForces


def _stage(source, name: str):
    from linkgen.pipeline.registry import stage

    return stage(source, name)


def structure(source):
    """Mobility, the Assur groups (or the spatial chain) and the structure formula
    (``linkgen structure``): the family's structure result."""
    return _stage(source, "structure")(source)


def kinematics(source, phi, omega=None, epsilon=None):
    """Positions, velocities, accelerations, jerks and transfer functions at drive angles φ
    (scalar or (n,); rad or "30deg"), speed ω [rad/s or "120rpm"] and acceleration ε [rad/s² or
    "60rpm/s"] (default the description's; the jerk takes ε constant in time: x‴ω³ + 3x″ωε)."""
    return _stage(source, "kinematics")(source, angle_argument(phi, "phi"), rate_argument(omega, "omega", "rad/s"),
                                        rate_argument(epsilon, "epsilon", "rad/s²"))


def forces(source, phi, omega=None, epsilon=None):
    """Kinetostatics (``linkgen forces``) at drive angles φ, speed ω, acceleration ε (as
    ``kinematics``)."""
    return _stage(source, "forces")(source, angle_argument(phi, "phi"), rate_argument(omega, "omega", "rad/s"),
                                    rate_argument(epsilon, "epsilon", "rad/s²"))


def summary(source, omega=None, epsilon=None):
    """The design summary over the drive range (``linkgen analyze --summary``): strokes or
    swings, limit positions, time ratio, extreme transmission or pressure angles, peak loads."""
    return _stage(source, "summary")(source, rate_argument(omega, "omega", "rad/s"),
                                     rate_argument(epsilon, "epsilon", "rad/s²"))


def _spatial(source) -> bool:
    from linkgen.families.spatial.description import SpatialMechanism

    return isinstance(source, SpatialMechanism)


def _assembly(source: Mechanism | Assembly) -> Assembly:
    return source if isinstance(source, Assembly) else assemble(source)


def write_mjcf(source: Mechanism | Assembly, settings=None) -> str:
    """The MJCF text (``linkgen build``); any structure class."""
    if _spatial(source):
        from linkgen.mujoco.spatial_mjcf import write_spatial_mjcf

        return write_spatial_mjcf(source, settings)
    from linkgen.errors import StructureError
    from linkgen.mujoco.mjcf import write_mjcf as _write

    if isinstance(source, Mechanism):
        try:
            source = assemble(source)
        except StructureError:  # class III and higher: MuJoCo needs no Assur groups
            pass
    return _write(source, settings)


def simulate(source: Mechanism | Assembly, **options):
    """A MuJoCo run over the drive range (``linkgen simulate``); options as
    ``linkgen.mujoco.simulate.simulate``."""
    from linkgen.mujoco.simulate import simulate as _simulate, simulate_mechanism

    if isinstance(source, Mechanism):
        return simulate_mechanism(source, **options)
    return _simulate(source, **options)


def validate(source: Mechanism | Assembly, **options):
    """MuJoCo against the closed form (``linkgen validate``): a ``CrossCheck`` with ``.ok``,
    ``.to_json()`` and the diagnosis; options as ``linkgen.crosscheck.run.crosscheck``."""
    if _spatial(source):  # a SpatialCheck (linkgen.crosscheck.spatial)
        from linkgen.crosscheck.spatial import check_spatial

        return check_spatial(source, **options)
    asm = _assembly(source)
    if asm.mechanism.cams:  # contact in MuJoCo: a CamLinkageCheck (linkgen.mujoco.cam_linkage)
        from linkgen.mujoco.cam_linkage import check_cam_linkage

        return check_cam_linkage(asm)
    from linkgen.crosscheck.run import crosscheck

    return crosscheck(asm, **options)


__all__ = ["ForcesResult", "KinematicsResult", "forces", "kinematics", "simulate", "structure", "summary",
           "validate", "write_mjcf"]
