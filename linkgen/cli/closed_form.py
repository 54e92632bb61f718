"""The closed form from the command line, written once for every family through the registry
(``pipeline.registry.stage``): ``linkgen structure``, ``analyze`` (one state, samples, the
transfer functions, the design summary), ``forces`` and ``profile``. What differs between
families is in their results' ``text()``, ``to_dict()`` and ``columns()``.

One output option: ``-o/--out FILE``, the format from its extension: ``.csv`` the samples,
``.json`` the JSON object (of one state, of the samples with --samples, or of the summary)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

from linkgen.cli.common import OptionError, add_crank_arguments, check_finite, print_json, write_rows

# Conventions of ``linkgen forces`` in every family (docs/format.md, "Conventions"), its --help.
FORCES_HELP = ("Closed-form joint reactions and balancing torque; planar linkages also the reduced inertia and the "
               "reduced moment of the loads. Conventions (docs/format.md, \"Conventions\"), the same in every family: "
               "at a revolute or spherical pair J, reactions[J].force [N] (in space also its moment [N·m]) is what the "
               "pair's second link (in the order of the [links.NAME] tables) exerts on its first, in world axes; each "
               "result names them (on, by). At a prismatic pair the guide acts on the slider: in the plane "
               "normal_force [N] along the guide's left normal and moment [N·m] about the slider's point, in space a "
               "force square to the line and a moment. balancing_torque [N·m] is the torque the drive applies to the "
               "crank about its axis (+z in the plane), positive when it turns the crank the positive way.")
# What -o/--out writes, by extension (``common.output_kind``).
SAMPLES = {".csv": "the samples over the drive range", ".json": "the JSON object, as --json prints it"}
SUMMARY = {".json": "the summary's JSON object, as --json prints it"}
PROFILE = {".csv": "the points", ".json": "the JSON object"}
STRUCTURE = {".json": "the structure's JSON object, as --json prints it"}


def _output(args, kinds: dict[str, str], command: str | None = None) -> tuple[Path | None, str, str | None]:
    """The file the command writes (-o/--out, or a hidden old spelling), how the user named it
    and its format ("csv", "json"; None: no file)."""
    from linkgen.cli.common import output_kind, spelling

    path = args.out
    if path is None:
        return None, "-o/--out", None
    return path, spelling(args, path), output_kind(args, path, kinds, command).lstrip(".")


def write_json(obj, path: Path | None) -> None:
    """``obj`` as strict JSON on stdout or, atomically, to ``path``."""
    if path is None:
        print_json(obj)
        return
    from linkgen.cli.files import atomic_open

    check_finite(obj)
    with atomic_open(path) as out:
        out.write(json.dumps(obj, indent=2, allow_nan=False) + "\n")
    print(f"wrote {path}", file=sys.stderr)


def _load(args):
    from linkgen.pipeline.registry import load

    return load(args.model)


def cmd_structure(args) -> int:
    from linkgen.pipeline.registry import stage

    path, spelled, fmt = _output(args, STRUCTURE)
    if args.json and path is not None:
        raise OptionError(f"--json prints what {spelled} {path} writes: give one of them")
    desc = _load(args)
    result = stage(desc, "structure")(desc)
    if args.json or fmt == "json":
        write_json(result.to_dict(), path)
        return 0
    print(result.text())
    return 0


def _check(args, path: Path | None, fmt: str | None, spelled: str) -> bool:
    """Whether the command evaluates samples (--samples N, or -o FILE.csv: 360 by default);
    OptionError for options that exclude each other, saying what is allowed."""
    sampled = [o for o, v in (("--samples", args.samples), (f"{spelled} {path}", path if fmt == "csv" else None))
               if v is not None]
    if sampled and args.angle is not None:
        raise OptionError(f"--angle cannot be combined with {sampled[0]}: --angle evaluates one crank angle (printed, "
                          "--json, or -o FILE.json); --samples N and -o FILE.csv evaluate samples over the drive range")
    if args.json and path is not None:
        raise OptionError(f"--json prints what {spelled} {path} writes: give one of them")
    if args.keep_singular and not sampled:
        raise OptionError("--keep-singular is for samples (--samples, -o FILE.csv); at one crank angle a singular "
                          "position is an error")
    return bool(sampled)


def _closed_form(args, name: str) -> int:
    """``analyze`` (name "kinematics") and ``forces``: one state (text or JSON) or samples (CSV or JSON)."""
    from linkgen.cli.singular import report_singular
    from linkgen.pipeline.registry import stage

    path, spelled, fmt = _output(args, SAMPLES)
    sampled = _check(args, path, fmt, spelled)
    desc = _load(args)
    fn = stage(desc, name)
    angles = stage(desc, "angles")
    transfer = bool(getattr(args, "transfer", False))
    if sampled:
        r = fn(desc, angles(desc, args.samples or 360), args.omega, args.epsilon, on_singular="mark")
    else:
        r = fn(desc, angles(desc) if args.angle is None else args.angle, args.omega, args.epsilon)
    if fmt == "json" or args.json:
        write_json(r.to_dict(transfer=transfer), path)
    elif sampled:
        cols = r.columns(transfer=transfer)
        write_rows(list(cols), list(cols.values()), path, rows=getattr(r, "ROWS", "crank angles"))
    else:
        check_finite(r.to_dict(transfer=transfer))
        print(r.text(transfer=transfer))
    return report_singular(args.model, r.singular_lines(), args.keep_singular) if sampled else 0


def cmd_analyze(args) -> int:
    if args.summary:
        return cmd_summary(args)
    return _closed_form(args, "kinematics")


def cmd_forces(args) -> int:
    return _closed_form(args, "forces")


def cmd_summary(args) -> int:
    """``analyze --summary``: the family's design summary as text or JSON."""
    from linkgen.pipeline.registry import stage

    path, spelled, fmt = _output(args, SUMMARY, "analyze --summary")
    used = [o for o, v in (("--angle", args.angle), ("--samples", args.samples), ("--transfer", args.transfer or None),
                           ("--keep-singular", args.keep_singular or None)) if v is not None]
    if used:
        raise OptionError(f"--summary covers the whole drive range; it cannot be combined with {used[0]} (it is "
                          "printed, or given as JSON by --json or -o FILE.json)")
    if args.json and path is not None:
        raise OptionError(f"--json prints what {spelled} {path} writes: give one of them")
    desc = _load(args)
    s = stage(desc, "summary")(desc, args.omega, args.epsilon)
    result = s.to_dict()
    check_finite(result)
    if args.json or fmt == "json":
        write_json(result, path)
        return 0
    print(s.text())
    return 0


