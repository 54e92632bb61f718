"""The report's figures: one file per figure, legends that never cover a curve, and a sensible
axis for a quantity that does not change."""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pytest  # noqa: E402
from PIL import Image  # noqa: E402

from linkgen import assemble, load  # noqa: E402
from linkgen.report import figures  # noqa: E402
from linkgen.crosscheck.run import crosscheck  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def scotch_yoke():
    return crosscheck(assemble(load(ROOT / "models" / "scotch_yoke.toml")), practical=False).comparison


def test_every_figure_is_written_and_readable(scotch_yoke, tmp_path):
    names = figures.plot_model(scotch_yoke, tmp_path)
    assert names == ["scotch_yoke_paths.png", "scotch_yoke_kinematics.png", "scotch_yoke_forces.png"]
    for n in names:
        with Image.open(tmp_path / n) as im:
            assert im.format == "PNG" and im.size[0] >= 600 and im.size[1] >= 400
            assert len(np.unique(np.asarray(im.convert("L")))) > 10  # not a blank canvas


def test_legends_sit_outside_the_axes(scotch_yoke, tmp_path, monkeypatch):
    seen = []
    real_close = plt.close

    def keep(fig):
        seen.append(fig)

    monkeypatch.setattr(plt, "close", keep)
    figures.plot_forces(scotch_yoke, tmp_path / "f.png")
    figures.plot_kinematics(scotch_yoke, tmp_path / "k.png")
    assert len(seen) == 2
    for fig in seen:
        fig.canvas.draw()
        renderer = fig.canvas.get_renderer()
        for ax in fig.axes:
            leg = ax.get_legend()
            if leg is None:
                continue
            assert leg.get_window_extent(renderer).x0 >= ax.get_window_extent(renderer).x1 - 1e-6
        real_close(fig)


def test_a_flat_quantity_gets_an_axis_of_its_scale_not_of_its_rounding():
    fig, ax = plt.subplots()
    flat = np.full(50, 0.003) + 1e-17 * np.arange(50)
    ax.plot(flat)
    figures._flat_limits(ax, [flat], scale=np.pi)
    lo, hi = ax.get_ylim()
    assert hi - lo == pytest.approx(2 * figures.FLAT_SPAN * np.pi)
    moving = np.linspace(0.0, 1.0, 50)
    ax2 = fig.add_subplot(2, 1, 2)
    ax2.plot(moving)
    before = ax2.get_ylim()
    figures._flat_limits(ax2, [moving], scale=1.0)
    assert ax2.get_ylim() == before
    plt.close(fig)


def test_the_report_gives_the_prediction_and_the_status(validated):
    # Issue 30: the prediction made before the run, and the verdict, are in the report as in the JSON.
    from linkgen.report.sections import linkage_section

    r = validated("fourbar").to_dict() | {"total_wall_s": 1.0}
    text = "\n".join(linkage_section(r))
    assert "**Prediction before the run** (status: ok): predicted to pass" in text
    assert "Measured: gap " in text


def test_the_report_says_loops_came_apart_as_predicted(tmp_path):
    # Fidelity corpus seed 195: its loops need 8e8 steps a turn; at a 50 000-step budget they come
    # apart, as predicted before the run.
    import subprocess
    import sys

    data = Path(__file__).resolve().parent / "data" / "slow_crank_apart.toml"
    proc = subprocess.run([sys.executable, "-m", "linkgen", "validate", str(data), "--max-steps", "50000", "-o",
                           str(tmp_path / "report")], capture_output=True, text=True, timeout=300)
    assert proc.returncode == 1, proc.stderr
    text = (tmp_path / "report" / "README.md").read_text()
    assert "| slow_crank_apart | **NO** (explained, as predicted) |" in text
    assert "predicted to come apart" in text and "The run stopped before any comparison." in text
