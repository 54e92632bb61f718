"""The varied fields of a study: ``--vary FIELD=START:STOP:N`` read into ``Field``s, and a
variant's values set into the parsed TOML of the description (``override``).

A field is a dotted path into the description as the user wrote it: tables by key
(``links.coupler.length``, ``drive.omega``), an array's item by index (``force[0].force[1]``)
and a point's or a vector's coordinates by ``.x``/``.y`` (``points.C.x``,
``mechanism.gravity.y``). The path must name a number in the base description (a quantity
written with a unit, "120rpm", counts: it is replaced by the value in SI). Values are SI
(m, kg, rad, rad/s, N); ``START`` and ``STOP`` may carry a unit the description takes
("80rpm", "30deg", "5mm")."""

from __future__ import annotations

import copy
import math
import re
from collections.abc import Mapping, MutableSequence
from dataclasses import dataclass
from typing import Any

from linkgen.errors import ArgumentError
from linkgen.model.units import ACCELERATION_UNITS, LENGTH_UNITS, SPEED_UNITS, shown

_PART = re.compile(r"^([A-Za-z_][A-Za-z0-9_\-]*)((?:\[\d+\])*)$")
_COORD = {"x": 0, "y": 1}
# Units a bound may carry, each to its SI factor (the description's own units).
_UNITS = {**LENGTH_UNITS, **SPEED_UNITS, **ACCELERATION_UNITS, "deg": math.pi / 180, "°": math.pi / 180,
          "rad": 1.0, "kg": 1.0, "N": 1.0}
_BOUND = re.compile(r"^\s*([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*([A-Za-z°/²2]*)\s*$")
# The unit of a field's value by its last key (SI), for the table's column names.
_FIELD_UNITS = {"x": "m", "y": "m", "length": "m", "offset": "m", "radius": "m", "module": "m", "density": "kg/m",
                "areal_density": "kg/m²", "mass": "kg", "inertia": "kg·m²", "omega": "rad/s",
                "epsilon": "rad/s²", "angle": "rad", "stiffness": "N/m", "damping": "N·s/m", "torque": "N·m",
                "force": "N", "gravity": "m/s²", "preload": "N"}


@dataclass(frozen=True)
class Field:
    """One varied field: its path, its range [SI] and, on a grid, its number of values."""

    path: str
    start: float
    stop: float
    count: int | None = None

    @property
    def unit(self) -> str:
        keys = [k for k in re.split(r"[.\[\]]", self.path) if k and not k.isdigit()]
        last = keys[-1] if keys else ""
        if last in ("x", "y") and len(keys) >= 2 and keys[-2] in _FIELD_UNITS and keys[0] != "points":
            last = keys[-2]
        return _FIELD_UNITS.get(last, "1")

    @property
    def column(self) -> str:
        return f"{self.path} [{self.unit}]"


def bound(text: str, where: str) -> float:
    m = _BOUND.match(text)
    if not m or (m.group(2) and m.group(2) not in _UNITS):
        raise ArgumentError(f"{where}: expected a number, optionally with a unit ({', '.join(sorted(_UNITS))}), "
                            f"got {text!r}")
    value = float(m.group(1)) * (_UNITS[m.group(2)] if m.group(2) else 1.0)
    if not math.isfinite(value):
        raise ArgumentError(f"{where}: expected a finite number, got {text!r}")
    return value


def parse_vary(spec: str, *, grid: bool = True) -> Field:
    """``FIELD=START:STOP:N`` (grid) or ``FIELD=START:STOP`` (Latin hypercube, ``grid=False``)."""
    form = "FIELD=START:STOP:N" if grid else "FIELD=START:STOP (with --lhs)"
    if "=" not in spec:
        raise ArgumentError(f"--vary {spec!r}: expected {form}, e.g. links.coupler.length=0.9:1.1:5")
    path, _, rng = spec.partition("=")
    path = path.strip()
    parts = rng.split(":")
    if len(parts) != (3 if grid else 2):
        raise ArgumentError(f"--vary {spec!r}: expected {form}")
    start, stop = bound(parts[0], f"--vary {path} START"), bound(parts[1], f"--vary {path} STOP")
    count = None
    if grid:
        if not parts[2].strip().isdigit() or not 1 <= int(parts[2]) <= 100_000:
            raise ArgumentError(f"--vary {path} N: expected a whole number of values from 1 to 100000, "
                                f"got {parts[2]!r}")
        count = int(parts[2])
        if count > 1 and start == stop:
            raise ArgumentError(f"--vary {path}: START equals STOP ({start:g}) with N = {count}")
    return Field(path, start, stop, count)


def steps(path: str) -> list[str | int]:
    """The keys and indices of a path, in order."""
    out: list[str | int] = []
    for part in path.split("."):
        m = _PART.match(part)
        if not m:
            raise ArgumentError(f"--vary {path}: {part!r} is not a key or key[index]")
        out.append(m.group(1))
        out += [int(i) for i in re.findall(r"\[(\d+)\]", m.group(2))]
    return out


def walk(data: Any, path: str, create: bool = False) -> tuple[Any, str | int]:
    """The container holding the field and its key or index in it (``create``: a table's last
    key may be missing: an optional field left at its default)."""
    keys = steps(path)
    node, where = data, ""
    for i, step in enumerate(keys):
        last = i == len(keys) - 1
        if isinstance(step, str) and step in _COORD and isinstance(node, MutableSequence):
            step = _COORD[step]
        if isinstance(step, int):
            if not isinstance(node, MutableSequence) or step >= len(node):
                raise ArgumentError(f"--vary {path}: {where or 'the description'} has no item [{step}]")
        elif not isinstance(node, Mapping) or (step not in node and not (create and last)):
            have = ", ".join(map(str, node)) if isinstance(node, Mapping) else "no keys"
            raise ArgumentError(f"--vary {path}: {where or 'the description'} has no {step!r} (it has {have})")
        if last:
            return node, step
        node = node[step]
        where = f"{where}.{step}" if isinstance(step, str) and where else (step if not where else f"{where}[{step}]")
    raise ArgumentError(f"--vary {path}: empty path")


def check_path(data: dict, path: str) -> None:
    """ArgumentError unless ``path`` names a number (or a quantity with its unit) in ``data``."""
    try:
        node, key = walk(data, path)
    except ArgumentError:
        _optional(data, path)
        return
    value = node[key]
    if isinstance(value, bool) or not isinstance(value, (int, float, str)) or \
            (isinstance(value, str) and not _BOUND.match(value)):
        raise ArgumentError(f"--vary {path}: the description has {shown(value)} there; only a number can be "
                            f"varied")


def _optional(data: dict, path: str) -> None:
    """Accept a path whose last key the description leaves out when the loader takes it (an
    optional field at its default, ``drive.epsilon``); else the ArgumentError naming it."""
    from linkgen.errors import DescriptionError
    from linkgen.pipeline.registry import from_dict

    node, key = walk(data, path, create=True)  # the tables up to it exist, or this raises
    try:
        from_dict(override(data, {path: 0.0}), None)
    except DescriptionError as exc:
        if "unknown key" in exc.problem:
            walk(data, path)  # raises the ArgumentError naming what the table has
    return None


def override(data: dict, values: dict[str, float]) -> dict:
    """A copy of the parsed TOML ``data`` with each path of ``values`` set to its value [SI]."""
    out = copy.deepcopy(data)
    for path, value in values.items():
        node, key = walk(out, path, create=True)
        node[key] = float(value)
    return out


__all__ = ["Field", "bound", "check_path", "override", "parse_vary", "steps", "walk"]
