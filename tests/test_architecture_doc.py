"""docs/architecture.md says what the code does: its table of stages is the layout test's order
and every stage package exists; its table of families is the registry's (title, description
type, commands), in the registry's order; its table of the family interface is
pipeline/family.py's STAGES (every stage, its call, what it returns, when it is required)."""

from __future__ import annotations

import re
from pathlib import Path

import linkgen
from linkgen.api import FUNCTIONS
from linkgen.pipeline.family import STAGES
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


def test_the_interface_table_is_every_stage_of_the_interface():
    # before: the doc listed ten stage names and no calls; angles, figures, report and profile,
    # which a new family needs, were missing
    rows = _rows("interface")
    want = [[f"`{s.name}`", f"`{s.name}{s.call}`", s.returns.replace("``", "`"), ", ".join(s.needed_by)]
            for s in STAGES]
    assert rows == want


def test_the_doc_names_every_function_of_the_api():
    for name in FUNCTIONS:
        assert f"`linkgen.{name}`" in DOC, name
