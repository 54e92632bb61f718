"""``linkgen assemble``: a rough sketch is placed exactly from the link lengths, and --write puts
it back into the file keeping everything else."""

import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from linkgen import load
from linkgen.families.planar.description import GROUND
from linkgen.families.planar.sketch import exact_sketch

ROOT = Path(__file__).resolve().parents[1]
from conftest import MODELS  # linkages (cam files have tests of their own)
# Lengths after assembly against the given ones: a few roundings of the closed form.
LENGTH_TOL = 1e-12


def _movable(mech):
    """Moving points whose every carrier has its shape from `length` (two points) or is a block:
    moving them changes no link's shape. The crank's points are left: they set the crank angle; so
    are a planet gear's: they set its phase against the crank, which the sketch gives."""
    ground = set(mech.link(GROUND).points) | set(mech.link(mech.crank).points)
    ground |= {p for planet in mech.planets for p in mech.link(planet).points}
    out = []
    for p in mech.points:
        carriers = [l for l in mech.links if p in l.points]
        if p not in ground and all(len(l.points) == 1 or (len(l.points) == 2 and l.length is not None)
                                   for l in carriers):
            out.append(p)
    return out


@pytest.mark.parametrize("path", MODELS, ids=[p.stem for p in MODELS])
def test_a_rough_sketch_assembles_to_the_exact_one(path, tmp_path):
    mech = load(path)
    movable = _movable(mech)
    if not movable:
        return  # nothing in this model can be moved without changing a link's shape
    exact = exact_sketch(mech)
    size = max(np.ptp(np.array(list(mech.points.values())), axis=0))
    rng = np.random.default_rng(len(path.stem))
    text = path.read_text()
    for p in movable:  # move each by 10 % of the sketch's size
        x, y = exact.points[p]
        d = 0.1 * size * np.array([math.cos(a := rng.uniform(0, 2 * math.pi)), math.sin(a)])
        text, n = re.subn(rf"(?m)^{p}\s*=\s*\[[^\]]*\]", f"{p} = [{float(x + d[0])!r}, {float(y + d[1])!r}]", text)
        assert n == 1
    rough = tmp_path / path.name
    rough.write_text(text)
    p = subprocess.run([sys.executable, "-m", "linkgen", "assemble", str(rough), "--write"], capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    back = load(rough)  # loads: its sketch is within the tolerance again
    for name in movable:
        assert np.hypot(*(np.array(back.points[name]) - exact.points[name])) < 1e-9 * size
    for link in back.links:
        if link.length is not None:
            a, b = (np.array(back.points[q]) for q in link.points)
            assert abs(np.hypot(*(b - a)) - link.length) <= LENGTH_TOL * max(link.length, 1.0)
    # everything but the lines of the points it placed is as the user wrote it
    placed = set(movable) | {q for q, d in exact.moved.items() if d > 0}
    keep = [line for line in path.read_text().splitlines() if not any(re.match(rf"{q}\s*=", line) for q in placed)]
    assert keep == [line for line in rough.read_text().splitlines()
                    if not any(re.match(rf"{q}\s*=", line) for q in placed)]


def test_lengths_that_do_not_close_name_the_group(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text((ROOT / "models" / "fourbar.toml").read_text().replace("length = 0.7\n", "length = 0.05\n"))
    p = subprocess.run([sys.executable, "-m", "linkgen", "assemble", str(bad)], capture_output=True, text=True)
    assert p.returncode == 2 and "II(2,3)" in p.stderr and "Traceback" not in p.stderr


def test_printing_leaves_the_file_alone(tmp_path):
    f = tmp_path / "f.toml"
    f.write_text((ROOT / "models" / "fourbar.toml").read_text())
    before = f.read_text()
    p = subprocess.run([sys.executable, "-m", "linkgen", "assemble", str(f), "--angle", "30deg"], capture_output=True,
                       text=True)
    assert p.returncode == 0 and "[points]" in p.stdout and f.read_text() == before
