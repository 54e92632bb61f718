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
    stages:      stage name → callable(description, ...): structure, kinematics, forces, summary,
                 mjcf, validate, draw, ... (see ``STAGES``).
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

    def __repr__(self) -> str:
        return f"Family({self.name!r})"


# The command-line options that depend on the family: --transfer (transfer functions d/dφ…),
# --keep-singular (samples marked singular), --practical (MuJoCo's usual settings in build).
FAMILY_OPTIONS = ("--transfer", "--keep-singular", "--practical")

# The stages of the interface, in the order data flows through them.
STAGES = ("angles", "structure", "kinematics", "forces", "summary", "profile", "mjcf", "simulate", "validate",
          "figures", "report", "draw", "animate", "render")
# The closed-form stages: angles(desc, samples=None) → the default crank angle or a sample grid;
# structure(desc), kinematics(desc, phi, omega=None, epsilon=None), forces(...), summary(desc,
# omega=None, epsilon=None), profile(desc, points) → results with to_dict(), columns(), text().
# The MuJoCo and picture stages (pipeline/*_mujoco.py): mjcf(desc, settings=None, practical=False) → MJCF
# text; simulate(desc, **options) → a run; validate(desc, **options) → a result with ok, summary(wall),
# to_dict() and diagnosis; figures(desc, result, folder) → the report's entries (figures, …);
# report(entry) → the report's (row, section) writers; draw(desc, angles, out) → what was drawn;
# animate(desc, frames, progress, mujoco, notice) → (frames, how); render(desc, angle, width, height)
# → (frame, what).

__all__ = ["FAMILY_OPTIONS", "Family", "STAGES"]
