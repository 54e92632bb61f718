"""What a user reads when something is refused or fails, found by auditing issue 21 as a new and a
hostile user would: every line names the file, the field, the value and what is allowed, in the
same words for every family, and nothing crashes on a description the loader accepts."""

import math
import shutil
from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT
from linkgen.cli.main import main
from linkgen.crosscheck.spatial import SpatialCheck

MODELS = ROOT / "models"


def _variant(tmp_path: Path, model: str, old: str, new: str, name: str | None = None) -> Path:
    """A bundled model with one piece of its text replaced (``old`` must occur once)."""
    text = (MODELS / model).read_text(encoding="utf-8")
    assert text.count(old) == 1, old
    path = tmp_path / (name or model)
    path.write_text(text.replace(old, new), encoding="utf-8")
    return path


def test_validate_says_why_when_no_run_compared_anything(tmp_path, capsys):
    # before: "run: – (tolerance 0) at : run failed — omega must be …", the same text again under
    # "tried", and in the report a row saying "run failed" with no section giving the reason
    path = _variant(tmp_path, "fourbar.toml", "omega = 10.0      # rad/s", "omega = -10.0")
    report = tmp_path / "report"
    assert main(["validate", str(path), "--no-practical", "--report", str(report)]) == 1
    why = "drive.omega: must be > 0 rad/s for a MuJoCo run (it drives the crank forwards through its range), got -10.0"
    assert capsys.readouterr().out.splitlines()[:3] == [
        "fourbar                FAIL",
        f"    run failed: {why}",
        "    tried: derived settings → failed as above",
    ]
    text = (report / "README.md").read_text(encoding="utf-8")
    assert "| fourbar | **NO** | run failed |" in text
    assert (f"## fourbar\n\nNo prediction before the run: the settings were not derived from the closed form (no scan of "
            f"the loop forces).\n\n**Diagnosis**\n\n- run failed: {why}\n") in text


@pytest.mark.parametrize("omega", ["0.0", "-10.0"])
def test_a_spatial_run_names_drive_omega(tmp_path, capsys, omega):
    # before: "rssr: omega must be > 0 rad/s to drive the crank" (the mechanism, not the field)
    path = _variant(tmp_path, "rssr.toml", "omega = 10.0 ", f"omega = {omega} ")
    assert main(["validate", str(path)]) == 2
    assert capsys.readouterr().err == (f"linkgen: error: {path}: drive.omega: must be > 0 rad/s for a MuJoCo run (it "
                                       f"drives the crank forwards through a turn), got {omega}\n")


def test_build_of_a_folder_reports_every_family_in_order(tmp_path, capsys):
    # before: a cam's and a spatial file's "wrote" went to stdout, a linkage's and the errors to
    # stderr, so a mixed folder's log came out of order
    for name, model in (("a.toml", "fourbar.toml"), ("b.toml", "cam_flat_face.toml"), ("c.toml", "rssr.toml")):
        shutil.copy(MODELS / model, tmp_path / name)
    (tmp_path / "d.toml").write_text("x = [", encoding="utf-8")
    assert main(["build", str(tmp_path)]) == 2
    out, err = capsys.readouterr()
    assert out == ""
    assert err.splitlines() == [f"wrote {tmp_path / 'a.xml'}", f"wrote {tmp_path / 'b.xml'}", f"wrote {tmp_path / 'c.xml'}",
                                f"linkgen: error: {tmp_path / 'd.toml'}: not valid TOML: Invalid value (at end of document)",
                                "linkgen: 1 of 4 descriptions failed"]


def test_the_cam_line_gives_each_force_its_own_tolerance():
    # before: "contact force … and cam torque … of their peaks as 5° means (tolerance 0.07)" with the
    # contact force's tolerance for both, though the cam torque is held to its own
    from linkgen.crosscheck.cam import CamCheck

    r = CamCheck("cam", {"errors_relative": {"displacement": 1e-4, "contact_force": 0.05, "cam_torque": 0.075},
                         "profile_points": 4000, "windows": 72, "steps": 100},
                 {"displacement": 2e-4, "contact_force": 0.07, "cam_torque": 0.08})
    assert r.summary("validated in 1.00 s") == (
        "ok   cam in MuJoCo (contact with a 4000-vertex profile): displacement 1.00e-04 of the stroke (tolerance "
        "0.0002), contact force 5.00e-02 (tolerance 0.07) and cam torque 7.50e-02 (tolerance 0.08) of their peaks as "
        "5° means, 100 steps, validated in 1.00 s")


