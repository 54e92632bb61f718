"""Two pairs at one point acting on one link (Andrews' squeezer: rocker_5 and rocker_7 both
pinned to the ground at A; rod_4, rod_6 and the lever at the coupler's E) drew two arrows under
one label, "R_A on ground" twice: each now names the link it comes from."""

import math

from conftest import ROOT
from linkgen.families.planar.assembly import assemble
from linkgen.pipeline.registry import load


def test_reactions_at_one_point_on_one_link_name_where_they_come_from():
    from linkgen.draw.vectors import force_arrows

    asm = assemble(load(ROOT / "models" / "andrews_squeezer.toml"))
    labels = [a.label for a in force_arrows(asm, math.radians(45.0)).arrows if a.kind == "reaction"]
    assert len(labels) == len(set(labels)), labels
    # the model's [links.rocker_5] and [links.rocker_7] both hold A, a ground point
    assert {"R_A on ground from rocker_5", "R_A on ground from rocker_7"} <= set(labels), labels
    assert "R_O on ground" in labels  # a pair alone at its point keeps the short label
