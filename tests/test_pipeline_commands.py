"""One pipeline for every family (issue 22): every CLI command on every bundled model works or
refuses in one line; every family's validation result has ``.ok``, ``.summary()``,
``.to_dict()`` and its diagnosis; ``-o/--out`` is the one output option (the earlier spellings
still work, hidden); ``validate FOLDER`` writes nothing where the user did not ask.

Cheap by design: the long commands (simulate, validate, check-settings, animate, render, dynamics, flywheel) run
on one small model each; on every other model only the refusal path of the families that do
not take them is exercised."""

import json
import re
import shutil

import pytest

from conftest import EVERY_MODEL, ROOT
from linkgen.cli.main import EVERY_FAMILY_COMMANDS, build_parser, main

MODELS = ROOT / "models"
ALL = sorted(p.name for p in MODELS.glob("*.toml"))


def _commands() -> list[str]:
    """The commands a family takes or refuses (referee and suite are every family's: test_referee.py)."""
    sub = next(a for a in build_parser()._actions if a.dest == "command")
    return sorted(set(sub.choices) - EVERY_FAMILY_COMMANDS)


# The arguments each command runs with ({tmp}: the test's folder): short runs only.
ARGS = {"structure": [], "analyze": [], "forces": [], "assemble": [], "profile": ["--points", "8"],
        "build": ["-o", "{tmp}/m.xml"], "draw": ["-o", "{tmp}/m.png"],
        "simulate": ["--samples", "3", "--revolutions", "0.01"], "validate": ["--no-practical"],
        "animate": ["--frames", "2", "-o", "{tmp}/m.gif"], "render": ["--width", "32", "--height", "24", "-o", "{tmp}/m.png"],
        "dynamics": ["--duration", "0.02", "--samples", "5"], "flywheel": ["--delta", "0.05"],
        "check-settings": ["--no-search"], "page": ["--frames", "2", "-o", "{tmp}/m.html"],
        "sweep": ["--vary", "drive.omega=5:10:2", "-o", "{tmp}/sweep"],
        "optimize": ["--vary", "drive.omega=5:10", "--minimize", "peak_balancing_torque", "-o", "{tmp}/best.toml",
                     "--no-validate"]}
# Commands that take long (a MuJoCo run, an animation, an ODE): run on these models only; on
# every other model the command must still work or refuse in one line, which for a family that
# takes the command means running it: those pairs are left to the models below.
LONG = {"build": {m for m in ALL if not m.startswith("cam_")} | {"cam_translating.toml"},  # a cam's mesh: seconds
        "simulate": {"fourbar.toml"}, "validate": {"bennett.toml"},
        "animate": {"fourbar.toml", "cam_translating.toml", "rssr.toml"},
        "render": {"fourbar.toml", "cam_translating.toml", "rssr.toml"},
        "dynamics": {"motor_startup.toml"}, "flywheel": {"flywheel_sine.toml"}, "check-settings": {"fourbar.toml"},
        "page": {"fourbar.toml", "cam_translating.toml", "rssr.toml"},  # every model's page: test_teaching_pictures
        # a drawing, ~0.3 s: every representative's drawing is test_teaching_pictures'; all in `make every-model`
        "draw": ({"fourbar.toml", "cam_translating.toml", "rssr.toml"} if not EVERY_MODEL else set(ALL)),
        "sweep": {"fourbar.toml", "slider_crank_offset.toml"}, "optimize": {"fourbar.toml"}}
# Commands of ours (this pipeline's stages) that must work on every model whose family takes them.
MUST_WORK = {"build", "draw"}


def _family(model: str):
    from linkgen.pipeline.registry import family_of_file

    return family_of_file(MODELS / model)


@pytest.mark.every_model
@pytest.mark.parametrize("command", _commands())
@pytest.mark.parametrize("model", ALL)
def test_every_command_on_every_model_works_or_refuses_in_one_line(tmp_path, capsys, model, command):
    family = _family(model)
    takes = command in family.commands
    if takes and command in LONG and model not in LONG[command]:
        # the long command is run on LONG's models; here only that it is not refused as a family's
        assert family is not None
        return
    args = [a.format(tmp=tmp_path) for a in ARGS[command]]
    status = main([command, str(MODELS / model), *args])
    out, err = capsys.readouterr()
    assert "Traceback" not in err
    if not takes:
        assert status == 2 and err.count("\n") == 1, err
        assert f"`linkgen {command}` is for " in err and f"{family.plural} take " in err, err
        return
    if command in MUST_WORK or model in LONG.get(command, ()):
        assert status == 0, err
    else:  # a command the family takes may still refuse this file (no [machine] table, class III …)
        assert status == 0 or (status == 2 and err.count("\n") == 1 and err.startswith("linkgen")), err