def test_a_cam_csv_counts_cam_angles(tmp_path, capsys):
    # before: "wrote 36 crank angles × 5 columns" for a cam, whose rows are cam angles θ
    cam = MODELS / "cam_translating.toml"
    assert main(["profile", str(cam), "--points", "36", "-o", str(tmp_path / "p.csv")]) == 0
    assert main(["analyze", str(cam), "--samples", "12", "--csv", str(tmp_path / "a.csv")]) == 0
    assert capsys.readouterr().err.splitlines() == [f"wrote 36 cam angles × 5 columns to {tmp_path / 'p.csv'}",
                                                    f"wrote 12 cam angles × 8 columns to {tmp_path / 'a.csv'}"]


@pytest.mark.parametrize("teeth,shown", [("[60.0, 20]", "teeth[0]: must be a whole number written as an integer (60, "
                                                         "not 60.0 or 6e1), got 60.0"),
                                         ("[60, 1e18]", "teeth[1]: must be a whole number written as an integer (60, "
                                                        "not 60.0 or 6e1), got 1e+18"),
                                         ("[60.5, 20]", "teeth[0]: must be a whole number, got 60.5")])
def test_teeth_written_as_floats_are_explained(tmp_path, capsys, teeth, shown):
    # before: "must be a whole number, got 1e+18" — a whole number, which TOML reads as a float
    path = _variant(tmp_path, "planetary_lever.toml", "teeth = [60, 20]", f"teeth = {teeth}")
    assert main(["structure", str(path)]) == 2
    assert capsys.readouterr().err == f"linkgen: error: {path}: gear.mesh.{shown}\n"


@pytest.mark.parametrize("model,what", [
    ("rssr.toml", "a spatial four-bar (docs/spatial.md); `linkgen profile` is for stand-alone cams; spatial four-bars "
                  "take structure, analyze, forces, build, validate, draw, page, animate, render"),
    ("cam_rocker_slider.toml", "a planar linkage (docs/format.md); `linkgen profile` is for stand-alone cams; planar "
                               "linkages take structure, analyze, forces, assemble, build, simulate, validate, "
                               "check-settings, draw, page, animate, render, dynamics, flywheel, sweep, optimize"),
    ("fourbar.toml", "a planar linkage (docs/format.md); `linkgen profile` is for stand-alone cams; planar linkages "
                     "take structure, analyze, forces, assemble, build, simulate, validate, check-settings, draw, page, animate, "
                     "render, dynamics, flywheel, sweep, optimize")])
def test_profile_says_what_it_takes(capsys, model, what):
    # before: a spatial file was told `profile` "is for planar linkages"; a linkage with a [cam.disc]
    # table was told it needs "a [cam] table"
    assert main(["profile", str(MODELS / model)]) == 2
    assert capsys.readouterr().err == f"linkgen: error: {MODELS / model}: {what}\n"  # the registry's one line


@pytest.mark.parametrize("gap,line", [
    (5e-9, "ok   RSSR: worst loop gap 5.00e-09 of the size (tolerance 1e-08), 100 steps, validated in 1.00 s"),
    (2e-8, "FAIL RSSR: worst loop gap 2.00e-08 of the size (tolerance 1e-08), 100 steps, validated in 1.00 s"),
    (1e-10, "ok   RSSR: worst balancing_torque 1.00e-07 (tolerance 1e-06), loop gap 1.0e-10 of the size (tolerance "
            "1e-08), 100 steps, validated in 1.00 s")])
def test_the_spatial_line_reads_like_the_planar_one(gap, line):
    # before: "worst loop gap 5.00e-09 (tolerance 1e-08), loop gap 5.0e-09 of the size (tolerance
    # 1e-08)" — the gap twice — and "FAILED" where every other family says "FAIL"
    r = SpatialCheck("m", "RSSR", {"balancing_torque": (1e-7, 1e-6)}, gap, 100, 9.0, None, {})
    assert r.summary("validated in 1.00 s") == line


@pytest.mark.parametrize("key", ["link", "point"])
def test_a_spatial_load_names_a_list_given_for_a_name(tmp_path, capsys, key):
    # before: "force[0].link: unknown link ['rocker']" (the planar reader: "must be a string")
    value = {"link": '"rocker"', "point": '"B"'}
    value[key] = f"[{value[key]}]"
    path = tmp_path / "m.toml"
    path.write_text((MODELS / "rssr.toml").read_text(encoding="utf-8")
                    + f'\n[[force]]\nlink = {value["link"]}\npoint = {value["point"]}\nforce = [1.0, 0.0, 0.0]\n',
                    encoding="utf-8")
    assert main(["forces", str(path)]) == 2
    shown = "['rocker']" if key == "link" else "['B']"
    assert capsys.readouterr().err == f"linkgen: error: {path}: force[0].{key}: must be a string, got {shown}\n"


