"""What a student reads on a forces drawing. Two pairs at one point acting on one link (Andrews' squeezer: rocker_5 and rocker_7 both
pinned to the ground at A; rod_4, rod_6 and the lever at the coupler's E) drew two arrows under
one label, "R_A on ground" twice: each now names the link it comes from. Where every force is
zero (a balanced rotor without gravity: dc_motor_startup) the drawing said "1 m of drawing =
1 N" under no arrow: it now says that they are all zero."""

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


def test_a_drawing_of_forces_that_are_all_zero_says_so():
    from linkgen.draw.plan import plt_module
    from linkgen.draw.teaching import teaching_figure
    from linkgen.draw.vectors import force_arrows

    # dc_motor_startup.toml: one rotor on its axis, its centre of mass on it, no gravity: R_O = 0
    asm = assemble(load(ROOT / "models" / "dc_motor_startup.toml"))
    arrows = force_arrows(asm, 0.0)
    fig, _, mu = teaching_figure(asm, 0.0, arrows=arrows)
    texts = [t.get_text() for t in fig.axes[0].texts]
    plt_module().close(fig)
    assert mu is None
    assert any(t.startswith("forces: every one zero here") for t in texts), texts
    assert not any("1 m of drawing" in t for t in texts), texts
