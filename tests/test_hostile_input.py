"""Hostile and extreme description files: each loads or raises a DescriptionError naming the
file, the field and what is allowed; physical magnitudes within linkgen.limits give finite,
correctly scaled answers."""

import json
import math
import tomllib

import pytest

from conftest import ROOT
from linkgen import DescriptionError, from_dict, load
from linkgen.cli.main import main
from linkgen.families.planar.kinetostatics import forces

FOURBAR = ROOT / "models" / "fourbar.toml"
# Scaling laws hold to the measured 7e-13 of each quantity's peak (validation/limits_scan.py);
# 1e-11 leaves a margin for the single pose tested here.
SCALING_TOLERANCE = 1e-11


def _write(tmp_path, data: bytes, name="m.toml"):
    path = tmp_path / name
    path.write_bytes(data)
    return path


def _error(path) -> str:
    with pytest.raises(DescriptionError) as info:
        load(path)
    assert info.value.source == str(path)
    return str(info.value)


def test_binary_file(tmp_path):
    path = _write(tmp_path, b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR")
    assert _error(path) == (f"{path}: is not UTF-8 text (byte 0x89 at line 1, offset 0); "
                            "a description is a UTF-8 TOML file")


def test_latin1_file_names_the_line(tmp_path):
    path = _write(tmp_path, "[mechanism]\nname = 'Kurbelschwinge für'\n".encode("latin-1"))
    assert _error(path) == (f"{path}: is not UTF-8 text (byte 0xfc at line 2, offset 36); "
                            "a description is a UTF-8 TOML file")


def test_nul_bytes(tmp_path):
    path = _write(tmp_path, b"[mechanism]\x00\n")
    assert _error(path) == f"{path}: contains NUL bytes: a description is a UTF-8 TOML text file"


def test_byte_order_mark_is_accepted(tmp_path):
    path = _write(tmp_path, b"\xef\xbb\xbf" + FOURBAR.read_bytes())
    assert load(path) == load(FOURBAR)


@pytest.mark.parametrize("text", ["a = " + "[" * 5000 + "]" * 5000, "a = " + "{b = " * 5000 + "1" + "}" * 5000])
def test_deep_nesting(tmp_path, text):
    path = _write(tmp_path, text.encode())
    assert _error(path) == (f"{path}: nested too deeply to parse: a description needs at most a few levels of "
                            "tables and arrays")


def test_deep_value_in_a_field_is_quoted_short(tmp_path):
    text = FOURBAR.read_text().replace("O = [0.0, 0.0]", "O = " + "[" * 200 + "]" * 200)
    path = _write(tmp_path, text.encode())
    assert _error(path) == f"{path}: points.O: must be a list of 2 lengths [x, y], got [[[[...]]]]"


def test_huge_bad_name_is_quoted_short(tmp_path):
    # a name of a million characters that is not a name: the message quotes its beginning, once
    # in the field (its first 60 characters of the 1000008 of 'points.<name>') and once as the
    # value, and says how long it is
    name = "9" + "a" * 10**6
    text = FOURBAR.read_text().replace("O = [0.0, 0.0]", f"O = [0.0, 0.0]\n{name} = [1.0, 1.0]")
    path = _write(tmp_path, text.encode())
    message = _error(path)
    assert message == (f"{path}: points.9{'a' * 52}... (999948 more characters): must be a name of letters, digits "
                       f"and '_' not starting with a digit, got '9{'a' * 26}...{'a' * 28}' (1000001 characters)")


def test_integer_beyond_float_range(tmp_path):
    text = FOURBAR.read_text().replace("omega = 10.0", "omega = " + "9" * 400)
    path = _write(tmp_path, text.encode())
    assert _error(path).startswith(f"{path}: drive.omega: must be finite, got 999999999")


def test_folder_as_a_description(tmp_path):
    assert _error(tmp_path) == f"{tmp_path}: is a folder; give one description file"


def test_device_instead_of_a_file():
    assert _error("/dev/zero") == "/dev/zero: is not a regular file (a device, pipe or socket); give a description file"


def test_file_too_large(tmp_path):
    from linkgen.families.planar.reader import MAX_FILE_BYTES

    path = tmp_path / "big.toml"
    with open(path, "wb") as f:
        f.truncate(MAX_FILE_BYTES + 1)  # sparse: no disk space used
    assert _error(path) == f"{path}: is 67108865 bytes; a description is at most 67108864 bytes"


def _scaled(s: float = 1.0, mu: float = 1.0, w: float = 1.0) -> dict:
    """The four-bar with lengths ×s, masses ×mu and rates ×w (its links are uniform bars)."""
    d = tomllib.loads(FOURBAR.read_text())
    d["points"] = {k: [x * s for x in v] for k, v in d["points"].items()}
    for link in d["links"].values():
        if "length" in link:
            link["length"] *= s
        if "density" in link:
            link["density"] *= mu / s
    d["mechanism"]["gravity"] = [g * s * w * w for g in d["mechanism"]["gravity"]]
    d["drive"]["omega"] *= w
    return d


@pytest.mark.parametrize("s, message", [
    # the bounding box of O, A, B, C: 1.0143 × 0.6999 (times s), diagonal 1.23234...
    (1e-300, "points: the sketch spans 1.23234...e-300 m; linkgen needs 1e-90..1e+12 m (its limits, see the README)"),
    (1e300, "points.A[0]: must be within ±1e+12 m (linkgen's limits, see the README), got 3e+299"),
])
def test_geometry_scaled_out_of_range(s, message):
    with pytest.raises(DescriptionError) as info:
        from_dict(_scaled(s, mu=s))  # masses scaled too: only the length is out of range
    head, _, tail = message.partition("...")
    assert str(info.value).startswith(head) and str(info.value).endswith(tail)


@pytest.mark.parametrize("edit, message", [
    (("omega = 10.0", "omega = 1.3e154"),
     "drive.omega: must be within ±1e+30 rad/s (linkgen's limits, see the README), got 1.3e+154"),
    (("omega = 10.0", "omega = 10.0\nepsilon = -1e61"),
     "drive.epsilon: must be within ±1e+60 rad/s² (linkgen's limits, see the README), got -1e+61"),
    (("gravity = [0.0, -9.81]", "gravity = [0.0, -1e73]"),
     "mechanism.gravity[1]: must be within ±1e+72 m/s² (linkgen's limits, see the README), got -1e+73"),
    (("density = 10.0    # uniform bar, kg/m", "density = 1e-15"),
     "links.crank.density: mass 3e-16 kg (density × length = 1e-15 kg/m × 0.3 m) is outside 1e-15..1e+30 kg "
     "(MuJoCo's smallest body mass and linkgen's limits, see the README)"),
    (("[links.rocker]\npoints = [\"C\", \"B\"]\nlength = 0.7\ndensity = 10.0",
      "[links.rocker]\npoints = [\"C\", \"B\"]\nlength = 0.7\ninertial = { mass = 1e31, com = [0.35, 0.0], "
      "inertia = 1.0 }"),
     "links.rocker.inertial.mass: mass 1e+31 kg (as given) is outside 1e-15..1e+30 kg "
     "(MuJoCo's smallest body mass and linkgen's limits, see the README)"),
    (("omega = 10.0", "omega = 10.0\n[[force]]\nlink = \"rocker\"\npoint = \"B\"\nforce = [1e103, 0.0]"),
     "force[0].force[0]: must be within ±1e+102 N (linkgen's limits, see the README), got 1e+103"),
    (("omega = 10.0", "omega = 10.0\n[[torque]]\nlink = \"rocker\"\ntorque = -2e114"),
     "torque[0].torque: must be within ±1e+114 N·m (linkgen's limits, see the README), got -2e+114"),
    (("omega = 10.0", "omega = 10.0\nrange = [1e5, 100001.0]"),
     "drive.range[0]: must be within ±10000 rad (linkgen's limits, see the README), got 100000.0"),
])
def test_magnitudes_beyond_the_limits(tmp_path, edit, message):
    text = FOURBAR.read_text()
    assert edit[0] in text
    path = _write(tmp_path, text.replace(*edit).encode())
    assert _error(path) == f"{path}: {message}"


def test_default_mass_of_a_tiny_link_is_named(tmp_path):
    data = _scaled(1e-16)
    for name in ("crank", "coupler", "rocker"):
        del data["links"][name]["density"]
    with pytest.raises(DescriptionError) as info:
        from_dict(data)
    assert str(info.value) == ("links.crank: mass 3e-17 kg (the default bar of 1 kg/m × 3e-17 m (give inertial or "
                               "density)) is outside 1e-15..1e+30 kg (MuJoCo's smallest body mass and linkgen's "
                               "limits, see the README)")


# (1e11, 1e29, 1e29): size 1.2e11 m, masses up to 1e30 kg, ω = 1e30 rad/s, gravity 1e70 m/s²;
# (1e-89, 1e-15, 1.0): size 1.2e-89 m, the lightest link 3e-15 kg.
@pytest.mark.parametrize("s, mu, w", [(1e11, 1e29, 1e29), (1e-89, 1e-15, 1.0)])
def test_corners_of_the_limits_scale_exactly(s, mu, w):
    """At the largest (and smallest) allowed sizes and masses the closed form is finite and obeys
    the scaling laws: reactions ×mu·s·w², balancing torque ×mu·s²·w², reduced inertia ×mu·s²."""
    ref_mech, mech = from_dict(_scaled()), from_dict(_scaled(s, mu, w))
    assert mech.drive.omega == pytest.approx(10.0 * w, rel=1e-15)
    phi = [0.0, 1.0, 2.0, 4.0]
    ref = forces(ref_mech, phi, ref_mech.drive.omega)
    got = forces(mech, phi, mech.drive.omega)

    def check(value, reference, factors):
        back = value
        for f in factors:  # undo the scale factor by factor: their product may leave float range
            back = back / f
        peak = float(abs(reference).max())
        assert float(abs(back - reference).max()) <= SCALING_TOLERANCE * peak

    check(got.balancing_torque, ref.balancing_torque, (mu, s, s, w, w))
    check(got.reduced.inertia, ref.reduced.inertia, (mu, s, s))
    for k in ref.reactions:
        check(got.reactions[k], ref.reactions[k], (mu, s, w, w))


@pytest.mark.parametrize("option, value, message", [
    ("--omega", "1.3e154", "expected a number within ±1e+30 rad/s (linkgen's limits, see the README), got '1.3e154'"),
    ("--epsilon", "-inf", "expected a number in rad/s² or one with its unit (e.g. 60rpm/s), got '-inf'"),
    ("--omega", "nan", "expected a number in rad/s or one with its unit (e.g. 100rpm), got 'nan'"),
    ("--omega", "[1, 2]", "expected a number in rad/s or one with its unit (e.g. 100rpm), got '[1, 2]'"),
    ("--samples", "1000001", "expected a whole number from 1 to 1000000, got '1000001'"),
])
def test_rates_on_the_command_line(capsys, option, value, message):
    with pytest.raises(SystemExit) as info:
        main(["forces", str(FOURBAR), f"{option}={value}", "--json"])
    assert info.value.code == 2
    captured = capsys.readouterr()
    assert captured.err == f"linkgen forces: error: argument {option}: {message} (see linkgen forces --help)\n"
    assert captured.out == ""


def test_json_at_the_largest_rates_is_strict_and_finite(capsys):
    assert main(["forces", str(FOURBAR), "--omega", "1e30", "--epsilon=-1e60", "--json"]) == 0

    def reject(token):
        raise AssertionError(f"non-JSON constant {token}")

    out = json.loads(capsys.readouterr().out, parse_constant=reject)
    assert math.isfinite(out["balancing_torque"]) and abs(out["balancing_torque"]) > 1e50


def test_non_finite_result_is_never_printed(capsys):
    from linkgen.cli.common import print_json

    with pytest.raises(Exception) as info:
        print_json({"points": {"O": {"acceleration": [0.0, float("-inf")]}}})
    assert str(info.value) == ("the result is not finite at points.O.acceleration[1] (the computation overflowed "
                               "or hit a singular position); nothing was printed")
    assert capsys.readouterr().out == ""


def test_random_mutants_of_the_models_fail_cleanly():
    """300 random byte-level mutants of the bundled models (validation/fuzz_files.py runs more):
    each loads and solves with finite forces, or fails with a LinkgenError; load errors name the file."""
    import sys

    sys.path.insert(0, str(ROOT / "validation"))
    try:
        from fuzz_files import main as fuzz
    finally:
        sys.path.pop(0)
    assert fuzz(300, 3) == 0
