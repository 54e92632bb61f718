"""TOML text from a TOML-shaped dict (tomllib reads but does not write)."""

from __future__ import annotations

import json
import math


def _string(s: str) -> str:
    """A TOML basic string: JSON's escapes are TOML's, but TOML also forbids a raw DEL."""
    return json.dumps(s, ensure_ascii=False).replace("\x7f", "\\u007f")


def _value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        if isinstance(v, float) and not math.isfinite(v):
            return "nan" if v != v else ("inf" if v > 0 else "-inf")
        return repr(v)
    if isinstance(v, str):
        return _string(v)
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_key(k)} = {_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(f"cannot write {type(v).__name__} as TOML")


def _key(k: str) -> str:
    return k if k and all(c.isalnum() and c.isascii() or c in "_-" for c in k) else _string(k)


def _is_tables(v) -> bool:
    return isinstance(v, list) and bool(v) and all(isinstance(x, dict) for x in v)


def _table(lines: list[str], path: list[str], table: dict, header: str | None) -> None:
    simple = [(k, v) for k, v in table.items() if not isinstance(v, dict) and not _is_tables(v)]
    if header is not None and (simple or not table or header.startswith("[[")):
        lines += ["", header]  # a table holding only sub-tables needs no header of its own
    for k, v in simple:
        lines.append(f"{_key(k)} = {_value(v)}")
    for k, v in table.items():
        sub = path + [_key(k)]
        if isinstance(v, dict):
            _table(lines, sub, v, f"[{'.'.join(sub)}]")
        elif _is_tables(v):
            for item in v:
                _table(lines, sub, item, f"[[{'.'.join(sub)}]]")


def to_toml(desc: dict) -> str:
    """TOML text that ``tomllib`` reads back as ``desc`` (floats written exactly by repr)."""
    lines: list[str] = []
    _table(lines, [], desc, None)
    return "\n".join(lines).lstrip("\n") + "\n"


__all__ = ["to_toml"]
