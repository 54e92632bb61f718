"""Mutants of the bundled descriptions for validation/fuzz_commands.py: a family for every
models/*.toml, a TOML writer, and seeded mutations of the parsed tables (numbers, types,
names, removed and added keys) or of the text itself, plus special files (/dev/zero, a FIFO,
a folder, an empty file).

A mutant is a pure function of (seed, index): ``mutant(seed, k)`` gives the same bytes on
every machine, so a reproducer is its index and seed, or the file it wrote.
"""

from __future__ import annotations

import copy
import json
import math
import re
import tomllib
from dataclasses import dataclass
from pathlib import Path

import numpy as np

MODELS_DIR = Path(__file__).resolve().parent.parent / "models"
FAMILIES = ("planar", "gears", "cam_linkage", "cam", "machine", "spatial", "special")
SPECIAL = ("dev_zero", "fifo", "folder", "empty", "binary")


def family_of(data: dict) -> str:
    """The family of a parsed description (the registry's), a planar one told apart further by
    the layers over it (the bundled models' classification)."""
    from linkgen.pipeline.registry import family_of_data

    family = family_of_data(data).name
    if family != "planar":
        return family
    return next((kind for key, kind in (("machine", "machine"), ("gear", "gears"), ("cam", "cam_linkage"))
                 if key in data), "planar")


def bundled() -> list[tuple[str, str, bytes]]:
    """(family, stem, text) of every models/*.toml, in name order."""
    out = []
    for p in sorted(MODELS_DIR.glob("*.toml")):
        raw = p.read_bytes()
        out.append((family_of(tomllib.loads(raw.decode())), p.stem, raw))
    return out


# ---------------------------------------------------------------- TOML writer
_BARE = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(k: str) -> str:
    return k if _BARE.match(k) else json.dumps(k, ensure_ascii=False)


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, float):
        if math.isnan(v):
            return "nan"
        if math.isinf(v):
            return "inf" if v > 0 else "-inf"
        return repr(v)
    if isinstance(v, int):
        return str(v)
    if isinstance(v, str):  # JSON's escapes (\uXXXX, \", \\, \n) are TOML basic-string escapes
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + "}"
    if isinstance(v, list):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    return json.dumps(str(v))


def to_toml(data: dict, prefix: tuple[str, ...] = ()) -> str:
    """TOML text of ``data``: scalars and arrays first, then sub-tables and arrays of tables."""
    lines, later = [], []
    for k, v in data.items():
        if isinstance(v, dict):
            later.append((k, v, False))
        elif isinstance(v, list) and v and all(isinstance(x, dict) for x in v):
            later.append((k, v, True))
        else:
            lines.append(f"{_key(k)} = {_value(v)}")
    text = "\n".join(lines) + ("\n" if lines else "")
    for k, v, many in later:
        path = prefix + (k,)
        head = ".".join(_key(p) for p in path)
        for table in (v if many else [v]):
            text += f"\n[[{head}]]\n" if many else f"\n[{head}]\n"
            text += to_toml(table, path)
    return text


# ---------------------------------------------------------------- mutations
NUMBERS = [0, 0.0, -0.0, -1.0, 1e-300, 5e-324, 1e308, -1e308, 1e15, 1e-15, float("nan"), float("inf"),
           float("-inf"), 10**400, -(10**30), 2**63, "1e400", "nan", "inf", "30deg", "1e400deg", "100rpm",
           "-5 mm", "1e999 m", "0rad/s", "12 furlongs", True]
NAMES = ["\x01ctl", "a\x1fb", "--", "a--b", "<x>", "&amp;", "\"q\"", "Δφ", "名前", "", " ", "x" * 300, "A0", "O",
         "ground", "crank", "\u202eevil", "tab\tname", "new\nline"]
SCALAR_FOR_TABLE = [1.0, "x", [], True, 0]
NEW_KEYS = ["extra", "mass", "length", "omega", "kind", "space", "points", "inertial", "drive", "title", "teeth"]