@pytest.fixture(scope="module")
def results(validated):
    """One MuJoCo validation per family, on its cheapest model (fourbar without the
    practical-settings runs, a translating cam, the Bennett chain)."""
    return {name: validated(name) for name in ("fourbar", "cam_translating", "bennett")}


@pytest.mark.parametrize("name", ["fourbar", "cam_translating", "bennett"])
def test_every_familys_validation_result_has_one_protocol(results, name):
    r = results[name]
    line = r.summary()
    assert "\n" not in line and line.startswith("ok   ") and r.ok, line
    assert r.summary("validated in 9.99 s").endswith("validated in 9.99 s") or "validated in 9.99 s;" in \
        r.summary("validated in 9.99 s")
    d = r.to_dict()
    assert d["ok"] is True and d["model"] == name
    json.dumps(d, allow_nan=False)  # JSON as it is
    assert isinstance(r.diagnosis, tuple) and not r.diagnosis
    with pytest.raises(Exception):  # frozen
        r.model = "other"


def test_a_cam_linkage_result_has_the_same_protocol():
    import math

    import numpy as np

    from linkgen.crosscheck.cam import check_cam_linkage
    from linkgen.mujoco.cam_linkage import CamLinkageCheck

    assert check_cam_linkage.__module__ == "linkgen.crosscheck.cam"
    n = 360
    th = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    r = CamLinkageCheck("rocker", {"points": (1e-5, 2e-4)}, n, 1e-5, 1.0, {"points": np.full(n, 1e-5)},
                        {"disc": {"theta": th}})
    assert r.summary("validated in 1.00 s").startswith("ok   linkage with a cam") and "\n" not in r.summary()
    assert r.to_dict()["quantities"]["points"] == {"relative_error": 1e-5, "tolerance": 2e-4, "ok": True}
    assert r.diagnosis == ()


def test_validate_a_folder_writes_nothing_in_the_working_folder(tmp_path, monkeypatch, capsys):
    """Before: ``validate FOLDER`` wrote validation/report under the working folder (from ~ it
    made ~/validation/report); now the report goes only where -o names."""
    models, cwd = tmp_path / "models", tmp_path / "cwd"
    models.mkdir()
    cwd.mkdir()
    shutil.copy(MODELS / "bennett.toml", models)
    monkeypatch.chdir(cwd)
    assert main(["validate", str(models)]) == 0
    assert list(cwd.iterdir()) == []
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cwd", "models"]
    assert sorted(p.name for p in models.iterdir()) == ["bennett.toml"]
    assert "no report written (-o DIR writes one" in capsys.readouterr().err


def test_the_report_goes_where_out_names_and_the_old_spelling_still_works(tmp_path, capsys):
    from pathlib import Path

    assert build_parser().parse_args(["validate", "m.toml", "-o", "here"]).out == Path("here")
    assert main(["validate", str(MODELS / "bennett.toml"), "--report", str(tmp_path / "r")]) == 0
    assert (tmp_path / "r" / "README.md").is_file() and (tmp_path / "r" / "bennett_drawing.png").is_file()
    assert f"report: {tmp_path / 'r' / 'README.md'}" in capsys.readouterr().err


@pytest.mark.parametrize("command, old", [("build", "--output"), ("draw", "--output"), ("render", "--output"),
                                          ("animate", "--output"), ("validate", "--report"), ("dynamics", "--csv"),
                                          ("dynamics", "--report"), ("dynamics", "--mjcf"), ("flywheel", "--report")])
def test_out_is_the_one_output_option_and_the_old_spellings_are_hidden(command, old):
    sub = next(a for a in build_parser()._actions if a.dest == "command").choices[command]
    help_text = sub.format_help()
    assert re.search(r"-o (OUT|FILE|DIR), --out \1", help_text) and old not in help_text
    assert any(old in a.option_strings for a in sub._actions)  # still accepted


def test_dynamics_writes_each_output_told_by_its_extension(tmp_path, capsys):
    model = str(MODELS / "motor_startup.toml")
    args = ["dynamics", model, "--duration", "0.02", "--samples", "5"]
    assert main(args + ["-o", str(tmp_path / "m.csv"), "-o", str(tmp_path / "fig"), "-o", str(tmp_path / "m.xml")]) == 0
    assert (tmp_path / "m.csv").read_text().startswith("t [s],phi [rad]")
    assert (tmp_path / "fig" / "motor_startup_machine.png").is_file()
    assert (tmp_path / "m.xml").read_text().startswith("<mujoco")
    capsys.readouterr()
    assert main(args + ["-o", str(tmp_path / "m.txt")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "-o/--out" in err and ".csv" in err and not (tmp_path / "m.txt").exists()
    assert main(args + ["-o", str(tmp_path / "a.csv"), "--csv", str(tmp_path / "b.csv")]) == 2
    assert "given twice" in capsys.readouterr().err
