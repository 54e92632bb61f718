"""The command line as a user meets it, through the console script: version, angles that need
a unit, negative values, units on rates, JSON and CSV that say what they hold, transfer
functions, and a report that goes where the user says."""

import csv
import io
import json
import math
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
FOURBAR = ROOT / "models" / "fourbar.toml"
SCRIPT = shutil.which("linkgen", path=str(Path(sys.executable).parent))
# Transfer functions against central differences of the printed positions (step 1e-6 rad):
# truncation ~1e-12, rounding of positions ~1e-16/1e-6.
FD_TOL = 1e-8


def run(*args, cwd=None):
    return subprocess.run([SCRIPT, *map(str, args)], capture_output=True, text=True, timeout=300, cwd=cwd)


def test_the_console_script_is_installed():
    assert SCRIPT is not None


def test_version():
    p = run("--version")
    assert p.returncode == 0 and p.stdout.startswith("linkgen ") and p.stdout.strip() != "linkgen"


def test_an_angle_without_a_unit_is_an_error_that_suggests_one():
    p = run("analyze", FOURBAR, "--angle", "30")
    assert p.returncode == 2 and "30deg" in p.stderr and "30rad" in p.stderr and "Traceback" not in p.stderr


@pytest.mark.parametrize("angle", ["30deg", "30°", f"{math.radians(30)!r}rad"])
def test_angle_units_agree(angle):
    out = json.loads(run("analyze", FOURBAR, "--angle", angle, "--json").stdout)
    assert out["phi"] == pytest.approx(math.radians(30), rel=1e-15)


def test_negative_values_with_units():
    out = json.loads(run("analyze", FOURBAR, "--angle", "-30deg", "--omega", "-100rpm", "--json").stdout)
    assert out["phi"] == pytest.approx(-math.radians(30)) and out["omega"] == pytest.approx(-100 * 2 * math.pi / 60)


def test_json_says_what_it_holds():
    out = json.loads(run("forces", FOURBAR, "--angle", "10deg", "--json").stdout)
    a = json.loads(run("analyze", FOURBAR, "--angle", "10deg", "--json").stdout)
    assert {"model", "phi", "omega", "epsilon", "units"} <= set(a)
    assert a["model"] == "fourbar" and a["units"]["velocity"] == "m/s"
    assert "balancing_torque" in out and out["model"] == "fourbar" and out["phi"] == pytest.approx(math.radians(10))
    assert out["units"]["force"] == "N" and out["omega"] == 10.0


def test_csv_headers_carry_units():
    p = run("analyze", FOURBAR, "--samples", "4")
    header = next(csv.reader(io.StringIO(p.stdout)))
    assert header[:3] == ["phi [rad]", "singular", "O.position.x [m]"]
    assert "rocker.angular_acceleration [rad/s²]" in header
    f = run("forces", FOURBAR, "--samples", "4")
    assert "balancing_torque [N·m]" in next(csv.reader(io.StringIO(f.stdout)))


def test_transfer_functions_against_differences_of_positions():
    phi, h = 0.7, 1e-6

    def pos(x):
        return json.loads(run("analyze", FOURBAR, "--angle", f"{x!r}rad", "--json").stdout)["points"]["B"]["position"]

    out = json.loads(run("analyze", FOURBAR, "--angle", f"{phi!r}rad", "--json", "--transfer").stdout)
    d1 = (np.array(pos(phi + h)) - np.array(pos(phi - h))) / (2 * h)
    d2 = (np.array(pos(phi + h)) - 2 * np.array(pos(phi)) + np.array(pos(phi - h))) / h**2
    assert np.abs(d1 - out["points"]["B"]["d1"]).max() < FD_TOL
    assert np.abs(d2 - out["points"]["B"]["d2"]).max() < 1e-3  # second difference: ~eps/h²
    text = run("analyze", FOURBAR, "--angle", "40deg", "--transfer").stdout
    assert "transfer functions" in text and "d/dφ" in text


def test_report_goes_where_the_user_says_for_one_file(tmp_path):
    work = tmp_path / "work"
    work.mkdir()
    p = run("validate", FOURBAR, "--report", tmp_path / "rep", "--no-practical", cwd=work)
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "rep" / "README.md").is_file() and (tmp_path / "rep" / "fourbar_kinematics.png").is_file()
    assert list(work.iterdir()) == []  # nothing in the working directory


def test_every_option_says_its_unit_or_that_it_has_none():
    words = ("[", "deg", "rad", "no unit", "file", "FILE", "SI units", "folder", "print", "JSON", "also", "skip", "exit", "default",
             "e.g.")
    for cmd in ("analyze", "forces", "simulate", "validate", "dynamics", "flywheel", "build", "draw", "page", "animate",
                "render"):
        text = run(cmd, "--help").stdout
        opts = text.split("options:")[1]
        entries = [e for e in opts.split("\n  -") if e.strip() and not e.strip().startswith("h, --help")]
        for e in entries:
            assert any(w in e for w in words), (cmd, e)
