"""The interactive page follows its model's input: a prismatic input (a planar linkage's slide
drive, a PSSR/PSSP chain's slider) is sampled over its strokes s [m] from the description's
[drive] start..stop, and its slider, curves' axis and balancing load speak of s, metres and a
force [N]; a crank's page keeps φ, degrees and a torque [N·m]."""

import numpy as np
import pytest

from conftest import ROOT
from linkgen.draw.page import page_figure
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
    layout = page_figure(data).layout
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
    layout = page_figure(data).layout
    assert not data.stroke and "balancing torque [N·m]" in data.curves
    assert layout.xaxis2.title.text == "φ [°]" and layout.sliders[0].currentvalue.prefix == "φ = "
    assert layout.sliders[0].steps[1].label == "72°"  # a turn in 5: every 72°
