"""The Python API. Its way in, for every family: one function for each CLI command that
computes a result (the command in brackets): ``structure`` (structure), ``kinematics``
(analyze), ``forces`` (forces), ``summary`` (analyze --summary), ``profile`` (profile),
``write_mjcf`` (build), ``simulate`` (simulate), ``validate`` (validate). Each takes any
description ``linkgen.load`` returns (a planar ``Mechanism`` or an assembled one, a
``CamMechanism``, a ``SpatialMechanism``), calls its family's stage of that name
(``linkgen.pipeline.family.STAGES``; ``write_mjcf`` the ``mjcf`` stage) through the registry and
returns its frozen result; a family without the stage is refused with UnsupportedError in one
line. ``referee`` (``linkgen referee``) judges a solver's table of results against them. The commands that draw (draw, animate, render), place a sketch (assemble) or study a
machine (dynamics, flywheel) are the CLI's only.

    mech = linkgen.load("models/fourbar.toml")
    k = linkgen.kinematics(mech, "30deg")        # k.points["B"].position has shape (2,)
    f = linkgen.forces(mech, np.linspace(0, 1, 50), omega="120rpm")
    f.reactions["B"].force                       # (50, 2) [N]; JSON reactions.B.force, CSV B.force.x
    f.columns()                                  # {"phi [rad]": (50,), "balancing_torque [N·m]": …}
    linkgen.summary(mech).text(); linkgen.write_mjcf(mech); linkgen.validate(mech).ok

Arguments, one rule for every family: a drive angle φ is a number in rad or a string with its
unit ("30deg", "0.5rad"), or a non-empty 1-D array/list of them; the speed ω and the
acceleration ε are one value each for the whole call (a number in rad/s, rad/s², or a string:
"120rpm", "10rad/s", "60rpm/s"; None: the description's drive). A bad one raises ArgumentError
naming the argument, the value and what is allowed; so does an option a stage does not take
(naming the ones it takes). A scalar φ gives scalar-shaped results (a point (2,), an angle a
float); an array φ (n,) gives (n, 2) and (n,). ``to_dict()`` gives JSON-ready nested dicts with
the same keys as the attributes, ``columns()`` flat "name.quantity[.x|.y] [unit]" → 1-D array
columns (pandas-ready), ``text()`` what the CLI prints.

The planar family's own closed form is exported too, for planar linkages only (another family
is refused in one line): ``assemble``, ``decompose`` (the Assur groups), ``solve`` (positions
and transfer functions), ``solve_motion`` (positions to jerks); angles and rates as above, and
``solve_motion`` also takes ω, ε per angle (arrays (n,)).
"""

from __future__ import annotations

import inspect

import numpy as np

from linkgen.errors import ArgumentError
from linkgen.families.planar.assembly import SKETCH_TOLERANCE, Assembly
from linkgen.families.planar.forces_result import PlanarForces
from linkgen.families.planar.motion_result import PlanarKinematics
from linkgen.model.arguments import angle_argument, one_rate, rate_argument

# The planar results under their former names.
KinematicsResult = PlanarKinematics
ForcesResult = PlanarForces

# The API's functions of every family → the stage each calls.
FUNCTIONS = {"structure": "structure", "kinematics": "kinematics", "forces": "forces", "summary": "summary",
             "profile": "profile", "write_mjcf": "mjcf", "simulate": "simulate", "validate": "validate"}


def _stage(source, name: str):
    """The stage ``name`` of the family of ``source`` (any description ``linkgen.load`` returns,
    or an assembled planar mechanism); UnsupportedError names the families that have it."""
    from linkgen.pipeline.registry import stage

    return stage(source, name)


def _rates(omega, epsilon) -> tuple:
    return one_rate(omega, "omega", "rad/s"), one_rate(epsilon, "epsilon", "rad/s²")


def _with_options(source, name: str, options: dict):
    """The stage ``name`` of the source's family, once every key of ``options`` is one of the
    stage's options (the same in every family: ``pipeline.family.STAGES``)."""
    fn = _stage(source, name)
    allowed = [p.name for p in list(inspect.signature(fn).parameters.values())[1:]
               if p.kind in (p.KEYWORD_ONLY, p.POSITIONAL_OR_KEYWORD)]
    unknown = [k for k in options if k not in allowed]
    if unknown:
        raise ArgumentError(f"{unknown[0]}: not an option of linkgen.{name}; its options are {', '.join(allowed)}")
    return fn


def structure(source):
    """Mobility, the Assur groups (or the spatial chain) and the structure formula
    (``linkgen structure``): the family's structure result."""
    return _stage(source, "structure")(source)


