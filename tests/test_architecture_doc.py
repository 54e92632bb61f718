"""docs/architecture.md says what the code does: its table of stages is the layout test's order
and every stage package exists; its table of families is the registry's (title, description
type, commands), in the registry's order."""

from __future__ import annotations

import re
from pathlib import Path

import linkgen
from linkgen.pipeline.registry import FAMILIES

ROOT = Path(__file__).resolve().parents[1]
DOC = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")


def _rows(marker: str) -> list[list[str]]:
    block = re.search(rf"<!-- {marker}:.*?-->\n(.*?)<!-- /{marker} -->", DOC, flags=re.S)
    assert block, marker
    lines = [ln for ln in block.group(1).splitlines() if ln.startswith("|")][2:]  # past the header and rule
    return [[c.strip() for c in ln.strip("|").split("|")] for ln in lines]


def test_the_stage_table_is_the_layout_tests_order():
    import test_layout

    rows = _rows("stages")
    assert [r[0] for r in rows] == ["bottom", *test_layout.STAGES], [r[0] for r in rows]
    pkg = Path(linkgen.__file__).parent
    for stage, packages, _ in rows:
        for name in re.findall(r"`([^`]+)`", packages):
            assert (pkg / name).exists(), (stage, name)


def test_the_family_table_is_the_registry():
    rows = _rows("families")
    assert len(rows) == len(FAMILIES)
    for (title, description, _, commands), fam in zip(rows, FAMILIES):
        assert title == fam.title
        assert description == f"`{fam.description.__name__}` ({fam.doc})"
        assert [c.strip() for c in commands.split(",")] == list(fam.commands)
        assert (ROOT / fam.doc).is_file(), fam.doc
