"""The command line as a user meets it (runs the installed entry point's code in-process)."""

import json
import math

import pytest

from conftest import ROOT
from linkgen.cli.main import main

MODELS = ROOT / "models"


def test_analyze_seven_link_json(capsys):
    assert main(["analyze", str(MODELS / "seven_link.toml"), "--angle", "38.117deg", "--omega", "4", "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert set(out) == {"model", "phi", "omega", "epsilon", "units", "points", "links", "sliders"}
    assert out["model"] == "seven_link" and out["omega"] == 4.0 and out["epsilon"] == 0.0
    assert out["phi"] == 38.117 * 3.141592653589793 / 180 and out["units"]["acceleration"] == "m/s²"
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
    main(["analyze", str(MODELS / "fourbar.toml"), "--angle", "0.5rad", "--json"])
    rad = json.loads(capsys.readouterr().out)
    main(["analyze", str(MODELS / "fourbar.toml"), "--angle", f"{math.degrees(0.5)!r}deg", "--json"])
    deg = json.loads(capsys.readouterr().out)
    assert rad["points"]["B"]["position"] == pytest.approx(deg["points"]["B"]["position"], abs=1e-15)


def test_analyze_csv_over_a_revolution(tmp_path, capsys):
    out = tmp_path / "fb.csv"
    assert main(["analyze", str(MODELS / "fourbar.toml"), "--samples", "360", "--csv", str(out)]) == 0
    lines = out.read_text().splitlines()
    assert len(lines) == 361
    assert lines[0].startswith("phi [rad],singular,O.position.x [m],O.position.y [m],")
    assert {line.split(",")[1] for line in lines[1:]} == {"0"}  # the four-bar has no singular pose


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


GROUP = "II(2,3) PRP [block, slider]"  # the tangent mechanism's one group
CAUSE = "its two guides are (nearly) parallel"


def _tangent(tmp_path, drive_range: str):
    """The tangent mechanism (x_B = 0.2 m / tan φ, singular where sin φ = 0) over ``drive_range``."""
    text = (MODELS / "tangent_prp.toml").read_text()
    assert 'range = ["40deg", "140deg"]' in text
    path = tmp_path / "tangent.toml"
    path.write_text(text.replace('range = ["40deg", "140deg"]', f"range = {drive_range}"))
    return path


def _rows(path):
    lines = path.read_text().splitlines()
    head = lines[0].split(",")
    return [dict(zip(head, line.split(","))) for line in lines[1:]]


@pytest.mark.parametrize("command", ["analyze", "forces"])
def test_sampled_run_marks_singular_samples(tmp_path, capsys, command):
    # 0°..180° in 1° steps: by hand the slot is parallel to the guide (sin φ = 0) at 0° and 180° only;
    # the next samples have sin 1° = 0.017, far above SINGULAR_TOL = 1e-4.
    model, out = _tangent(tmp_path, '["0deg", "180deg"]'), tmp_path / "s.csv"
    assert main([command, str(model), "--samples", "181", "--csv", str(out)]) == 3
    err = capsys.readouterr().err.splitlines()
    assert err[-1] == (f"linkgen: error: {model}: group {GROUP} is singular at crank angles 0.000°, 180.000° "
                       f"(2 of 181 samples: {CAUSE}); marked singular = 1 in the output, every other value in "
                       "those rows set to 0 (exit status 3; --keep-singular accepts them)")
    rows = _rows(out)
    assert [i for i, r in enumerate(rows) if r["singular"] == "1"] == [0, 180]
    assert {r["singular"] for r in rows} == {"0", "1"}
    for r in rows:
        assert all(math.isfinite(float(v)) for v in r.values())
    if command == "analyze":  # the rows in between are ordinary: x_B = h / tan φ by hand
        phi = float(rows[60]["phi [rad]"])
        assert float(rows[60]["B.position.x [m]"]) == pytest.approx(0.2 / math.tan(phi), rel=1e-12)
    else:
        assert float(rows[0]["balancing_torque [N·m]"]) == 0.0 and float(rows[60]["balancing_torque [N·m]"]) != 0.0
    # asked to keep them: the same file, a warning and status 0
    first = out.read_text()
    assert main([command, str(model), "--samples", "181", "--csv", str(out), "--keep-singular"]) == 0
    err = capsys.readouterr().err.splitlines()
    assert err[-1].startswith(f"linkgen: warning: {model}: group {GROUP} is singular at crank angles 0.000°, 180.000°")
    assert err[-1].endswith("(kept: --keep-singular)")
    assert out.read_text() == first


def test_near_singular_forces_are_no_longer_answered(tmp_path, capsys):
    # The reported case: at a transfer-function denominator of 1e-16 `linkgen forces` printed a
    # balancing torque of -2.3e78 N·m with a warning and exit status 0.
    tangent = MODELS / "tangent_prp.toml"
    assert main(["forces", str(tangent), "--angle", "1e-16rad"]) == 2
    captured = capsys.readouterr()
    assert captured.out == ""
    assert captured.err == (f"linkgen: error: {tangent}: group {GROUP} is singular at crank angles 0.000°: {CAUSE} "
                            "(normalised transfer-function denominator below SINGULAR_TOL = 0.0001; transfer "
                            "functions grow as its inverse)\n")
    assert main(["analyze", str(tangent), "--angle", "1e-16rad", "--json"]) == 2
    assert capsys.readouterr().err == captured.err
    # sampled from that angle on: the sample is marked, every number finite, status 3
    model = _tangent(tmp_path, "[1e-16, 3.0]")
    assert main(["forces", str(model), "--samples", "5"]) == 3
    captured = capsys.readouterr()
    lines = captured.out.splitlines()
    head = lines[0].split(",")
    rows = [dict(zip(head, line.split(","))) for line in lines[1:]]
    assert [r["singular"] for r in rows] == ["1", "0", "0", "0", "0"] and float(rows[0]["phi [rad]"]) == 1e-16
    # the largest, at 3.0 rad, is 1.1e3 N·m; the old answer at 1e-16 was -2.3e78 N·m
    assert all(abs(float(r["balancing_torque [N·m]"])) < 1e4 for r in rows)
    assert captured.err.endswith(f"group {GROUP} is singular at crank angles 0.000° (1 of 5 samples: {CAUSE}); "
                                 "marked singular = 1 in the output, every other value in those rows set to 0 "
                                 "(exit status 3; --keep-singular accepts them)\n")


@pytest.mark.parametrize("options", [[], ["--angle", "1rad"], ["--json"]])
def test_keep_singular_is_for_samples(tmp_path, capsys, monkeypatch, options):
    monkeypatch.chdir(tmp_path)
    assert main(["forces", str(MODELS / "fourbar.toml"), "--keep-singular", *options]) == 2
    assert capsys.readouterr().err == ("linkgen forces: error: --keep-singular is for samples (--samples, -o FILE.csv); "
                                       "at one crank angle a singular position is an error\n")
    assert list(tmp_path.iterdir()) == []
