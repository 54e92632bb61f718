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

from linkgen.families.planar.forces_result import PlanarForces
from linkgen.families.planar.motion_result import PlanarKinematics
from linkgen.model.arguments import angle_argument, rate_argument

# The planar results under their former names.
KinematicsResult = PlanarKinematics
ForcesResult = PlanarForces


def _stage(source, name: str):
    """The stage ``name`` of the family of ``source`` (any description ``linkgen.load`` returns,
    or an assembled planar mechanism); UnsupportedError names the families that have it."""
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


def write_mjcf(source, settings=None) -> str:
    """The MJCF text (``linkgen build``) of any description: a planar linkage of any structure
    class, a stand-alone cam or a spatial four-bar; ``settings`` (default: derived from the
    mechanism, as ``validate`` runs it)."""
    return _stage(source, "mjcf")(source, settings)


def simulate(source, **options):
    """A MuJoCo run over the drive range (``linkgen simulate``); options as
    ``linkgen.mujoco.simulate.simulate``."""
    return _stage(source, "simulate")(source, **options)


def validate(source, **options):
    """MuJoCo against the closed form (``linkgen validate``), for every family: a result with
    ``.ok``, ``.summary()`` (the line the CLI prints), ``.to_dict()`` (its JSON) and
    ``.diagnosis`` — a ``CrossCheck`` (``linkgen.crosscheck.run``; options as its ``crosscheck``),
    a ``CamLinkageCheck`` for a crank carrying a cam, a ``CamCheck`` (``linkgen.crosscheck.cam``)
    for a stand-alone cam, a ``SpatialCheck`` (``linkgen.crosscheck.spatial``) for a spatial
    four-bar."""
    return _stage(source, "validate")(source, **options)


__all__ = ["ForcesResult", "KinematicsResult", "forces", "kinematics", "simulate", "structure", "summary",
           "validate", "write_mjcf"]
