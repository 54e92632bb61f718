"""NaN and inf in what a command printed or wrote (validation/fuzz_cli.py): a number token
``nan``/``inf`` in text and JSON, in a CSV row not marked singular, in an MJCF or SVG attribute
made of numbers (not in a name), in an .npz array."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np

_TOKEN = re.compile(r"(?<![A-Za-z_])[-+]?(?:nan|inf(?:inity)?)(?![A-Za-z_])", re.IGNORECASE)
_ATTR = re.compile(r'([\w:-]+)="([^"]*)"')
# Attributes holding names (the description's, free text) rather than numbers.
_NAMED = {"name", "class", "childclass", "id", "joint", "joint1", "joint2", "body", "body1", "body2", "site", "geom1",
          "geom2", "mesh", "material", "texture", "objname", "target", "actuator", "tendon", "href", "xlink:href"}


def text_non_finite(text: str) -> str | None:
    m = _TOKEN.search(text)
    return None if m is None else f"{m.group()!r} in {text[max(0, m.start() - 60):m.end() + 20]!r}"


def _csv_non_finite(text: str) -> str | None:
    lines = text.splitlines()
    if not lines:
        return None
    head = lines[0].split(",")
    sing = next((i for i, h in enumerate(head) if h.strip().startswith("singular")), None)
    for line in lines[1:]:
        cells = line.split(",")
        if sing is not None and sing < len(cells) and cells[sing].strip() == "1":
            continue  # a singular sample is written marked; its values are documented as meaningless
        bad = text_non_finite(line)
        if bad:
            return bad
    return None


def _markup_non_finite(text: str) -> str | None:
    """NaN/inf in an attribute value made of numbers (MJCF, SVG), not in names."""
    for m in _ATTR.finditer(text):
        if m.group(1) in _NAMED:
            continue
        toks = m.group(2).replace(",", " ").split()
        if toks and all(re.fullmatch(r"[-+0-9.eE]+|[-+]?(?:nan|inf(?:inity)?)", t, re.IGNORECASE) for t in toks):
            bad = text_non_finite(f'{m.group(1)}="{m.group(2)}"')
            if bad:
                return bad
    return None


def output_non_finite(path: Path) -> str | None:
    """The first NaN/inf in an output file, or None."""
    try:
        if path.suffix == ".npz":
            with np.load(path, allow_pickle=False) as z:
                for k in z.files:
                    a = z[k]
                    if a.dtype.kind in "fc" and not np.all(np.isfinite(a)):
                        return f"{path.name}[{k}] non-finite"
            return None
        if path.suffix in (".csv", ".json", ".xml", ".svg"):
            text = path.read_text(encoding="utf-8", errors="replace")
            check = {".csv": _csv_non_finite, ".json": text_non_finite}.get(path.suffix, _markup_non_finite)
            bad = check(text)
            return f"{path.name}: {bad}" if bad else None
    except (OSError, ValueError) as exc:
        return f"{path.name} unreadable: {exc}"
    return None
