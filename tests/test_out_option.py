"""One output option for the closed-form commands: ``-o/--out FILE``, the format from the
extension (.csv the samples, .json the JSON object), another extension refused in one line; the
old spellings (``--csv``, ``profile --output``) still work, hidden from --help."""

from __future__ import annotations

import csv
import json
from pathlib import Path

import pytest

from linkgen.cli.main import build_parser, main

MODELS = Path(__file__).resolve().parents[1] / "models"


@pytest.mark.parametrize("command,model", [("analyze", "fourbar"), ("forces", "fourbar"), ("analyze", "rssr"),
                                           ("forces", "bennett"), ("analyze", "cam_oscillating")])
def test_out_csv_writes_the_samples_and_json_the_object(tmp_path, capsys, command, model):
    path = str(MODELS / f"{model}.toml")
    assert main([command, path, "--samples", "6"]) == 0
    printed = capsys.readouterr().out
    assert main([command, path, "--samples", "6", "-o", str(tmp_path / "s.csv")]) == 0
    assert (tmp_path / "s.csv").read_bytes().decode() == printed
    assert main([command, path, "--csv", str(tmp_path / "old.csv"), "--samples", "6"]) == 0  # the old spelling
    assert (tmp_path / "old.csv").read_bytes().decode() == printed
    assert main([command, path, "--json"]) == 0
    one = json.loads(capsys.readouterr().out)
    assert main([command, path, "--out", str(tmp_path / "one.json")]) == 0
    assert json.loads((tmp_path / "one.json").read_text(encoding="utf-8")) == one
    assert main([command, path, "--samples", "6", "-o", str(tmp_path / "s.json")]) == 0
    samples = json.loads((tmp_path / "s.json").read_text(encoding="utf-8"))
    rows = list(csv.reader(printed.splitlines()))
    assert len(samples.get("phi", samples.get("theta"))) == len(rows) - 1 == 6


@pytest.mark.parametrize("args", [["analyze", "{m}", "-o", "{d}/out.txt"], ["forces", "{m}", "--out", "{d}/out"],
                                  ["analyze", "{m}", "--summary", "-o", "{d}/s.xml"],
                                  ["profile", "{c}", "-o", "{d}/p.dat"]])
def test_another_extension_is_refused_in_one_line(tmp_path, capsys, args):
    argv = [a.format(m=MODELS / "fourbar.toml", c=MODELS / "cam_translating.toml", d=tmp_path) for a in args]
    assert main(argv) == 2
    err = capsys.readouterr().err
    target = Path(argv[-1])
    writes = {"analyze": ".csv (the samples over the drive range) or .json (the JSON object, as --json prints it)",
              "forces": ".csv (the samples over the drive range) or .json (the JSON object, as --json prints it)",
              "profile": ".csv (the points) or .json (the JSON object)"}
    command = "analyze --summary" if "--summary" in argv else argv[0]
    allowed = ".json (the summary's JSON object, as --json prints it)" if "--summary" in argv else writes[argv[0]]
    assert err == (f"linkgen {argv[0]}: error: -o/--out {target}: `linkgen {command}` writes {allowed}; got "
                   f"{target.suffix or 'no extension'}\n")
    assert list(tmp_path.iterdir()) == []


def test_profile_writes_csv_or_json_and_keeps_its_old_spelling(tmp_path, capsys):
    cam = str(MODELS / "cam_translating.toml")
    assert main(["profile", cam, "--points", "8"]) == 0
    printed = capsys.readouterr().out
    assert main(["profile", cam, "--points", "8", "--output", str(tmp_path / "old.csv")]) == 0
    assert (tmp_path / "old.csv").read_bytes().decode() == printed
    assert main(["profile", cam, "--points", "8", "-o", str(tmp_path / "p.json")]) == 0
    p = json.loads((tmp_path / "p.json").read_text(encoding="utf-8"))
    rows = list(csv.reader(printed.splitlines()))[1:]
    assert [[float(x) for x in r[1:3]] for r in rows] == p["profile"]


def test_the_summary_writes_its_json_where_asked(tmp_path, capsys):
    path = str(MODELS / "fourbar.toml")
    assert main(["analyze", path, "--summary", "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    assert main(["analyze", path, "--summary", "-o", str(tmp_path / "s.json")]) == 0
    assert json.loads((tmp_path / "s.json").read_text(encoding="utf-8")) == printed


def test_help_names_one_output_option_and_hides_the_old_ones():
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command").choices
    for command in ("analyze", "forces", "profile"):
        text = sub[command].format_help()
        assert "-o FILE, --out FILE" in text and "--csv" not in text and "--output" not in text, command


@pytest.mark.parametrize("model,line", [("rssr", "omega = 10.0      # rad/s"), ("fourbar", "omega = 10.0      # rad/s"),
                                        ("cam_translating", "omega = 10.0             # rad/s, counter-clockwise")])
def test_the_summary_takes_omega_for_every_family(tmp_path, capsys, model, line):
    """`--summary --omega 20` is the summary of the same description with its drive at 20 rad/s
    (before: a spatial four-bar's summary ignored --omega)."""
    src = (MODELS / f"{model}.toml").read_text(encoding="utf-8")
    assert line in src
    faster = tmp_path / f"{model}.toml"
    faster.write_text(src.replace(line, "omega = 20.0"), encoding="utf-8")
    assert main(["analyze", str(MODELS / f"{model}.toml"), "--summary", "--json", "--omega", "20"]) == 0
    given = json.loads(capsys.readouterr().out)
    assert main(["analyze", str(faster), "--summary", "--json"]) == 0
    assert given == json.loads(capsys.readouterr().out)


@pytest.mark.parametrize("model", ["fourbar", "rssr"])
def test_structure_prints_and_writes_its_json(tmp_path, capsys, model):
    """`structure` had no --json nor -o though its result has to_dict() (second audit): --json
    prints what -o FILE.json writes, the API's structure result as a dict."""
    import json

    import linkgen
    from linkgen.cli.main import main

    path = MODELS / f"{model}.toml"
    assert main(["structure", str(path), "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    out = tmp_path / "s.json"
    assert main(["structure", str(path), "-o", str(out)]) == 0
    assert json.loads(out.read_text()) == printed
    assert printed == json.loads(json.dumps(linkgen.structure(linkgen.load(path)).to_dict()))
    assert printed["mobility"] == 1 and printed["model"] == model