def test_a_cam_linkage_standing_still_builds(tmp_path, capsys):
    # before: ZeroDivisionError in the cam's timestep (2π/ω) for drive.omega = 0
    path = _variant(tmp_path, "cam_rocker_slider.toml", "omega = 10.0", "omega = 0.0")
    assert main(["build", str(path), "-o", str(tmp_path / "m.xml")]) == 0
    assert (tmp_path / "m.xml").read_text(encoding="utf-8").startswith("<mujoco")


@pytest.mark.parametrize("omega,ok", [("1e-30", True), ("1e-31", False), ("1e-300", False)])
def test_a_slow_cam_builds_or_is_refused_at_load(tmp_path, capsys, omega, ok):
    # before: ZeroDivisionError for ω = 1e-300 (ω² underflowed in the cam shaft's inertia)
    path = _variant(tmp_path, "cam_oscillating.toml", "omega = 10.0 ", f"omega = {omega} ")
    assert main(["build", str(path), "-o", str(tmp_path / "m.xml")]) == (0 if ok else 2)
    if not ok:
        assert capsys.readouterr().err == (f"linkgen: error: {path}: cam.omega: must be at least 1e-30 rad/s (the cam "
                                           f"turns counter-clockwise; linkgen's limits, see the README), got {omega}\n")


@pytest.mark.parametrize("model,args", [
    ("fourbar.toml", ["build", "{m}", "-o", "{m}"]),
    ("fourbar.toml", ["analyze", "{m}", "--samples", "5", "--csv", "{m}"]),
    ("fourbar.toml", ["forces", "{m}", "--samples", "5", "--csv", "{m}"]),
    ("fourbar.toml", ["build", "{m}", "-o", "{link}"]),
    ("cam_translating.toml", ["analyze", "{m}", "--samples", "5", "--csv", "{m}"]),
    ("rssr.toml", ["analyze", "{m}", "--samples", "5", "--csv", "{m}"]),
    ("rssr.toml", ["build", "{m}", "-o", "{m}"])], ids=lambda v: v if isinstance(v, str) else " ".join(v[:1]))
def test_no_output_replaces_the_description(tmp_path, capsys, model, args):
    # before: each of these replaced the user's description by the output (exit 0)
    suffix = ".xml" if args[0] == "build" else ".csv"  # named as the output's kind: the extension allows it
    path = tmp_path / f"m{suffix}"
    shutil.copy(MODELS / model, path)
    link = tmp_path / f"hard{suffix}"  # the same file under another name
    link.hardlink_to(path)
    before = path.read_bytes()
    out = link if "{link}" in args else path
    assert main([a.format(m=path, link=link) for a in args]) == 2
    assert capsys.readouterr().err.endswith(f"{out}: is the description being read; linkgen does not write over it: "
                                            "give another output name\n")
    assert path.read_bytes() == before


def test_profile_does_not_replace_a_description_named_like_its_output(tmp_path, capsys):
    path = tmp_path / "m.csv"  # -o takes .csv or .json: a description under such a name
    shutil.copy(MODELS / "cam_translating.toml", path)
    before = path.read_bytes()
    assert main(["profile", str(path), "-o", str(path)]) == 2
    assert capsys.readouterr().err.endswith(f"{path}: is the description being read; linkgen does not write over it: "
                                            "give another output name\n")
    assert path.read_bytes() == before


def test_a_description_named_like_its_mjcf_is_not_overwritten(tmp_path, capsys):
    # before: `build m.xml` wrote the MJCF beside the description under its own name: over it
    path = tmp_path / "m.xml"
    shutil.copy(MODELS / "fourbar.toml", path)
    before = path.read_bytes()
    assert main(["build", str(path)]) == 2
    assert path.read_bytes() == before
    assert main(["build", str(path), "-o", str(tmp_path / "out.xml")]) == 0  # the next command may write
    assert (tmp_path / "out.xml").read_text(encoding="utf-8").startswith("<mujoco")