def kinematics(source, phi, omega=None, epsilon=None, *, on_singular: str = "raise"):
    """Positions, velocities, accelerations, jerks and transfer functions (``linkgen analyze``)
    at drive angles φ (a number or a non-empty (n,); rad or "30deg"), one speed ω [rad/s or
    "120rpm"] and one acceleration ε [rad/s² or "60rpm/s"] (default the description's; the jerk
    takes ε constant in time: x‴ω³ + 3x″ωε). ``on_singular="mark"`` marks the samples at a
    singular position (``singular``) instead of raising SingularityError."""
    fn = _stage(source, "kinematics")
    return fn(source, angle_argument(phi, "phi"), *_rates(omega, epsilon), on_singular=_singular(on_singular))


def forces(source, phi, omega=None, epsilon=None, *, on_singular: str = "raise"):
    """Kinetostatics (``linkgen forces``) at drive angles φ, speed ω, acceleration ε and
    ``on_singular`` (as ``kinematics``)."""
    fn = _stage(source, "forces")
    return fn(source, angle_argument(phi, "phi"), *_rates(omega, epsilon), on_singular=_singular(on_singular))


def _singular(value) -> str:
    if value not in ("raise", "mark"):
        raise ArgumentError(f"on_singular: expected \"raise\" or \"mark\", got {value!r}")
    return value


def summary(source, omega=None, epsilon=None):
    """The design summary over the drive range (``linkgen analyze --summary``) at one speed ω and
    acceleration ε (as ``kinematics``): strokes or swings, limit positions, time ratio, extreme
    transmission or pressure angles, peak loads."""
    fn = _stage(source, "summary")
    return fn(source, *_rates(omega, epsilon))


def profile(source, points: int = 720):
    """A stand-alone cam's profile and pitch curve at ``points`` cam angles over one turn
    (``linkgen profile``)."""
    from linkgen.model.limits import MAX_SAMPLES

    fn = _stage(source, "profile")
    if isinstance(points, bool) or not isinstance(points, (int, np.integer)) or not 1 <= points <= MAX_SAMPLES:
        raise ArgumentError(f"points: expected a whole number from 1 to {MAX_SAMPLES} (as `linkgen profile "
                            f"--points`), got {points!r}")
    return fn(source, int(points))


def write_mjcf(source, settings=None, robot=None) -> str:
    """The MJCF text (``linkgen build``) of any description: a planar linkage of any structure
    class, a stand-alone cam or a spatial four-bar; ``settings`` a
    ``linkgen.mujoco.options.Settings`` (None: derived from the mechanism, as ``validate`` runs
    it; a stand-alone cam carries its own); ``robot`` a ``linkgen.mujoco.robot.RobotOptions``:
    the robot-ready model (``build --robot``) of a linkage or a spatial four-bar."""
    fn = _stage(source, "mjcf")
    if settings is not None:
        from linkgen.mujoco.options import Settings

        if not isinstance(settings, Settings):
            raise ArgumentError(f"settings: expected None (derived from the mechanism) or a "
                                f"linkgen.mujoco.options.Settings, got {settings!r} ({type(settings).__name__})")
    if robot is None:
        return fn(source, settings)
    from linkgen.mujoco.robot import RobotOptions

    if not isinstance(robot, RobotOptions):
        raise ArgumentError(f"robot: expected None or a linkgen.mujoco.robot.RobotOptions, got {robot!r}")
    return fn(source, settings, robot=robot)


def _counts(options: dict) -> dict:
    """``options`` with ω and ε read as everywhere in the API and the counts and sizes checked:
    whole numbers ≥ 1 (samples at most the CLI's --samples), revolutions a positive number."""
    from linkgen.model.limits import MAX_SAMPLES

    out = dict(options)
    for name, unit in (("omega", "rad/s"), ("epsilon", "rad/s²")):
        if name in out:
            out[name] = one_rate(out[name], name, unit)
    for name, high in (("samples", MAX_SAMPLES), ("nthread", None), ("max_steps", None)):
        v = out.get(name)
        if v is not None and (isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1
                              or (high is not None and v > high)):
            raise ArgumentError(f"{name}: expected a whole number from 1" + (f" to {high}" if high else "")
                                + f" (or None), got {v!r}")
    v = out.get("revolutions")
    if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float, np.integer, np.floating))
                          or not 0 < v < float("inf")):
        raise ArgumentError(f"revolutions: expected a positive number (or None), got {v!r}")
    return out


