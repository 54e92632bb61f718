"""``linkgen validate --engine mjwarp`` (linkgen.mujoco.float32): the float32 tolerances from
their stated derivation, and the refusals — MuJoCo Warp missing (it is an optional extra, ~410 MB
with warp-lang, not in `test`: a fresh clone's `make test` runs without it), a family that is not
a planar linkage, a report folder."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from linkgen.errors import SimulationError

ROOT = Path(__file__).resolve().parents[1]
# float32's machine epsilon, 2^-23 (IEEE 754 binary32), written out rather than read from numpy.
EPS32 = 2.0**-23


def test_tolerances_follow_their_derivation():
    from linkgen.mujoco.float32 import tolerances

    # size 2 m, dt 50 µs, τ 1 ms (20 steps), accelerations' scale 200 m/s²: gap 2·eps32·20 = 40·eps32
    # of the size, times the factor 3 of issue 30's predictions; force gap·size/(τ²·a) times 3
    t = tolerances(2.0, 5e-5, 1e-3, 200.0)
    assert t["loop_gap"] == pytest.approx(3 * 40 * EPS32, rel=1e-12)
    assert t["constraint_force"] == pytest.approx(3 * 40 * EPS32 * 2.0 / (1e-6 * 200.0), rel=1e-12)
    # a time constant shorter than a step piles up no more than one step's rounding
    assert tolerances(1.0, 1e-3, 1e-4, 10.0)["loop_gap"] == pytest.approx(3 * 2 * EPS32, rel=1e-12)


def test_missing_mujoco_warp_is_refused_with_how_to_install(monkeypatch):
    from linkgen.mujoco import float32

    monkeypatch.setitem(sys.modules, "mujoco_warp", None)  # import fails as if not installed
    with pytest.raises(SimulationError, match=r"--engine mjwarp needs MuJoCo Warp, which is not installed .*"
                                              r"pip install 'linkgen\[mjwarp\]'"):
        float32.engine()


def _cli(*args):
    return subprocess.run([sys.executable, "-m", "linkgen", "validate", *args], capture_output=True, text=True,
                          cwd=ROOT, timeout=120)


def test_a_cam_is_refused_naming_the_family():
    r = _cli("models/cam_translating.toml", "--engine", "mjwarp")
    assert r.returncode == 2, r.stderr
    assert "models/cam_translating.toml: --engine mjwarp runs planar linkages" in r.stderr
    assert "this is a stand-alone cam" in r.stderr and "Traceback" not in r.stderr


def test_a_report_folder_is_refused(tmp_path):
    r = _cli("models/fourbar.toml", "--engine", "mjwarp", "-o", str(tmp_path / "rep"))
    assert r.returncode == 2 and "--engine mjwarp prints its comparison" in r.stderr, r.stderr
    assert not (tmp_path / "rep").exists()