def test_build_leaves_no_mujoco_log_in_the_working_directory(tmp_path, monkeypatch):
    # before: deriving the settings stepped MuJoCo outside no_log_file: for this cam linkage with a
    # rod a million kilometres long, MuJoCo's warnings (a near-singular inertia matrix) were
    # appended to MUJOCO_LOG.TXT in the user's working directory
    path = _variant(tmp_path, "cam_rocker_slider.toml", "E = [0.6938143274617465, 0.45]", "E = [1e9, 0.45]")
    monkeypatch.chdir(tmp_path)
    assert main(["build", str(path), "-o", str(tmp_path / "m.xml")]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cam_rocker_slider.toml", "m.xml"]


@pytest.mark.parametrize("command", [["analyze"], ["build"], ["profile"]])
def test_a_file_name_with_control_characters_is_shown_by_their_codes(tmp_path, capsys, command):
    # before: the name went to the terminal raw: the escape recoloured it, the line end split the message
    path = tmp_path / "evil\x1b[31mred\nline.toml"
    path.write_text("x = [", encoding="utf-8")
    assert main(command + [str(path)]) == 2
    assert capsys.readouterr().err == (f"linkgen: error: {tmp_path}/evil\\x1b[31mred\\x0aline.toml: not valid TOML: "
                                       "Invalid value (at end of document)\n")


def test_simulate_out_names_the_option_not_the_description(tmp_path, capsys):
    # before: "linkgen: error: …/fourbar.toml: --out: …" — the description blamed for an option
    assert main(["simulate", str(MODELS / "fourbar.toml"), "--out", str(tmp_path / "run.txt")]) == 2
    assert capsys.readouterr().err == (f"linkgen simulate: error: -o/--out {tmp_path / 'run.txt'}: `linkgen simulate` "
                                       "writes .npz (the sampled arrays) or .csv (the samples as columns with their "
                                       "units); got .txt\n")


@pytest.mark.parametrize("args,message", [
    (["render", "--width", "0"], "linkgen render: error: argument --width: expected a whole number from 16 to 1280, got '0'"),
    (["render", "--height", "961"], "linkgen render: error: argument --height: expected a whole number from 16 to 960, "
                                    "got '961'"),
    (["animate", "--frames", "1"], "linkgen animate: error: argument --frames: expected a whole number from 2 to 2000, "
                                   "got '1'")])
def test_picture_sizes_are_refused_with_the_range_they_allow(tmp_path, capsys, args, message):
    # before: the options took 1 to 1000000, then the run refused 0 px or 1 frame with another range,
    # blaming the description ("…/fourbar.toml: frames must be 2..2000, got 1")
    with pytest.raises(SystemExit) as exit_:
        main([args[0], str(MODELS / "fourbar.toml"), "-o", str(tmp_path / "x.png")] + args[1:])
    assert exit_.value.code == 2
    assert capsys.readouterr().err.splitlines()[-1].startswith(message)


def test_a_report_refuses_two_files_of_one_mechanism_name(tmp_path, capsys):
    # before: both ran and wrote fourbar_*.png into the report, the second over the first, and the
    # report showed one model's figures under both rows
    shutil.copy(MODELS / "fourbar.toml", tmp_path / "a.toml")
    _variant(tmp_path, "fourbar.toml", "omega = 10.0      # rad/s", "omega = 5.0", name="b.toml")
    assert main(["validate", str(tmp_path), "--report", str(tmp_path / "report")]) == 2
    assert capsys.readouterr().err == (
        f"linkgen validate: error: {tmp_path / 'a.toml'} and {tmp_path / 'b.toml'} both name their mechanism "
        "'fourbar': the report names its figures and sections after it, so one would overwrite the other's; give "
        "them different [mechanism] names, or validate them into separate -o/--out folders\n")
    assert not (tmp_path / "report").exists()


@pytest.mark.parametrize("axis", ["[0.0, 1e9, 1.0]", "[0.0, 1e12, 1.0]", "[0.0, 1.0, 1e-9]"])
def test_nearly_parallel_4r_axes_are_a_clear_refusal(tmp_path, capsys, axis):
    # before: numpy's LinAlgError "Singular matrix" traceback in every command: the common normal of
    # two axes 1e-9 rad apart solved a 2×2 system whose determinant 1 − cos² rounds to exactly 0
    path = _variant(tmp_path, "bennett.toml", "axis = [0.0, 0.0, 1.0]", f"axis = {axis}")
    assert main(["structure", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"linkgen: error: {path}: bennett: the four revolutes A0, A, B, B0 are neither parallel, nor "
                          "meet at one point, nor make a Bennett linkage")
    assert err.count("\n") == 1


def test_the_common_normal_of_nearly_parallel_lines():
    from linkgen.families.spatial.chain import common_normal

    # two lines 1e-9 rad apart, 1 m from each other along y: the common normal runs along y
    # (expected by hand: the lines x-axis and (0, 1, 0) + s·(1, 0, 1e-9)/|·| meet the normal where
    # z = 0, i.e. at x = 0 on both)
    u2 = np.array([1.0, 0.0, 1e-9]) / math.hypot(1.0, 1e-9)
    a, alpha, f1, f2 = common_normal(np.zeros(3), np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0]), u2)
    np.testing.assert_allclose([a, abs(alpha)], [1.0, 1e-9], rtol=1e-9)  # rtol: float64 rounding of the 1e-9 twist
    np.testing.assert_allclose(f1, [0.0, 0.0, 0.0], atol=1e-12)
    np.testing.assert_allclose(f2, [0.0, 1.0, 0.0], atol=1e-12)
