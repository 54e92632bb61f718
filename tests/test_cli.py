"""The command line as a user meets it (runs the installed entry point's code in-process)."""

import json
import math

import pytest

from conftest import ROOT
from linkgen.cli import main

MODELS = ROOT / "models"


def test_analyze_seven_link_json(capsys):
    assert main(["analyze", str(MODELS / "seven_link.toml"), "--angle", "38.117deg", "--omega", "4", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == {"points", "links", "sliders"}
    assert set(out["points"]) == {"O", "A", "G", "B", "C", "E", "F"}
    assert set(out["links"]) == {"ground", "crank", "block", "rocker", "rod", "slider", "coupler", "lever"}
    assert set(out["sliders"]) == {"block", "slider"}
    a = out["points"]["A"]
    # the crank pin by hand: OA·(cos, sin)(38.117°), v = ω·OA, a = ω²·OA towards O
    phi = math.radians(38.117)
    assert a["position"] == pytest.approx([0.1716 * math.cos(phi), 0.1716 * math.sin(phi)], abs=1e-15)
    assert math.hypot(*a["velocity"]) == pytest.approx(4 * 0.1716, rel=1e-14)
    assert math.hypot(*a["acceleration"]) == pytest.approx(16 * 0.1716, rel=1e-14)
    # the slider stays on y = 0, the rocker's angular velocity is the block's
    assert out["points"]["C"]["position"][1] == pytest.approx(0.0, abs=1e-15)
    assert out["links"]["block"]["angular_velocity"] == pytest.approx(out["links"]["rocker"]["angular_velocity"],
                                                                      rel=1e-14)


def test_analyze_angle_in_radians_equals_degrees(capsys):
    main(["analyze", str(MODELS / "fourbar.toml"), "--angle", "0.5", "--json"])
    rad = json.loads(capsys.readouterr().out)
    main(["analyze", str(MODELS / "fourbar.toml"), "--angle", f"{math.degrees(0.5)!r}deg", "--json"])
    deg = json.loads(capsys.readouterr().out)
    assert rad["points"]["B"]["position"] == pytest.approx(deg["points"]["B"]["position"], abs=1e-15)


def test_analyze_csv_over_a_revolution(tmp_path, capsys):
    out = tmp_path / "fb.csv"
    assert main(["analyze", str(MODELS / "fourbar.toml"), "--samples", "360", "--csv", str(out)]) == 0
    lines = out.read_text().splitlines()
    assert len(lines) == 361
    assert lines[0].startswith("phi,O.position.x,O.position.y,")


def test_structure_prints_the_formula(capsys):
    assert main(["structure", str(MODELS / "g123.toml")]) == 0
    out = capsys.readouterr().out
    assert "structure formula: I(0,1) → II(2,3) → II(4,5) → II(6,7)" in out
    assert "group II(2,3) RRR [coupler, rocker]" in out


def test_user_errors_exit_2_without_traceback(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text("[mechanism]\nname = 'x'\n")
    assert main(["analyze", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err == f"linkgen: error: {bad}: description.drive: is required\n"
    assert main(["analyze", str(MODELS / "seven_link.toml"), "--angle", "180deg"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"linkgen: error: {MODELS / 'seven_link.toml'}: group ")
    assert "cannot be assembled at crank angles 180.000°" in err


@pytest.mark.parametrize("command", ["structure", "analyze", "forces", "build", "simulate", "validate"])
def test_every_command_names_the_file(tmp_path, capsys, command):
    bad = tmp_path / "bad.toml"
    bad.write_bytes(b"\x00\x01\x02\xff")
    assert main([command, str(bad)]) == 2
    assert capsys.readouterr().err == (f"linkgen: error: {bad}: is not UTF-8 text (byte 0xff at line 1, offset 3); "
                                       "a description is a UTF-8 TOML file\n")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml"]