def cmd_profile(args) -> int:
    from linkgen.pipeline.registry import stage

    path, spelled, fmt = _output(args, PROFILE)
    desc = _load(args)
    p = stage(desc, "profile")(desc, args.points)
    if fmt == "json":
        write_json(p.to_dict(), path)
        return 0
    cols = p.columns()
    write_rows(list(cols), list(cols.values()), path, rows="cam angles")
    return 0


def _out_argument(parser, kinds: dict[str, str], old: tuple[str, ...] = (), default: str = "") -> None:
    from linkgen.cli.common import add_out_argument, allowed_text

    add_out_argument(parser, f"write to FILE, the format from its extension: {allowed_text(kinds)}{default}",
                     old=old, metavar="FILE")


def add_commands(sub) -> None:
    """``structure``, ``analyze`` and ``forces``."""
    s = sub.add_parser("structure", help="mobility, Assur groups and the structure formula")
    s.add_argument("model", type=Path, help="description file (.toml)")
    s.add_argument("--json", action="store_true", help="print the structure as one JSON object")
    _out_argument(s, STRUCTURE)
    s.set_defaults(func=cmd_structure)

    a = sub.add_parser("analyze", help="closed-form positions, velocities, accelerations and jerks")
    add_crank_arguments(a, "38.117deg")
    _out_argument(a, SAMPLES, ("--csv",), "; CSV writes --samples N angles (default 360)")
    a.add_argument("--transfer", action="store_true",
                   help="also the transfer functions d1, d2, d3 = d/dφ, d²/dφ², d³/dφ³ (m/rad, rad/rad; in the table, "
                        "JSON or CSV)")
    a.add_argument("--summary", action="store_true",
                   help="print the design summary over the drive range (SI units and degrees in the text, "
                        "radians in --json): stroke, swing, limit positions, time ratio, least transmission "
                        "angles, peak torque and reactions")
    a.set_defaults(func=cmd_analyze)

    f = sub.add_parser("forces", help="joint reactions and balancing torque (closed form; planar linkages also the "
                                      "reduced inertia)",
                       description=FORCES_HELP)
    add_crank_arguments(f, "30deg")
    _out_argument(f, SAMPLES, ("--csv",), "; CSV writes --samples N angles (default 360)")
    f.set_defaults(func=cmd_forces)


def add_profile(sub) -> None:
    """``profile``: a cam's profile."""
    from linkgen.cli.common import _positive_int

    p = sub.add_parser("profile", help="a cam's profile and pitch curve as point coordinates (CSV or JSON)")
    p.add_argument("model", type=Path, help="cam description file (.toml)")
    _out_argument(p, PROFILE, ("--output",), " (default: CSV on stdout)")
    p.add_argument("--points", type=_positive_int, default=720, help="points over the turn (no unit; default 720)")
    p.set_defaults(func=cmd_profile)


__all__ = ["FORCES_HELP", "add_commands", "add_profile", "cmd_analyze", "cmd_forces", "cmd_profile", "cmd_structure", "cmd_summary",
           "write_json"]
