"""The command line says what it accepts and accepts what it says: one output option whose
format comes from the extension for every command (one message style for what is refused), the
hidden earlier spellings meaning no more than -o, one parser for every --omega, refusals that
say what is allowed, simulate's samples named as analyze and forces name them, and help texts
generated from what the registry's families take."""

from __future__ import annotations

import csv
import io
import json
import math
import re
import shutil
from pathlib import Path

import numpy as np
import pytest

from linkgen.cli.main import build_parser, main
from linkgen.pipeline.registry import FAMILIES

ROOT = Path(__file__).resolve().parents[1]
MODELS = ROOT / "models"
FOURBAR = str(MODELS / "fourbar.toml")
# 120 rpm → rad/s: a product and a quotient in float64, each within half an ulp (1.1e-16 relative).
RPM_TOL = 1e-15

# (command and its options, the -o value, the extension as the message gives it)
REFUSED = [
    (["build", FOURBAR], "x.png", ".png"),
    (["build", FOURBAR], "x.txt", ".txt"),
    (["simulate", FOURBAR], "run.txt", ".txt"),
    (["draw", FOURBAR], "d.jpg", ".jpg"),
    (["animate", FOURBAR], "a.png", ".png"),
    (["render", FOURBAR], "r.jpg", ".jpg"),
    (["analyze", FOURBAR], "a.png", ".png"),
    (["forces", FOURBAR, "--samples", "3"], "f.txt", ".txt"),
    (["profile", str(MODELS / "cam_translating.toml")], "p.dat", ".dat"),
    (["validate", FOURBAR], "rep.md", ".md"),
    (["flywheel", str(MODELS / "flywheel_sine.toml"), "--delta", "0.02"], "fw.jpg", ".jpg"),
    (["dynamics", str(MODELS / "flywheel_sine.toml")], "run.txt", ".txt"),
]


@pytest.mark.parametrize("argv,name,suffix", REFUSED, ids=[f"{a[0]}-{n}" for a, n, _ in REFUSED])
def test_every_command_refuses_an_extension_it_does_not_write_in_one_style(tmp_path, capsys, argv, name, suffix):
    # before: build wrote MJCF into x.png; validate made a folder named rep.md; three message styles
    out = tmp_path / name
    assert main([*argv, "-o", str(out)]) == 2
    captured = capsys.readouterr()
    pattern = (rf"linkgen {argv[0]}: error: -o/--out {re.escape(str(out))}: `linkgen {argv[0]}` writes "
               rf"(\.\w+|a folder)[^\n]*\); got {re.escape(suffix)}\n")
    assert re.fullmatch(pattern, captured.err), captured.err
    assert list(tmp_path.iterdir()) == []


def test_the_csv_spelling_writes_csv_only(tmp_path, capsys):
    # before: `analyze --samples 3 --csv x.json` wrote CSV into x.json
    assert main(["analyze", FOURBAR, "--samples", "3", "--csv", str(tmp_path / "x.json")]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"linkgen analyze: error: --csv {tmp_path / 'x.json'}: --csv (the earlier spelling of "
                          "-o/--out) writes .csv") and f"give -o {tmp_path / 'x.json'} to write .json" in err
    assert list(tmp_path.iterdir()) == []


def test_a_folder_builds_into_an_output_folder(tmp_path, capsys):
    # before: "-o/--out writes one model, but 'src' is a folder"
    src = tmp_path / "src"
    src.mkdir()
    for name in ("fourbar.toml", "rssr.toml"):
        shutil.copy(MODELS / name, src / name)
    assert main(["build", str(src), "-o", str(tmp_path / "out")]) == 0
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == ["fourbar.xml", "rssr.xml"]
    assert sorted(p.name for p in src.iterdir()) == ["fourbar.toml", "rssr.toml"]  # nothing beside the sources
    assert main(["build", str(src), "-o", str(tmp_path / "one.xml")]) == 2
    assert "a folder of descriptions" in capsys.readouterr().err and not (tmp_path / "one.xml").exists()