def _leaves(node, path=()):
    """(path, value) of every leaf and every container below ``node``."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield path + (k,), v
            yield from _leaves(v, path + (k,))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield path + (i,), v
            yield from _leaves(v, path + (i,))


def _set(data, path, value) -> None:
    node = data
    for p in path[:-1]:
        node = node[p]
    node[path[-1]] = value


def _pick(rng, seq):
    return seq[int(rng.integers(0, len(seq)))]


FACTORS = [-1.0, 0.0, 1e-300, 1e-100, 1e-12, 1e-6, 1e-3, 0.5, 0.9, 1.1, 2.0, 1e3, 1e6, 1e12, 1e100, 1e300]


def _scale(x, rng):
    y = float(x) * float(_pick(rng, FACTORS))
    return int(y) if isinstance(x, int) and abs(y) < 1e18 else y


def scale_numbers(data: dict, rng: np.random.Generator) -> tuple[dict, list[str]]:
    """1–2 numbers scaled (by 0 to 1e300, or negated): values of the right type the loader
    will mostly accept, which reach the solvers, the MJCF and the outputs."""
    data = copy.deepcopy(data)
    done = []
    for _ in range(_pick(rng, [1, 1, 2])):
        nums = [(p, v) for p, v in _leaves(data) if isinstance(v, (int, float)) and not isinstance(v, bool)]
        if not nums:
            break
        p, v = _pick(rng, nums)
        new = _scale(v, rng)
        _set(data, p, new)
        done.append(f"scale {'.'.join(map(str, p))}: {v!r} -> {new!r}")
    return data, done


def mutate_tables(data: dict, rng: np.random.Generator) -> tuple[dict, list[str]]:
    """1–3 mutations of the parsed description; returns it and what was done."""
    data = copy.deepcopy(data)
    done = []
    for _ in range(_pick(rng, [1, 1, 1, 2, 2, 3])):  # mostly one: a mutant should often get past the loader
        leaves = list(_leaves(data))
        if not leaves:
            break
        kind = _pick(rng, ["number", "number", "number", "type", "name", "name", "remove", "add"])
        if kind == "number":
            nums = [(p, v) for p, v in leaves if isinstance(v, (int, float)) and not isinstance(v, bool)]
            if not nums:
                continue
            p, v = _pick(rng, nums)
            new = _scale(v, rng) if rng.random() < 0.5 else _pick(rng, NUMBERS)
            _set(data, p, new)
            done.append(f"number {'.'.join(map(str, p))}: {v!r} -> {new!r}")
        elif kind == "type":
            p, v = _pick(rng, leaves)
            if isinstance(v, (dict, list)):
                new = _pick(rng, SCALAR_FOR_TABLE)
            else:
                new = _pick(rng, [[v, v], {"value": v}, [v], str(v)])
            _set(data, p, new)
            done.append(f"type {'.'.join(map(str, p))}: {type(v).__name__} -> {new!r}"[:200])
        elif kind == "name":
            tables = [(p, v) for p, v in [((), data)] + leaves if isinstance(v, dict) and v]
            strings = [(p, v) for p, v in leaves if isinstance(v, str)]
            if strings and rng.random() < 0.4:  # a name or title given as a value
                p, v = _pick(rng, strings)
                others = [s for _, s in strings if s != v]
                new = _pick(rng, others) if others and rng.random() < 0.3 else _pick(rng, NAMES)
                _set(data, p, new)
                done.append(f"name value {'.'.join(map(str, p))}: {v!r} -> {new!r}")
            else:  # a table key renamed (a link, point, joint ... name), sometimes to an existing name
                p, table = _pick(rng, tables)
                old = _pick(rng, list(table))
                names = [str(k) for q, t in leaves if isinstance(t, dict) for k in t]
                new = _pick(rng, names) if rng.random() < 0.3 else _pick(rng, NAMES)
                items = [(new if k == old else k, v) for k, v in table.items()]
                table.clear()
                table.update(items)
                done.append(f"rename {'.'.join(map(str, p + (old,)))} -> {new!r}")
        elif kind == "remove":
            p, _ = _pick(rng, leaves)
            node = data
            for q in p[:-1]:
                node = node[q]
            del node[p[-1]]
            done.append(f"remove {'.'.join(map(str, p))}")
        else:
            tables = [(p, v) for p, v in [((), data)] + leaves if isinstance(v, dict)]
            p, table = _pick(rng, tables)
            k = _pick(rng, NEW_KEYS)
            table[k] = _pick(rng, [1.0, -1.0, "x", [1.0, 2.0], {"a": 1.0}, 1e308])
            done.append(f"add {'.'.join(map(str, p + (k,)))} = {table[k]!r}")
    return data, done


_NUMBER = re.compile(rb"(?<![A-Za-z_\"])-?\d+\.?\d*(?:e-?\d+)?")
TEXT_EXTREMES = [b"1e308", b"-1e308", b"0", b"nan", b"inf", b"-inf", b"9" * 30, b"1e-320", b'"1e400deg"', b"[]",
                 b"{}", b'"x"']


def mutate_text(raw: bytes, rng: np.random.Generator) -> tuple[bytes, list[str]]:
    """The original text (comments and layout kept) with 1–2 numbers replaced, or a span cut."""
    done = []
    for _ in range(int(rng.integers(1, 3))):
        nums = list(_NUMBER.finditer(raw))
        if rng.random() < 0.8 and nums:
            m = _pick(rng, nums)
            new = _pick(rng, TEXT_EXTREMES)
            raw = raw[:m.start()] + new + raw[m.end():]
            done.append(f"text number at byte {m.start()}: {m.group().decode()} -> {new.decode()}")
        else:
            i, j = sorted(int(x) for x in rng.integers(0, max(len(raw), 1), 2))
            raw = raw[:i] + raw[j:]
            done.append(f"text cut bytes {i}:{j}")
    return raw, done


@dataclass(frozen=True)
class Mutant:
    """One input: ``data`` bytes for a regular file, or ``special`` (one of SPECIAL)."""

    index: int
    family: str
    origin: str
    data: bytes
    special: str | None
    what: tuple[str, ...]


def mutant(seed: int, index: int, families: tuple[str, ...] = FAMILIES) -> Mutant:
    """The ``index``-th mutant of run ``seed`` (families taken in turn, models at random)."""
    rng = np.random.default_rng([seed, index])
    family = families[index % len(families)]
    if family == "special":
        kind = _pick(rng, SPECIAL)
        data = bytes(rng.integers(0, 256, 300).astype(np.uint8)) if kind == "binary" else b""
        return Mutant(index, family, kind, data, kind if kind not in ("empty", "binary") else None, (kind,))
    models = [m for m in bundled() if m[0] == family]
    fam, stem, raw = _pick(rng, models)
    r = rng.random()
    if r < 0.15:
        data, what = mutate_text(raw, rng)
    else:
        tables = tomllib.loads(raw.decode())
        tables, what = scale_numbers(tables, rng) if r < 0.55 else mutate_tables(tables, rng)
        data = to_toml(tables).encode("utf-8", "surrogatepass")
    return Mutant(index, family, stem, data, None, tuple(what))


def materialise(m: Mutant, folder: Path) -> Path:
    """The mutant as a path in ``folder`` (a regular file, or the special file it stands for)."""
    if m.special == "dev_zero":
        return Path("/dev/zero")
    path = folder / "model.toml"
    if m.special == "fifo":
        import os

        os.mkfifo(path)
    elif m.special == "folder":
        path.mkdir()
    else:
        path.write_bytes(m.data)
    return path
