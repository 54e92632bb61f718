"""`validate --max-steps` holds for every family: a run past the budget is refused before its
first step, naming the steps it needs (one turn at the model's own timestep)."""

from __future__ import annotations

import math
import re
import subprocess
import sys
from pathlib import Path

import pytest
from lxml import etree

MODELS = Path(__file__).resolve().parent.parent / "models"
BUDGET = 1000  # far below one turn of any bundled model (every one takes > 10^4 steps)


@pytest.mark.parametrize("name", ["bennett", "cam_translating", "cam_rocker_slider"])
def test_a_run_past_the_step_budget_is_refused(name, tmp_path):
    r = subprocess.run([sys.executable, "-m", "linkgen", "validate", str(MODELS / f"{name}.toml"),
                        "--max-steps", str(BUDGET)], capture_output=True, text=True, cwd=tmp_path, timeout=120)
    assert r.returncode != 0, r.stdout
    m = re.search(r"needs (\d+) MuJoCo steps of ([0-9.e+-]+) s, past the step budget of (\d+)", r.stderr)
    assert m, r.stderr
    steps, budget = int(m.group(1)), int(m.group(3))
    assert budget == BUDGET and steps > BUDGET
    assert len(r.stderr.strip().splitlines()) == 1, r.stderr
    assert not list(tmp_path.iterdir())  # refused before anything was written


def test_the_steps_named_are_one_turn_and_a_lead_at_the_files_timestep(tmp_path):
    """The stand-alone cam: the bundled MJCF's timestep and the crank speed give the turn's steps
    independently of the run (a lead of an eighth of a turn settles the contact first)."""
    dt = float(etree.parse(str(MODELS / "cam_translating.xml")).find("option").get("timestep"))
    import tomllib

    omega = tomllib.loads((MODELS / "cam_translating.toml").read_text())["cam"]["omega"]
    per_turn = round(2 * math.pi / omega / dt)
    r = subprocess.run([sys.executable, "-m", "linkgen", "validate", str(MODELS / "cam_translating.toml"),
                        "--max-steps", str(BUDGET)], capture_output=True, text=True, cwd=tmp_path, timeout=120)
    steps = int(re.search(r"needs (\d+) MuJoCo steps", r.stderr).group(1))
    assert steps == per_turn + per_turn // 8
