"""What the commands share: option parsers with units, the crank grid, CSV and JSON output,
the checks of conflicting options."""

from __future__ import annotations

import argparse
import csv
import json
import math
import sys
from pathlib import Path

import numpy as np

from linkgen.model.turn import full_turn
from linkgen.errors import ArgumentError, LinkgenError
from linkgen.model import limits
from linkgen.model.arguments import angle_text, rate_text
from linkgen.cli.files import atomic_open
from linkgen.cli.singular import SINGULAR_STATUS


def crank_grid(mech, samples: int) -> np.ndarray:
    """``samples`` crank angles [rad] over the drive range (a full turn excludes its end)."""
    d = mech.drive
    full = full_turn(mech)
    return np.linspace(d.start, d.stop, samples, endpoint=not full)


def _angle_arg(text: str) -> float:
    """An argparse type: an angle with its unit (``linkgen.model.arguments``, as the API reads it)."""
    try:
        return angle_text(text)
    except ArgumentError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def _float_arg(text: str) -> float:
    try:
        x = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(x):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return x


def rate_arg(limit: float, unit: str):
    """An argparse type: a finite number with |x| <= ``limit`` (see linkgen.limits), in ``unit``
    (rad/s or rad/s²) or with its own unit (100rpm, 2rad/s2, 60rpm/s): ``linkgen.model.arguments``,
    as the API reads it."""

    def parse(text: str) -> float:
        try:
            return rate_text(text, unit, limit)
        except ArgumentError as exc:
            raise argparse.ArgumentTypeError(str(exc)) from None

    return parse


from linkgen.model.limits import MAX_SAMPLES  # noqa: E402 (the CLI's --samples bound, with the API's)


def whole_in(lo: int, hi: int | None = None):
    """An argparse type: a whole number from ``lo`` (to ``hi``, if given), refused with the
    range it allows."""

    def parse(text: str) -> int:
        try:
            n = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
        if n < lo or (hi is not None and n > hi):
            allowed = f">= {lo}" if hi is None else f"from {lo} to {hi}"
            raise argparse.ArgumentTypeError(f"expected a whole number {allowed}, got {text!r}")
        return n

    return parse


