"""The pictures follow their model's input: a prismatic input (a planar linkage's slide drive, a
PSSR/PSSP chain's slider) is a stroke s [m] at ṡ [m/s]. The interactive page samples it over the
description's [drive] start..stop and its slider, curves' axis and balancing load speak of s,
metres and a force [N]; the skeleton's and the plans' titles and the design summary say s and ṡ
(they said φ = 45.84° and ω = 0.1 rad/s for s = 0.8 m). A crank's keep φ, degrees and ω."""

import numpy as np
import pytest

from conftest import ROOT
from linkgen.draw.page import PIN_TRACE, SLIDER_TRACE, page_figure
from linkgen.pipeline.registry import load

FRAMES = 5
# [drive] start, stop [m] as written in the model files (pssr.toml, pssp.toml: from the sketch;
# hydraulic_boom.toml: the cylinder's length).
STROKES = {"pssr": (-0.1, 0.1), "pssp": (-0.1, 0.1), "hydraulic_boom": (0.8, 1.05)}
# linspace of the written ends, against the page's own: a few ulps of the ends.
ULPS = 1e-12


def _data(name: str):
    from linkgen.draw.page_families import spatial_page
    from linkgen.draw.page_planar import planar_page
    from linkgen.families.planar.assembly import assemble

    desc = load(ROOT / "models" / f"{name}.toml")
    return spatial_page(desc, FRAMES) if hasattr(desc, "drive") and getattr(desc.drive, "slides", False) \
        else planar_page(assemble(desc), FRAMES)


@pytest.mark.parametrize("name", sorted(STROKES))
def test_a_prismatic_inputs_page_samples_its_strokes_in_metres(name):
    data = _data(name)
    np.testing.assert_allclose(data.phi, np.linspace(*STROKES[name], FRAMES), rtol=0.0, atol=ULPS)
    assert data.stroke
    assert "balancing force [N]" in data.curves and not any("torque" in c for c in data.curves)
    fig = page_figure(data)
    names = [t.name for t in fig.data]
    assert SLIDER_TRACE in names and PIN_TRACE not in names  # no crank pin on a slider's page
    assert not any(c.startswith("lift ") for c in data.curves)  # hydraulic_boom's driven pair: s itself
    layout = fig.layout
    assert layout.xaxis2.title.text == "s [m]"
    slider = layout.sliders[0]
    assert slider.currentvalue.prefix == "s = "
    assert [s.label for s in slider.steps] == [f"{x:.4g} m" for x in np.linspace(*STROKES[name], FRAMES)]


def test_the_page_command_words_a_stroke_and_a_crank(tmp_path, capsys):
    from linkgen.cli.main import main

    for model, said in (("hydraulic_boom", "5 stroke positions s [m]"), ("pssr", "5 stroke positions s [m]"),
                        ("fourbar", "5 crank angles")):
        assert main(["page", str(ROOT / "models" / f"{model}.toml"), "--frames", "5", "-o",
                     str(tmp_path / f"{model}.html")]) == 0
        out = capsys.readouterr().out
        assert said in out, out
    data = _data("fourbar")
    fig = page_figure(data)
    assert PIN_TRACE in [t.name for t in fig.data]
    layout = fig.layout
    assert not data.stroke and "balancing torque [N·m]" in data.curves
    assert layout.xaxis2.title.text == "φ [°]" and layout.sliders[0].currentvalue.prefix == "φ = "
    assert layout.sliders[0].steps[1].label == "72°"  # a turn in 5: every 72°


def test_a_stroke_drawing_says_s_and_its_speed_not_an_angle():
    from linkgen.draw.polygons import spatial_plan_figure, vector_plan_figure
    from linkgen.draw.plan import plt_module
    from linkgen.draw.teaching import summary_lines, teaching_figure
    from linkgen.families.planar.assembly import assemble
    from linkgen.families.planar.summary import summarize
    from linkgen.families.planar.vector_plan import vector_plan
    from linkgen.families.spatial.plans import spatial_plan

    plt = plt_module()
    boom = assemble(load(ROOT / "models" / "hydraulic_boom.toml"))
    s0 = STROKES["hydraulic_boom"][0]
    fig, _, _ = teaching_figure(boom, s0)
    title = fig._suptitle.get_text()
    plt.close(fig)
    assert "s = 0.8 m, ṡ = 0.1 m/s" in title and "φ" not in title and "rad" not in title, title
    fig, _ = vector_plan_figure(boom.mechanism, vector_plan(boom, s0, "acceleration"))
    title = fig.axes[0].get_title()
    plt.close(fig)
    assert "plan at s = 0.8 m, ṡ = 0.1 m/s, s̈ = 0 m/s²" in title and "φ" not in title, title
    where = [line for line in summary_lines(summarize(boom)) if " at " in line]
    assert where and all(" at s = " in line and line.endswith(" m") for line in where), where
    pssr = load(ROOT / "models" / "pssr.toml")
    fig, _ = spatial_plan_figure(pssr, spatial_plan(pssr, 0.05, "velocity"))
    title = fig._suptitle.get_text()
    plt.close(fig)
    assert "plan at s = 0.05 m, ṡ = 0.5 m/s" in title and "φ" not in title, title
    fourbar = assemble(load(ROOT / "models" / "fourbar.toml"))
    fig, _, _ = teaching_figure(fourbar, np.radians(30.0))
    title = fig._suptitle.get_text()
    plt.close(fig)
    assert "φ = 30°, ω = 10 rad/s" in title, title


# MuJoCo's curve against the closed form's on the page: one pixel of a 300-px plot is 1/300 of
# its range (test_teaching_pictures' MUJOCO_CURVE); a curve on the wrong axis (s read as an
# angle) or a missing balancing force fails.
MUJOCO_CURVE = 1.0 / 300.0


def test_a_stroke_pages_mujoco_curves_lie_on_the_closed_forms():
    from linkgen.draw.page_planar import mujoco_curves, planar_page
    from linkgen.families.planar.assembly import assemble
    from linkgen.mujoco.simulate import simulate

    asm = assemble(load(ROOT / "models" / "hydraulic_boom.toml"))
    data = planar_page(asm, 24)
    theirs = mujoco_curves(data, simulate(asm, samples=60).samples)
    assert set(theirs) == set(data.curves) == {"boom angle [°]", "balancing force [N]"}
    fine = planar_page(asm, 720)
    for label, (s, values) in theirs.items():
        lo, hi = STROKES["hydraulic_boom"]  # MuJoCo's strokes on the range, to a pixel of the s axis
        assert lo - MUJOCO_CURVE * (hi - lo) <= s.min() and s.max() <= hi + MUJOCO_CURVE * (hi - lo), label
        ours = np.interp(s, fine.phi, fine.curves[label])
        assert float(np.max(np.abs(values - ours))) <= MUJOCO_CURVE * float(np.ptp(fine.curves[label])), label
