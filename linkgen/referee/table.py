"""The user's table of results: a crank-angle column ``phi`` and any quantities linkgen computes,
each headed ``name [unit]`` as ``linkgen analyze``/``forces`` write them (``B.position.x [mm]``,
``rocker.angle [deg]``, ``B.force.x [N]``); units are read from the header and the values taken
to SI. A map (a TOML file's ``[columns]`` table, or a dict) renames the user's headers:
``"theta4 (deg)" = "rocker.angle [deg]"``; an empty target leaves a column out.

A table that cannot be read is a DescriptionError naming the file, the column (or row) and the
value, and saying what is allowed."""

from __future__ import annotations

import csv
import difflib
import io
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Mapping

import numpy as np

from linkgen.errors import DescriptionError
from linkgen.referee.units import UnitError, split_header, to_si

ANGLE = "phi"
# The flags linkgen writes next to its quantities; read past, never compared.
IGNORED = ("singular",)


@dataclass(frozen=True)
class Column:
    """One of the user's columns: the header as written, the linkgen header it stands for
    (``key``, SI unit), the user's unit and its factor to SI, and the values in SI (n,)."""

    header: str
    key: str
    unit: str
    factor: float
    values: np.ndarray

    @property
    def name(self) -> str:
        return split_header(self.key)[0]


@dataclass(frozen=True)
class Table:
    """The user's results: where they came from, the crank angles φ (n,) [rad] (and the unit
    they were given in), and the columns by linkgen header."""

    source: str
    phi: np.ndarray
    phi_unit: str
    columns: Mapping[str, Column]


def read_map(path: str | Path) -> dict[str, str]:
    """A ``--map`` file: TOML with one ``[columns]`` table of strings."""
    from linkgen.model.toml_file import read_toml

    if not Path(path).is_file():
        raise DescriptionError("", "no such map file (--map names a TOML file with a [columns] table)", str(path))
    data = read_toml(path)
    extra = sorted(set(data) - {"columns"})
    if extra or not isinstance(data.get("columns"), dict):
        raise DescriptionError(extra[0] if extra else "columns", "a map file holds one [columns] table: "
                               "\"your header\" = \"linkgen header [unit]\" (\"\" leaves the column out)", str(path))
    for k, v in data["columns"].items():
        if not isinstance(v, str):
            raise DescriptionError(f"columns.{k}", f"expected a header string such as \"B.position.x [mm]\", got {v!r}",
                                   str(path))
    return dict(data["columns"])


def read_csv(path: str | Path) -> dict[str, np.ndarray]:
    """A CSV file's columns by header, as floats (every cell a finite number)."""
    text = _read_text(path)
    rows = list(csv.reader(io.StringIO(text)))
    rows = [r for r in rows if any(c.strip() for c in r)]
    if len(rows) < 2:
        raise DescriptionError("", "expected a header row and at least one row of numbers", str(path))
    header = [h.strip() for h in rows[0]]
    if len(set(header)) != len(header):
        dup = next(h for h in header if header.count(h) > 1)
        raise DescriptionError(dup, "this header appears twice", str(path))
    values = np.empty((len(rows) - 1, len(header)))
    for i, row in enumerate(rows[1:], start=2):
        if len(row) != len(header):
            raise DescriptionError(f"row {i}", f"has {len(row)} cells, the header {len(header)}", str(path))
        for j, cell in enumerate(row):
            try:
                values[i - 2, j] = float(cell)
            except ValueError:
                raise DescriptionError(header[j], f"row {i}: {cell.strip()!r} is not a number", str(path)) from None
    return {h: values[:, j] for j, h in enumerate(header)}


def _read_text(path: str | Path) -> str:
    from linkgen.outputs import note_input

    try:
        with open(path, "rb") as f:
            note_input(os.fstat(f.fileno()))  # no output of this run may replace it
            raw = f.read()
    except OSError as exc:
        raise DescriptionError("", f"cannot be read ({exc.strerror or exc})", str(path)) from None
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError:
        raise DescriptionError("", "is not UTF-8 text (a CSV file is expected)", str(path)) from None


