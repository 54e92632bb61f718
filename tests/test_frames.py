"""Animations and MuJoCo frames of cams and spatial four-bars from the command line."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
from PIL import Image

from conftest import ROOT

MODELS = ROOT / "models"


def run(*args):
    return subprocess.run([sys.executable, "-m", "linkgen", *map(str, args)], capture_output=True, text=True, cwd=ROOT)


def _red(path) -> np.ndarray:
    """Pixels of the crank's (the cam's) material: red over the grey floor."""
    with Image.open(path) as im:
        img = np.asarray(im.convert("RGB")).astype(float)
    return (img[:, :, 0] > 170) & (img[:, :, 1] < 120) & (img[:, :, 2] < 110)


def test_spatial_and_cam_animations_have_their_frames(tmp_path):
    for model, frames in (("bennett", 4), ("cam_translating", 5)):
        out = tmp_path / f"{model}.gif"
        p = run("animate", MODELS / f"{model}.toml", "--frames", frames, "-o", out)
        assert p.returncode == 0, p.stderr
        with Image.open(out) as im:
            assert im.format == "GIF" and im.n_frames == frames and im.is_animated


def test_spatial_and_cam_frames_turn_with_the_crank(tmp_path):
    """The crank (the cam) is drawn in its red material, and a quarter turn moves it on the image."""
    for model in ("rssr", "cam_oscillating"):
        shots = []
        for angle in ("0deg", "90deg"):
            out = tmp_path / f"{model}_{angle}.png"
            p = run("render", MODELS / f"{model}.toml", "--angle", angle, "-o", out)
            assert p.returncode == 0, p.stderr
            with Image.open(out) as im:
                assert im.size == (800, 600)
            shots.append(_red(out))
        assert shots[0].sum() > 20 and shots[1].sum() > 20, model
        centres = [np.argwhere(s).mean(axis=0) for s in shots]
        if model == "rssr":  # a bar turning about its pivot: its pixels' centre moves
            assert np.hypot(*(centres[1] - centres[0])) > 5.0
        else:  # the cam turns about its axis: its outline changes
            assert (shots[0] ^ shots[1]).sum() > 100


def test_mujoco_beside_the_drawing_is_refused_in_one_line_for_a_spatial_model(tmp_path):
    p = run("animate", MODELS / "rssr.toml", "--mujoco", "-o", tmp_path / "x.gif")
    assert p.returncode == 2 and "render" in p.stderr and "Traceback" not in p.stderr
    assert len(p.stderr.strip().splitlines()) == 1
