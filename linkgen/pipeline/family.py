"""What every mechanism family implements (``Family``), and the one-line refusal of a command a
family does not take.

A family's stages take its validated description first and return frozen results with the same
protocol in every family: ``to_dict()`` (JSON, SI units, the same keys as the attributes),
``columns()`` (CSV: "name.quantity[.x|.y|.z] [unit]" → 1-D arrays) where there are samples, and
``text()`` for the terminal. A stage a family does not have is missing from its ``stages``; the
CLI and the API refuse it in one line naming the families that do have it
(``registry.stage``)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Mapping


@dataclass(frozen=True)
class Family:
    """One mechanism family.

    name:        "planar", "cam" or "spatial": the registry's key and JSON's ``family``.
    title:       what the user reads ("planar linkage"), and ``plural`` ("planar linkages").
    doc:         where its description format is documented.
    description: the type ``from_dict`` returns (a frozen dataclass with ``name``).
    detects:     True for the parsed TOML of one of its descriptions (the registry asks the
                 families in order; the last one, planar, takes every other file).
    from_dict:   (parsed TOML, source or None) → validated description; DescriptionError names
                 the field, and the file when a source is given.
    commands:    the CLI commands it takes, in the order help lists them.
    options:     the command-line options only some families take (``FAMILY_OPTIONS``) that
                 this one takes; the CLI refuses the others naming the file and the families
                 that take them (``registry.check_command``).
    stages:      stage name → callable(description, ...), each with the call ``STAGES`` gives;
                 a stage that one of its commands needs is required (see ``Stage``).
    """

    name: str
    title: str
    plural: str
    doc: str
    description: type
    detects: Callable[[Mapping], bool]
    from_dict: Callable[[Mapping, str | None], Any]
    commands: tuple[str, ...]
    stages: Mapping[str, Callable]
    options: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        unknown = sorted(set(self.stages) - set(BY_STAGE))
        missing = [s.name for s in STAGES if s.name not in self.stages and set(s.needed_by) & set(self.commands)]
        if unknown or missing:
            raise TypeError(f"Family({self.name!r}): " + (f"unknown stages {unknown} (the interface's are "
                            f"{[s.name for s in STAGES]})" if unknown else
                            f"takes {', '.join(c for s in missing for c in BY_STAGE[s].needed_by)} but has no "
                            f"{', '.join(missing)} stage (pipeline/family.py STAGES)"))

    def __repr__(self) -> str:
        return f"Family({self.name!r})"


# The command-line options that depend on the family: --transfer (transfer functions d/dφ…),
# --keep-singular (samples marked singular), --practical (MuJoCo's usual settings in build),
# --robot (build's robot-ready MJCF).
FAMILY_OPTIONS = ("--transfer", "--keep-singular", "--practical", "--robot")

@dataclass(frozen=True)
class Stage:
    """One stage of the family interface: its call (every family's implementation has exactly
    these parameters, the description first), what it returns, and the CLI commands that call
    it: a family taking one of ``needed_by`` must have the stage (``Family`` refuses to be built
    without it); any other stage is optional, and asking a family for one it lacks is a one-line
    UnsupportedError (``registry.stage``)."""

    name: str
    call: str
    returns: str
    needed_by: tuple[str, ...]


# The stages of the interface, in the order data flows through them (docs/architecture.md's
# table of stages is generated from this one and checked by tests/test_architecture_doc.py).
STAGES: tuple[Stage, ...] = (
    Stage("angles", "(desc, samples=None)",
          "the default drive angle [rad], or ``samples`` angles (n,) over the drive range", ("analyze", "forces")),
    Stage("structure", "(desc)", "a structure result: mobility, the drive, the groups or chain; "
          "``to_dict()``, ``text()``", ("structure",)),
    Stage("kinematics", "(desc, phi, omega=None, epsilon=None, *, on_singular='raise')",
          "positions, velocities, accelerations, jerks (and transfer functions) at φ [rad], scalar or (n,); "
          "``to_dict()``, ``columns()``, ``text()``", ("analyze",)),
    Stage("forces", "(desc, phi, omega=None, epsilon=None, *, on_singular='raise')",
          "the balancing torque and every pair's reaction at φ, as ``kinematics``", ("forces",)),
    Stage("summary", "(desc, omega=None, epsilon=None)",
          "the design summary over the drive range (``model.summary``); ``to_dict()``, ``text()``", ("analyze",)),
    Stage("profile", "(desc, points=720)", "a cam's profile and pitch curve; ``to_dict()``, ``columns()``",
          ("profile",)),
    Stage("mjcf", "(desc, settings=None, practical=False, robot=None)", "the MJCF text (``robot``: a "
          "``mujoco.robot.RobotOptions``, the robot-ready model)", ("build",)),
    Stage("coupling", "(desc, settings=None, practical=False)", "(the loop-free MJCF text, its couplings and their "
          "errors) (``build --loops coupling``)", ()),
    Stage("simulate", "(desc, *, revolutions=None, omega=None, epsilon=None, settings=None, samples=None, "
          "nthread=None, progress=None, max_steps=None, settle=None, notice=None)",
          "a MuJoCo run over the drive range (None: the run's default)", ("simulate",)),
    Stage("validate", "(desc, *, practical=True, nthread=None, max_steps=None, progress=None, source=None, "
          "machine_progress=None)",
          "MuJoCo against the closed form: ``ok``, ``summary(wall)``, ``to_dict()``, ``diagnosis`` (options that do "
          "not apply to a family are ignored by it)", ("validate",)),
    Stage("check_settings", "(desc, settings, *, tolerance=0.001, search=True, progress=None)",
          "MuJoCo's accuracy at ``settings`` predicted before any step and measured, and the cheapest settings "
          "meeting ``tolerance``; ``to_dict()``, ``text()``", ("check-settings",)),
    Stage("figures", "(desc, check, out)", "the report's entries (``figures``: file names drawn into the folder "
          "``out``, ``summary``, …) of a validated description", ("validate",)),
    Stage("report", "(entry)", "the report's (row, section) writers of one ``validate --json`` entry",
          ("validate",)),
    Stage("draw", "(desc, angles, out, *, vectors=None, parts=False, free_body=None, plan=None)",
          "(what was drawn into ``out``, the drawn data or None): one position (a number, None: the default) with "
          "its ``vectors`` (``draw.vectors.Arrows``) or its velocity or acceleration ``plan`` "
          "(``model.plans.VectorPlan``), or a position plan (an array)", ("draw",)),
    Stage("page", "(desc, out, frames=72, mujoco=False, progress=None)", "what was written into ``out``: one "
          "self-contained interactive HTML page (the mechanism under a slider of its input, a crank angle or a prismatic "
          "input's stroke, its vectors, curves and "
          "design summary; with ``mujoco`` MuJoCo's curves beside the closed form's)", ("page",)),
    Stage("animate", "(desc, frames, progress=None, mujoco=False, notice=None)", "(frames, how they were made)",
          ("animate",)),
    Stage("render", "(desc, angle, width, height)", "(a MuJoCo frame (h, w, 3), what it shows)", ("render",)),
)
BY_STAGE: Mapping[str, Stage] = {s.name: s for s in STAGES}

__all__ = ["BY_STAGE", "FAMILY_OPTIONS", "Family", "STAGES", "Stage"]