def as_columns(table: Any) -> tuple[dict[str, np.ndarray], str]:
    """The columns of what ``linkgen.referee`` takes as a table: a CSV path, a mapping of header
    → values, or a data frame (anything with ``columns`` and item access)."""
    if isinstance(table, (str, Path)):
        return read_csv(table), str(table)
    if isinstance(table, Mapping):
        items = table.items()
    elif hasattr(table, "columns") and hasattr(table, "__getitem__"):
        items = ((h, table[h]) for h in table.columns)
    else:
        raise DescriptionError("table", f"expected a CSV file, a dict of columns or a data frame, got "
                               f"{type(table).__name__}")
    out = {}
    for h, v in items:
        try:
            out[str(h)] = np.asarray(v, dtype=float).reshape(-1)
        except (TypeError, ValueError):
            raise DescriptionError(str(h), "expected numbers", "<table>") from None
    return out, "<table>"


def build(raw: Mapping[str, np.ndarray], source: str, vocabulary: tuple[str, ...],
          mapping: Mapping[str, str] | None = None) -> Table:
    """The table's columns matched to linkgen's headers ``vocabulary`` (``name [SI unit]``)."""
    mapping = dict(mapping or {})
    unknown = [k for k in mapping if k not in raw]
    if unknown:
        raise DescriptionError(unknown[0], f"the map names a column the table does not have (its columns: "
                               f"{', '.join(raw)})", source)
    lengths = {len(v) for v in raw.values()}
    if len(lengths) != 1 or 0 in lengths:
        raise DescriptionError("", "every column needs the same, non-zero number of values", source)
    by_name: dict[str, list[str]] = {}
    for key in vocabulary:
        by_name.setdefault(split_header(key)[0], []).append(key)
    phi, phi_unit, columns = None, "", {}
    for header, values in raw.items():
        target = mapping.get(header, header)
        if target == "" or split_header(target)[0] in IGNORED:
            continue
        name, unit = split_header(target)
        if not np.all(np.isfinite(values)):
            row = int(np.flatnonzero(~np.isfinite(values))[0]) + 2
            raise DescriptionError(header, f"row {row}: {float(values[row - 2])!r} is not a finite number", source)
        if unit is None:
            raise DescriptionError(header, "no unit: write it in brackets, e.g. \"B.position.x [m]\", "
                                   "\"phi [deg]\" (or name it in --map)", source)
        try:
            factor, si = to_si(unit)
        except UnitError as exc:
            raise DescriptionError(header, str(exc), source) from None
        if name == ANGLE:
            if si != "rad":
                raise DescriptionError(header, f"the crank angle's unit must be an angle (rad or deg), got {unit!r}",
                                       source)
            phi, phi_unit = values * factor, unit
            continue
        key = f"{name} [{si}]"
        if key not in vocabulary:
            raise DescriptionError(header, _not_ours(name, si, unit, by_name), source)
        if key in columns:
            raise DescriptionError(header, f"gives {key} again (also {columns[key].header!r})", source)
        columns[key] = Column(header, key, unit, factor, values * factor)
    if phi is None:
        raise DescriptionError(ANGLE, "the table needs the crank-angle column, headed \"phi [rad]\" or \"phi [deg]\" "
                               "(or one named so in --map)", source)
    if not columns:
        raise DescriptionError("", "no quantity to compare: name columns as `linkgen analyze -o F.csv` and "
                               "`linkgen forces -o F.csv` head them (e.g. \"B.position.x [m]\")", source)
    return Table(source, phi, phi_unit, columns)


def _not_ours(name: str, si: str, unit: str, by_name: Mapping[str, list[str]]) -> str:
    if name in by_name:
        units = " or ".join(split_header(k)[1] for k in by_name[name])
        return f"{name} is in {units} in linkgen's results; {unit!r} is {si}, not that kind of unit"
    close = difflib.get_close_matches(name, list(by_name), n=3)
    hint = f" (close: {', '.join(close)})" if close else ""
    return (f"not a quantity linkgen computes for this mechanism{hint}; the names are those of `linkgen analyze "
            f"--transfer -o F.csv` and `linkgen forces -o F.csv`, or map yours with --map")

