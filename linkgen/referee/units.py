"""Units of a results table's headers: ``name [unit]`` → the name, the unit's factor to SI and
its SI spelling as linkgen writes it (``mm/s²`` → 1e-3, ``m/s²``; ``deg`` → π/180, ``rad``;
``rpm`` → 2π/60, ``rad/s``; ``kN·m`` → 1e3, ``N·m``).

A unit is symbols joined by ``·`` (or ``*``) and at most one ``/``, each symbol with an optional
power (``s²``, ``s^2``, ``s2``). Symbols: lengths m, cm, mm; angles rad, deg, °; time s, ms, min;
forces N, kN; mass kg, g; power W, kW; and rpm (one revolution per minute)."""

from __future__ import annotations

import math
import re

# symbol → (factor to SI, SI symbol); an empty SI symbol is a plain number.
SYMBOLS = {"m": (1.0, "m"), "cm": (1e-2, "m"), "mm": (1e-3, "m"), "rad": (1.0, "rad"),
           "deg": (math.pi / 180, "rad"), "°": (math.pi / 180, "rad"), "s": (1.0, "s"), "ms": (1e-3, "s"),
           "min": (60.0, "s"), "N": (1.0, "N"), "kN": (1e3, "N"), "kg": (1.0, "kg"), "g": (1e-3, "kg"),
           "W": (1.0, "W"), "kW": (1e3, "W")}
_POWERS = {"²": 2, "³": 3, "⁴": 4}
_SUPER = {2: "²", 3: "³", 4: "⁴"}
_HEADER = re.compile(r"^\s*(.*?)\s*\[\s*([^\[\]]*?)\s*\]\s*$")
_TOKEN = re.compile(r"^([A-Za-z°]+)(?:\^?([234])|([²³⁴]))?$")


class UnitError(ValueError):
    """A unit this module cannot read (the message says what it can)."""


def split_header(header: str) -> tuple[str, str | None]:
    """``"B.position.x [mm]"`` → ``("B.position.x", "mm")``; a header without brackets has no unit."""
    m = _HEADER.match(header)
    if m is None:
        return header.strip(), None
    return m.group(1), m.group(2)


def _factors(part: str) -> tuple[float, dict[str, int]]:
    factor, dims = 1.0, {}
    for token in re.split(r"[·*]", part):
        token = token.strip()
        if token in ("", "1"):
            continue
        if token == "rpm":  # one turn per minute
            factor *= 2 * math.pi / 60
            dims["rad"] = dims.get("rad", 0) + 1
            dims["s"] = dims.get("s", 0) - 1
            continue
        m = _TOKEN.match(token)
        if m is None or m.group(1) not in SYMBOLS:
            raise UnitError(f"unknown unit symbol {token!r} (known: {', '.join(SYMBOLS)}, rpm)")
        power = int(m.group(2) or _POWERS.get(m.group(3) or "", 1))
        f, si = SYMBOLS[m.group(1)]
        factor *= f ** power
        dims[si] = dims.get(si, 0) + power
    return factor, dims


def to_si(unit: str) -> tuple[float, str]:
    """The factor that takes a value in ``unit`` to SI, and the SI unit as linkgen spells it in
    its CSV headers (``m/s²``, ``N·m``, ``kg·m²/rad``, ``rad/rad``)."""
    text = unit.strip().replace("**", "^")
    if text.count("/") > 1:
        raise UnitError(f"{unit!r}: at most one '/' (e.g. m/s², N·m, kg·m²/rad)")
    top, _, bottom = text.partition("/")
    f_top, d_top = _factors(top)
    f_bottom, d_bottom = _factors(bottom)
    for k, v in list(d_top.items()):  # rpm's per second goes below the line: rpm/s → rad/s²
        if v < 0:
            d_bottom[k] = d_bottom.get(k, 0) - v
            d_top[k] = 0
    below = _spell(d_bottom)
    return f_top / f_bottom, _spell(d_top) + (f"/{below}" if below != "1" else "")


_ORDER = ("kg", "N", "m", "rad", "W", "s")


def _spell(dims: dict[str, int]) -> str:
    # top and bottom are spelled apart: a transfer function's rad/rad stays as linkgen writes it
    names = sorted((k for k, v in dims.items() if v), key=_ORDER.index)
    if not names:
        return "1"
    return "·".join(k + (_SUPER.get(dims[k], str(dims[k])) if dims[k] != 1 else "") for k in names)
