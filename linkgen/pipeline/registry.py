"""The registry of mechanism families: the only place that tells one kind of description from
another. ``load(path)`` opens every description linkgen reads; ``family_of`` gives the family of a
description (or of a file) and with it the stages every command and API function calls.

Adding a family: write its package (description, closed form and its stage modules) and one
entry in FAMILIES; nothing else branches on the kind of file."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Mapping

from linkgen.errors import ArgumentError, DescriptionError, UnsupportedError
from linkgen.pipeline.cam import CAM
from linkgen.pipeline.family import BY_STAGE, Family
from linkgen.pipeline.planar import PLANAR
from linkgen.pipeline.spatial import SPATIAL

# Asked in this order: the first whose ``detects`` accepts the parsed TOML reads it; planar last
# (it takes every other file and names what is wrong with it).
FAMILIES: tuple[Family, ...] = (SPATIAL, CAM, PLANAR)
BY_NAME: Mapping[str, Family] = {f.name: f for f in FAMILIES}


def family_of_data(data: Mapping) -> Family:
    """The family of a parsed TOML description."""
    return next(f for f in FAMILIES if f.detects(data))


def from_dict(data: Mapping, source: str | None = None) -> Any:
    """The validated description of any family from its parsed TOML (errors name ``source``)."""
    return family_of_data(data).from_dict(data, source)


def loads(raw: bytes | str, source: str = "<description>") -> Any:
    """The validated description of any family from the bytes or text of a TOML file."""
    from linkgen.model.toml_file import parse_toml

    return from_dict(parse_toml(raw, source), source)


def load(path: str | Path) -> Any:
    """Open any description linkgen reads: a planar linkage (``Mechanism``, with its cams, gears
    and ``[machine]``), a stand-alone cam (``CamMechanism``) or a spatial four-bar
    (``SpatialMechanism``). DescriptionError names the file, the field and the value."""
    from linkgen.model.toml_file import read_toml

    return from_dict(read_toml(path), str(path))


def family_of(description: Any) -> Family:
    """The family of a description (any object ``load`` returns, or a planar ``Assembly``)."""
    for f in FAMILIES:
        if isinstance(description, f.description):
            return f
    inner = getattr(description, "mechanism", None)  # an assembled planar mechanism
    if inner is not None and inner is not description:
        return family_of(inner)
    kinds = ", ".join(f"{f.description.__name__} ({f.plural})" for f in FAMILIES)
    raise ArgumentError(f"not a mechanism description: got {type(description).__name__}; linkgen takes {kinds} "
                        f"(linkgen.load opens every kind)")


def family_of_file(path: str | Path) -> Family | None:
    """The family of a description file, or None when the file cannot be read as TOML (the
    command then reports why, naming the file)."""
    from linkgen.model.toml_file import read_toml

    try:
        return family_of_data(read_toml(path))
    except DescriptionError:
        return None


def unsupported(family: Family, what: str, path: str | Path | None = None) -> UnsupportedError:
    """The one-line refusal of a command (or stage) ``what`` that ``family`` does not take."""
    others = [f.plural for f in FAMILIES if f is not family and what in f.commands]
    where = f"{path}: " if path is not None else ""
    takes = f"`linkgen {what}` is for {' and '.join(others)}" if others else f"`linkgen {what}` does not apply"
    article = "an" if family.title[0] in "aeiou" else "a"
    return UnsupportedError(f"{where}{article} {family.title} ({family.doc}); {takes}; {family.plural} take "
                            f"{', '.join(family.commands)}")


def stage(description: Any, name: str):
    """The stage ``name`` of the description's family (a callable taking the description first);
    UnsupportedError, naming the families that have it, if its family has none."""
    return family_stage(family_of(description), name, getattr(description, "name", "?"))


def family_stage(family: Family, name: str, model: str):
    """The stage ``name`` of ``family``; UnsupportedError naming the model, the families that
    have the stage, or the interface's stages for a name that is none of them."""
    fn = family.stages.get(name)
    if fn is not None and name in _AT_INPUT and family.name != "planar":  # only planar linkages have prismatic drives
        return _no_stroke(fn)
    if fn is not None:
        return fn
    if name not in BY_STAGE:
        raise UnsupportedError(f"{model}: {name!r} is not a stage; the stages are {', '.join(BY_STAGE)}")
    others = [f.plural for f in FAMILIES if name in f.stages]
    has = f"it is for {' and '.join(others)}" if others else "no family has it yet"
    raise UnsupportedError(f"{model}: {family.plural} have no {name.replace('_', ' ')} stage; {has}")


# Stages whose second argument is the drive's input (an angle, or a prismatic drive's stroke).
_AT_INPUT = ("kinematics", "forces", "draw", "render")


def _no_stroke(fn):
    """``fn`` refusing a stroke ("0.45m", ``arguments.Stroke``) where a crank angle is meant."""
    from functools import wraps

    from linkgen.model.arguments import input_kind

    @wraps(fn)
    def checked(desc, at=None, *args, **kwargs):
        return fn(desc, input_kind(at, False, "angle"), *args, **kwargs)

    return checked


def require(description: Any, family_name: str, what: str, instead: Mapping[str, str]) -> Family:
    """The description's family if it is ``family_name``; UnsupportedError in one line if not,
    naming ``what`` was asked, the family it is for and, of ``instead`` (function → the stage it
    calls), the functions that take the description's family."""
    family = family_of(description)
    if family.name == family_name:
        return family
    takes = [fn for fn, st in instead.items() if st in family.stages]
    raise UnsupportedError(f"{getattr(description, 'name', '?')}: {what} is for {BY_NAME[family_name].plural}; "
                           f"{family.plural} take {', '.join(takes)}")


def report_parts(entry: Mapping):
    """The report's (row, section) writers (``report.sections``) of one entry of ``linkgen
    validate --json``: its family's ``report`` stage, or the error's for a file that could not
    be validated."""
    from linkgen.report import sections

    family = BY_NAME.get(entry.get("family"))
    if "error" in entry or family is None:
        return sections.ERROR
    return family_stage(family, "report", str(entry.get("model", "?")))(entry)


def check_command(command: str, path: str | Path, options: tuple[str, ...] = ()) -> Family | None:
    """The family of the file ``path`` if it takes ``command`` and the family-dependent
    ``options`` given (``FAMILY_OPTIONS``: "--transfer", …); UnsupportedError naming the file and
    the families that do if not; None when the file cannot be read (the command reports that)."""
    family = family_of_file(path)
    if family is not None and command not in family.commands:
        raise unsupported(family, command, path)
    for option in options if family is not None else ():
        if option not in family.options:
            others = [f.plural for f in FAMILIES if option in f.options]
            article = "an" if family.title[0] in "aeiou" else "a"
            raise UnsupportedError(f"{path}: {article} {family.title} ({family.doc}) takes no {option}; {option} is "
                                   f"for {' and '.join(others)}")
    return family


__all__ = ["BY_NAME", "FAMILIES", "UnsupportedError", "check_command", "family_of", "family_of_data", "family_of_file",
           "family_stage", "from_dict", "load", "loads", "report_parts", "require", "stage", "unsupported"]