def _positive_int(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number, got {text!r}") from None
    if not 1 <= n <= MAX_SAMPLES:
        raise argparse.ArgumentTypeError(f"expected a whole number from 1 to {MAX_SAMPLES}, got {text!r}")
    return n


# Rows formatted at a time when writing CSV: bounds the text held in memory (~4096 rows ×
# 40 columns × 25 characters = 4 MB) whatever the number of samples.
CSV_CHUNK_ROWS = 4096


def _text(column: np.ndarray) -> list[str]:
    """A column's cells: whole numbers (booleans, integers) as such, floats at full precision."""
    if column.dtype.kind in "biu":
        return [str(int(x)) for x in column.tolist()]
    return [repr(float(x)) for x in column.tolist()]


def _write_csv(out, cols: list[str], data: list[np.ndarray]) -> int:
    writer = csv.writer(out)
    writer.writerow(cols)
    n = len(data[0]) if data else 0
    for start in range(0, n, CSV_CHUNK_ROWS):
        writer.writerows(zip(*(_text(np.asarray(d[start:start + CSV_CHUNK_ROWS])) for d in data)))
    return n


def check_finite_columns(cols: list[str], data: list[np.ndarray]) -> None:
    """Raise LinkgenError naming the first column and row holding a NaN or an infinity: such a
    number is never written (a CSV reader would take it for a result). Columns of shape (n,) or
    (n, k), row = the first axis."""
    for col, d in zip(cols, data):
        d = np.asarray(d)
        if d.dtype.kind in "fc" and not np.all(np.isfinite(d)):
            row = int(np.argwhere(~np.isfinite(d))[0][0])
            raise LinkgenError(f"the result is not finite in column {col!r} at row {row + 1} (the computation "
                               "overflowed or hit a singular position); nothing was written")


def write_rows(cols: list[str], data: list[np.ndarray], path: Path | None, rows: str = "crank angles") -> None:
    """Columns (each (n,)) as CSV with a header (each name with its unit, as the results'
    ``columns()`` give them), full precision, to ``path`` (written atomically) or stdout;
    ``rows``: what a row is, for the line that reports the write (a cam's rows are cam angles)."""
    check_finite_columns(cols, data)
    if path is None:
        _write_csv(sys.stdout, cols, data)
        return
    with atomic_open(path) as out:
        n = _write_csv(out, cols, data)
    print(f"wrote {n} {rows} × {len(cols)} columns to {path}", file=sys.stderr)


class OptionError(LinkgenError):
    """Command-line options that contradict each other (not about a file)."""


def _first_non_finite(obj, where: str = "") -> str | None:
    """The key path of the first NaN or infinity in a JSON-like structure, or None."""
    if isinstance(obj, float):
        return None if math.isfinite(obj) else where or "value"
    if isinstance(obj, dict):
        items = ((f"{where}.{k}" if where else str(k), v) for k, v in obj.items())
    elif isinstance(obj, (list, tuple)):
        items = ((f"{where}[{i}]", v) for i, v in enumerate(obj))
    else:
        return None
    for path, v in items:
        found = _first_non_finite(v, path)
        if found:
            return found
    return None


def check_finite(obj) -> None:
    """Raise LinkgenError naming the first NaN or infinity in a JSON-like result: such a value
    is never printed (and JSON has no such values)."""
    bad = _first_non_finite(obj)
    if bad is not None:
        raise LinkgenError(f"the result is not finite at {bad} (the computation overflowed or hit a singular "
                           "position); nothing was printed")


def print_json(obj) -> None:
    """``obj`` as strict JSON on stdout (checked by ``check_finite`` first)."""
    check_finite(obj)
    print(json.dumps(obj, indent=2, allow_nan=False))


def add_crank_arguments(parser: argparse.ArgumentParser, example_angle: str) -> None:
    """MODEL, one crank state (--angle, --omega, --epsilon, --json) or samples (--samples); the
    command adds its output option (-o/--out)."""
    parser.add_argument("model", type=Path, help="description file (.toml)")
    parser.add_argument("--angle", type=_angle_arg,
                        help=f"crank angle with its unit, e.g. {example_angle}, 30° or 0.52rad (default: the range's start)")
    parser.add_argument("--omega", type=rate_arg(limits.MAX_OMEGA, "rad/s"),
                        help="crank speed [rad/s], or with a unit, e.g. 100rpm (default: the description's)")
    parser.add_argument("--epsilon", type=rate_arg(limits.MAX_EPSILON, "rad/s²"),
                        help="crank acceleration [rad/s²], or with a unit, e.g. 60rpm/s (default: the description's)")
    parser.add_argument("--json", action="store_true", help="print the JSON object -o FILE.json writes: of one crank angle, or of the samples "
                             "with --samples N")
    parser.add_argument("--samples", type=_positive_int,
                        help="evaluate this many angles over the drive range (no unit): CSV on stdout (the JSON "
                             "object with --json), or to -o FILE")
    parser.add_argument("--keep-singular", action="store_true",
                        help="with samples: exit 0 even if some are singular (by default such samples are "
                             f"written marked, singular = 1, and the exit status is {SINGULAR_STATUS}); at one "
                             "crank angle a singular position is always an error (status 2)")



# The kind of an output folder among an output's kinds (``output_kind``): an existing folder, or
# a name without an extension (a name with one is a file's).
FOLDER = "folder"

# Hidden earlier spellings of -o/--out that named one kind of output: they write that kind only
# (``--csv x.json`` is refused, never CSV in a .json file); --output names any, as -o does.
ALIAS_KINDS = {"--csv": ".csv", "--mjcf": ".xml", "--report": FOLDER}


class _OutAction(argparse.Action):
    """``-o/--out`` and its hidden aliases: the path in ``out`` (a list when given once per
    output), and how the user spelled it in ``out_spelling`` (path → option), for the messages."""

    def __call__(self, parser, namespace, values, option_string=None):
        if self.const == "append":
            setattr(namespace, self.dest, [*(getattr(namespace, self.dest, None) or []), values])
        else:
            setattr(namespace, self.dest, values)
        spelling = dict(getattr(namespace, "out_spelling", None) or {})
        spelling[str(values)] = "-o/--out" if option_string in ("-o", "--out") else option_string
        namespace.out_spelling = spelling


def add_out_argument(parser: argparse.ArgumentParser, help: str, old: tuple[str, ...] = (), required: bool = False,
                     append: bool = False, metavar: str | None = None) -> None:
    """``-o/--out``, the one output option of every command that writes (a file, its format from
    the extension, or a folder: ``output_kind``); ``old``: earlier spellings kept as hidden aliases
    (``args.out`` either way). ``append``: given once per output (a list)."""
    kind = {"const": "append", "nargs": None} if append else {}
    group = parser.add_mutually_exclusive_group(required=required) if old and not append else parser
    group.add_argument("-o", "--out", type=Path, action=_OutAction, help=help, metavar=metavar,
                       required=required and not (old and not append), **kind)
    for option in old:
        group.add_argument(option, dest="out", type=Path, action=_OutAction, help=argparse.SUPPRESS, **kind)


def spelling(args, path: Path) -> str:
    """How the user named the output ``path`` (-o/--out, or a hidden old spelling)."""
    return (getattr(args, "out_spelling", None) or {}).get(str(path), "-o/--out")


def _kind_text(kinds: list[str], what: str) -> str:
    if kinds == [FOLDER]:
        return f"a folder ({what}; an existing folder or a name without an extension)"
    names = kinds[0] if len(kinds) == 1 else ", ".join(kinds[:-1]) + " or " + kinds[-1]
    return f"{names} ({what})"


def _or(parts: list[str]) -> str:
    return parts[0] if len(parts) == 1 else ", ".join(parts[:-1]) + " or " + parts[-1]


def allowed_text(kinds: dict[str, str]) -> str:
    """``kinds`` (extension or FOLDER → what it holds) as the messages and help texts list them:
    ".png, .svg or .pdf (the drawing)"."""
    groups: dict[str, list[str]] = {}
    for k, w in kinds.items():
        groups.setdefault(w, []).append(k)
    return _or([_kind_text(ks, w) for w, ks in groups.items()])


def output_kind(args, path: Path, kinds: dict[str, str], command: str | None = None) -> str:
    """The kind of output ``path`` names for ``args.command``: its extension (lower case) when in
    ``kinds`` (extension → what the command writes there; FOLDER for a folder), else FOLDER when
    the command writes one and ``path`` is a folder or has no extension. OptionError, one line in
    one style for every command, naming the option as spelled, the path, what the command writes
    and what was given (``command``: how to name the command, default ``args.command``); a hidden
    old spelling that named one kind (ALIAS_KINDS) takes only that."""
    spelled = spelling(args, path)
    suffix = path.suffix.lower()
    if FOLDER in kinds and (path.is_dir() or not suffix):
        kind = FOLDER
    elif suffix in kinds:
        kind = suffix
    else:
        got = "a folder" if path.is_dir() else suffix or "no extension"
        raise OptionError(f"{spelled} {path}: `linkgen {command or args.command}` writes {allowed_text(kinds)}; got {got}")
    named = ALIAS_KINDS.get(spelled)
    if named is not None and named != kind:
        raise OptionError(f"{spelled} {path}: {spelled} (the earlier spelling of -o/--out) writes "
                          f"{_kind_text([named], kinds.get(named, 'its output'))} only; give -o {path} to write "
                          f"{_kind_text([kind], kinds[kind])}")
    return kind