def test_flywheel_writes_its_figure_to_a_file_or_into_a_folder(tmp_path):
    # before: "fw.png: is not a folder" while dynamics took files by their extension
    model = str(MODELS / "flywheel_sine.toml")
    assert main(["flywheel", model, "--delta", "0.02", "-o", str(tmp_path / "fw.png")]) == 0
    assert (tmp_path / "fw.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert main(["flywheel", model, "--delta", "0.02", "-o", str(tmp_path / "figs")]) == 0
    assert [p.name for p in (tmp_path / "figs").iterdir()] == ["flywheel_sine_flywheel.png"]


def test_flywheel_omega_takes_a_unit_as_every_omega(capsys):
    # before: "argument --omega: expected a number, got '120rpm'"
    model = str(MODELS / "flywheel_sine.toml")
    assert main(["flywheel", model, "--delta", "0.02", "--omega", "120rpm", "--json"]) == 0
    given = json.loads(capsys.readouterr().out)
    assert given["omega_mean"] == pytest.approx(120 * 2 * math.pi / 60, rel=RPM_TOL)  # rpm → rad/s by definition
    assert main(["flywheel", model, "--delta", "0.02", "--omega", repr(4 * math.pi), "--json"]) == 0
    assert json.loads(capsys.readouterr().out) == given


@pytest.mark.parametrize("options,allowed", [
    (["--summary", "-o", "s.csv"], ".json (the summary's JSON object"),
    (["--angle", "30deg", "-o", "a.csv"], "--angle evaluates one crank angle (printed, --json, or -o FILE.json)"),
])
def test_a_refusal_says_what_is_allowed(tmp_path, capsys, monkeypatch, options, allowed):
    # before: "--summary … cannot be combined with -o/--out" though -o s.json writes it; "-o/--out
    # [is] for samples over the drive range" though --angle 30deg -o a.json writes one state
    monkeypatch.chdir(tmp_path)
    assert main(["analyze", FOURBAR, *options]) == 2
    assert allowed in capsys.readouterr().err
    assert main(["analyze", FOURBAR, *options[:-1], options[-1].replace(".csv", ".json")]) == 0
    assert [p.suffix for p in tmp_path.iterdir()] == [".json"]


@pytest.mark.parametrize("command", ["analyze", "forces"])
def test_json_prints_what_out_json_writes_for_samples_too(tmp_path, capsys, command):
    # before: `--samples 10 --json` refused while `--samples 10 -o s.json` wrote the sampled JSON
    assert main([command, FOURBAR, "--samples", "4", "-o", str(tmp_path / "s.json")]) == 0
    capsys.readouterr()
    assert main([command, FOURBAR, "--samples", "4", "--json"]) == 0
    assert capsys.readouterr().out == (tmp_path / "s.json").read_text(encoding="utf-8")


def test_simulate_names_its_samples_as_analyze_and_forces(tmp_path, capsys):
    # before: "time,loop_gap,phi,…,drive_torque,points.A.position.x" without units
    assert main(["simulate", FOURBAR, "--samples", "3", "-o", str(tmp_path / "run.csv")]) == 0
    assert main(["simulate", FOURBAR, "--samples", "3", "-o", str(tmp_path / "run.npz")]) == 0
    capsys.readouterr()
    header = next(csv.reader(io.StringIO((tmp_path / "run.csv").read_text(encoding="utf-8"))))
    assert all(re.fullmatch(r"[\w.:-]+ \[[^\]]+\]", h) for h in header), header
    assert main(["analyze", FOURBAR, "--samples", "3"]) == 0
    analyzed = next(csv.reader(io.StringIO(capsys.readouterr().out)))
    assert main(["forces", FOURBAR, "--samples", "3"]) == 0
    forced = next(csv.reader(io.StringIO(capsys.readouterr().out)))
    # what MuJoCo measures: positions to accelerations of the moving points and links, the reactions
    wanted = {h for h in analyzed if re.match(r"[ABC]\.(position|velocity|acceleration)\.|(crank|coupler|rocker)"
                                              r"\.angle|phi ", h)}
    wanted |= {h for h in forced if ".force." in h or h.startswith(("balancing_torque ", "reduced_inertia "))}
    assert wanted - {"C.position.x [m]", "C.position.y [m]", "C.velocity.x [m/s]", "C.velocity.y [m/s]",
                     "C.acceleration.x [m/s²]", "C.acceleration.y [m/s²]"} <= set(header)
    npz = np.load(tmp_path / "run.npz")
    assert {"A.position", "crank.angle", "O.force", "balancing_torque", "t"} <= set(npz.files)
    assert npz["A.position"].shape == (3, 2)


def test_help_lists_what_each_family_takes():
    # before: "Planar linkages take every command" (profile refuses them)
    text = " ".join(build_parser().format_help().split())
    assert "every command" not in text
    for family in FAMILIES:
        listed = ", ".join(family.commands[:-1]) + " and " + family.commands[-1]
        assert f"{family.plural} ({family.doc}) take {listed}".lower() in text.lower()


def _help(command: str) -> str:
    sub = next(a for a in build_parser()._actions if a.dest == "command").choices
    return " ".join(sub[command].format_help().split())


def test_forces_and_simulate_help_are_true_for_every_family():
    # before: forces --help: "about +z." for every family and the reduced inertia advertised
    # (spatial forces give none); simulate --omega: "[rad/s]" only though it takes 120rpm
    forces = _help("forces")
    assert "about its axis (+z in the plane)" in forces and "planar linkages also the reduced inertia" in forces
    assert "e.g. 120rpm" in _help("simulate") and "e.g. 120rpm" in _help("flywheel")


@pytest.mark.parametrize("doc", ["README.md", *sorted(p.name for p in (ROOT / "docs").glob("*.md"))])
def test_docs_show_only_the_one_output_option(doc):
    # before: README's "Limits" named `--csv`; docs/machine.md the earlier --csv, --report, --mjcf
    path = ROOT / doc if doc == "README.md" else ROOT / "docs" / doc
    text = path.read_text(encoding="utf-8")
    for old in ("--csv", "--report", "--mjcf", "--output"):
        assert not re.search(rf"(?<![\w-]){old}(?![\w=-])", text), (doc, old)  # --mjcf= is MuJoCo's viewer


@pytest.mark.parametrize("argv,option,takers", [
    (["analyze", "cam_translating", "--transfer"], "--transfer", ("planar linkages", "spatial four-bars")),
    (["analyze", "cam_translating", "--samples", "3", "--keep-singular"], "--keep-singular", ("planar linkages",)),
    # a spatial chain marks no singular samples (it raises at a dead centre): the option would do nothing
    (["analyze", "rssr", "--samples", "3", "--keep-singular"], "--keep-singular", ("planar linkages",)),
    (["build", "rssr", "--practical"], "--practical", ("planar linkages",)),
])
def test_an_option_of_other_families_is_refused_naming_the_file_and_who_takes_it(tmp_path, capsys, argv, option,
                                                                                  takers):
    # before: "--transfer and --keep-singular are for linkages" (no file named; spatial takes --transfer)
    path = MODELS / f"{argv[1]}.toml"
    assert main([argv[0], str(path), *argv[2:], *(["-o", str(tmp_path / "m.xml")] if argv[0] == "build" else [])]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"linkgen: error: {path}: ") and f"takes no {option}; {option} is for " in err
    assert all(t in err for t in takers) and list(tmp_path.iterdir()) == []
