"""The fuzz harness of validation/fuzz_commands.py: its mutants are reproducible and cover every
family and command, its classifiers see what they are meant to, and a short campaign over the
families and commands that pass today finds no crash, hang, non-finite output or unsafe write."""

from __future__ import annotations

import os
import sys
import tomllib
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "validation"))

import fuzz_cli  # noqa: E402
import fuzz_commands  # noqa: E402
import fuzz_mutants  # noqa: E402
import fuzz_outputs  # noqa: E402

from linkgen.cli.main import build_parser  # noqa: E402

# The short campaign: every family (and special files), through the commands that write files
# (a symlink or a 0600 file planted at the output, or SIGTERM mid-run) and the closed-form ones;
# the long campaigns (validation/fuzz_commands.py) run every command.
CAMPAIGN_FAMILIES = "planar,gears,cam_linkage,cam,machine,spatial,special"
CAMPAIGN_COMMANDS = "structure,analyze,analyze_csv,analyze_summary,forces_csv,draw_svg,assemble_write,profile,build"
CAMPAIGN_SEED = 21
CAMPAIGN_COUNT = 28  # four mutants per family; every fourth also through a command (symlinks, modes, SIGTERM)

def test_mutants_are_reproducible_and_differ_by_seed():
    a = [fuzz_mutants.mutant(4, k) for k in range(14)]
    b = [fuzz_mutants.mutant(4, k) for k in range(14)]
    c = [fuzz_mutants.mutant(5, k) for k in range(14)]
    assert a == b
    assert [m.data for m in a] != [m.data for m in c]
    assert {m.family for m in a} == set(fuzz_mutants.FAMILIES)

def test_toml_writer_round_trips_every_bundled_model():
    for family, stem, raw in fuzz_mutants.bundled():
        data = tomllib.loads(raw.decode())
        assert tomllib.loads(fuzz_mutants.to_toml(data)) == data, stem

def test_hostile_values_survive_the_writer():
    data = {"mechanism": {"name": "a\x01--\u202e名", "x": float("nan"), "y": float("-inf"), "n": 10**400},
            "points": {"A-B c": [1.0, {"v": True}]}}
    back = tomllib.loads(fuzz_mutants.to_toml(data))
    assert back["mechanism"]["name"] == data["mechanism"]["name"]
    assert back["mechanism"]["n"] == 10**400 and back["mechanism"]["y"] == float("-inf")
    assert back["points"] == data["points"]

def test_every_family_and_every_command_is_fuzzed():
    families = {f for f, _, _ in fuzz_mutants.bundled()}
    assert families == set(fuzz_mutants.FAMILIES) - {"special"}
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command")
    fuzzed = {argv[0] for argv, _, _ in fuzz_cli.COMMANDS.values()}
    assert set(sub.choices) == fuzzed
    for family, commands in fuzz_cli.FOR_FAMILY.items():
        assert set(commands) <= set(fuzz_cli.COMMANDS), family

def test_non_finite_numbers_are_found_in_outputs(tmp_path):
    csv = tmp_path / "a.csv"
    csv.write_text("phi [rad],x [m],singular\n0,1.5,0\n1,nan,1\n")
    assert fuzz_outputs.output_non_finite(csv) is None  # a singular row is written marked
    csv.write_text("phi [rad],x [m],singular\n0,1.5,0\n1,-inf,0\n")
    assert "inf" in fuzz_outputs.output_non_finite(csv)
    xml = tmp_path / "m.xml"
    xml.write_text('<mujoco><body name="inf" pos="0 0 0"/></mujoco>')
    assert fuzz_outputs.output_non_finite(xml) is None  # a name, not a number
    xml.write_text('<mujoco><body name="b" pos="0 nan 0"/></mujoco>')
    assert "nan" in fuzz_outputs.output_non_finite(xml)
    assert fuzz_outputs.text_non_finite("information, infinite, finance") is None
    assert fuzz_outputs.text_non_finite("stroke -inf m") is not None

def test_tree_differences_are_found(tmp_path):
    (tmp_path / "a").write_text("x")
    (tmp_path / "d").mkdir()
    before = fuzz_cli.snapshot(tmp_path)
    assert fuzz_cli._changed(before, fuzz_cli.snapshot(tmp_path)) == []
    os.chmod(tmp_path / "a", 0o600)
    (tmp_path / "d" / "tmp123").write_text("")
    (tmp_path / "link").symlink_to(tmp_path / "a")
    assert fuzz_cli._changed(before, fuzz_cli.snapshot(tmp_path)) == ["a", "d/tmp123", "link"]

def test_a_traceback_is_a_crash():
    err = 'Traceback (most recent call last):\n  File "/x/linkgen/a.py", line 3, in f\nKeyError: \'k\'\n'
    assert fuzz_cli._traceback(err) == "KeyError: 'k' at a.py:3"
    assert fuzz_cli._traceback("linkgen: error: m.toml: drive.omega: must be > 0\n") is None

def test_short_campaign_has_no_failure(tmp_path):
    args = fuzz_commands.parse(["--count", str(CAMPAIGN_COUNT), "--seed", str(CAMPAIGN_SEED), "--jobs", "1",
                                "--families", CAMPAIGN_FAMILIES, "--commands", CAMPAIGN_COMMANDS,
                                "--cli-every", "4", "--out", str(tmp_path / "repro")])
    rep = fuzz_commands.campaign(args)
    assert rep.count == CAMPAIGN_COUNT
    assert sum(sum(c.values()) for c in rep.commands.values()) == len(range(0, CAMPAIGN_COUNT, 4))
    assert rep.found == {}, "\n".join(f"{n} {sig}: {detail}" for sig, (n, _, detail) in rep.found.items())


def test_runs_are_classified():
    c = fuzz_cli.classify
    fail = "cam_translating        FAIL cam in MuJoCo: displacement 2.57e+03 of the stroke (tolerance 0.0002)\n"
    assert c(1, fail, "", False, [], None) == ("clean error", fail.strip())  # validate's honest FAIL
    assert c(1, "", "", False, [], None)[0] == "crash"  # a failure that says nothing
    assert c(2, "", "linkgen: error: m.toml: drive.omega: must be > 0\n", False, [], None)[0] == "clean error"
    assert c(-15, "", "", True, [], None)[0] == "interrupted"
    assert c(-11, "", "", False, [], None) == ("crash", "killed by signal 11")
    assert c(0, "", "", True, ["changed outside the outputs: cwd/.out.csv.x"], None)[0] == "unsafe write"
    assert c(0, "", "", False, [], "out.csv: 'nan'")[0] == "non-finite"
    assert c(3, "", "linkgen: error: ... singular", False, [], None)[0] == "clean error"
    assert c(0, "", "", False, [], None) == ("ok", "")