def simulate(source, /, **options):
    """A MuJoCo run over the drive range (``linkgen simulate``; planar linkages); options as the
    ``simulate`` stage (``pipeline.family.STAGES``): revolutions, omega and epsilon (one value
    each, as ``kinematics``), settings, samples, nthread, progress, max_steps, settle, notice —
    None or left out: the run's default."""
    fn = _with_options(source, "simulate", options)
    return fn(source, **_counts(options))


def validate(source, /, **options):
    """MuJoCo against the closed form (``linkgen validate``), for every family: a result with
    ``.ok``, ``.summary()`` (the line the CLI prints), ``.to_dict()`` (its JSON) and
    ``.diagnosis`` — a ``CrossCheck`` (``linkgen.crosscheck.run``), a ``CamLinkageCheck`` for a
    crank carrying a cam, a ``CamCheck`` (``linkgen.crosscheck.cam``) for a stand-alone cam, a
    ``SpatialCheck`` (``linkgen.crosscheck.spatial``) for a spatial four-bar. Options, the same
    in every family: practical, nthread, max_steps, progress, source, machine_progress (the
    ones that concern planar linkages only are ignored by the other families)."""
    fn = _with_options(source, "validate", options)
    return fn(source, **_counts(options))


def _planar(source, what: str) -> None:
    from linkgen.pipeline.registry import require

    require(source, "planar", f"linkgen.{what}", {f"linkgen.{k}": v for k, v in FUNCTIONS.items()})


def assemble(mech, *, sketch_tolerance: float | None = SKETCH_TOLERANCE) -> Assembly:
    """A planar linkage assembled: its structure, link shapes and each group's assembly mode
    from the sketch (``families.planar.assembly.assemble``)."""
    from linkgen.families.planar.assembly import assemble as run

    _planar(mech, "assemble")
    return run(mech, sketch_tolerance=sketch_tolerance)


def decompose(source):
    """A planar linkage's mobility and its decomposition into class-II Assur groups (a
    ``Structure``; ``families.planar.structure.analyze``). ``linkgen.structure`` gives the
    structure of every family as the CLI prints it."""
    from linkgen.families.planar.structure import analyze

    _planar(source, "decompose")
    return source.structure if isinstance(source, Assembly) else analyze(source)


def solve(source, phi, threads: int | None = None, *, on_singular: str = "raise"):
    """A planar linkage's positions and transfer functions at crank angles φ (as ``kinematics``)
    (``families.planar.kinematics.solve``)."""
    from linkgen.families.planar.kinematics import solve as run

    _planar(source, "solve")
    return run(source, angle_argument(phi, "phi"), threads, on_singular=on_singular)


def solve_motion(source, phi, omega, epsilon=0.0, threads: int | None = None, *, on_singular: str = "raise"):
    """A planar linkage's positions, velocities, accelerations and jerks at crank angles φ,
    speed ω and acceleration ε, each one value or one per angle (n,)
    (``families.planar.kinematics.solve_motion``)."""
    from linkgen.families.planar.kinematics import solve_motion as run

    _planar(source, "solve_motion")
    return run(source, angle_argument(phi, "phi"), rate_argument(omega, "omega", "rad/s"),
               rate_argument(epsilon, "epsilon", "rad/s²"), threads, on_singular=on_singular)


def referee(source, table, *, mapping=None, omega=None, epsilon=None, tolerance: float | None = None,
            mujoco: bool = False):
    """A solver's results against linkgen (``linkgen referee``, docs/referee.md): ``table`` is a
    CSV file, a dict of header → values or a data frame, headed as ``linkgen analyze``/``forces``
    write (``"phi [deg]"``, ``"B.position.x [mm]"``; ``mapping`` renames other headers); ω and ε
    as ``kinematics`` (default the description's); ``tolerance`` a fraction of each column's
    scale (default 1e-6); ``mujoco`` compares MuJoCo's forward and inverse routes too (planar
    linkages). Returns a ``linkgen.referee.verdict.Verdict``: ``ok``, ``columns`` (each with its
    errors, who it agrees with and its ``diagnosis``), ``to_dict()``, ``text()``."""
    from linkgen.referee.compare import DEFAULT_TOLERANCE, referee as run

    return run(source, table, mapping=mapping, omega=omega, epsilon=epsilon,
               tolerance=DEFAULT_TOLERANCE if tolerance is None else tolerance, mujoco=bool(mujoco))


__all__ = ["FUNCTIONS", "ForcesResult", "KinematicsResult", "assemble", "decompose", "forces", "kinematics", "profile",
           "referee", "simulate", "solve", "solve_motion", "structure", "summary", "validate", "write_mjcf"]
