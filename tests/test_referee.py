"""The referee (``linkgen referee``, ``linkgen.referee``): a solver that is not linkgen is refereed
with the right verdict; seeded mistakes made from the closed form on a four-bar, an offset
slider-crank, a slotted link and a six-bar are each diagnosed as what they are; correct results
are never diagnosed; the table's headers, units and errors; the report, JSON and the suite."""

from __future__ import annotations

import json
import math
import shutil
import sys
from pathlib import Path

import numpy as np
import pytest

import linkgen
from linkgen.cli.main import main

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "validation"))
sys.path.insert(0, str(ROOT / "tests"))

import referee_seeds  # noqa: E402
from referee_solver import SixBar  # noqa: E402

SIXBAR = ROOT / "tests" / "data" / "referee_sixbar.toml"
FOURBAR = ROOT / "models" / "fourbar.toml"
# Mechanisms of the seeded mistakes: a four-bar (RRR), an offset slider-crank (RRP), a slotted
# link (RPR, the Coriolis term in its accelerations) and a Watt six-bar (two RRR groups).
SEEDED = [FOURBAR, ROOT / "models" / "slider_crank_offset.toml", ROOT / "models" / "ga31.toml", SIXBAR]
# The independent solver converges Newton to |Δq| < 1e-15 rad; its velocities and accelerations
# are linear solves at that pose: agreement to ~1e-15 of the scale, here held to 1e-12.
SOLVER_TOL = 1e-12


def _asm(path):
    return referee_seeds.mechanism(path)


@pytest.mark.parametrize("path", SEEDED, ids=lambda p: p.stem)
@pytest.mark.parametrize("epsilon", [0.0, 30.0])
def test_seeded_mistakes_are_each_diagnosed_and_correct_results_never(path, epsilon):
    asm = _asm(path)
    phi = np.radians(np.arange(0.0, 360.0, 7.5))
    omega = float(asm.mechanism.drive.omega)
    v = linkgen.referee(asm, referee_seeds.correct(asm, phi, omega, epsilon), epsilon=epsilon)
    assert v.ok and all(c.diagnosis is None for c in v.columns)
    rng = np.random.default_rng(7)
    seeds = list(referee_seeds.seeded(asm, phi, omega, epsilon, rng, per_kind=1))
    kinds = {s.kind for s in seeds}
    assert {"sign", "unit_mm", "unit_deg", "phi_deg", "offset", "centripetal", "branch"} <= kinds, kinds
    seen = set()
    for table, members in referee_seeds.packed(seeds):
        by_key = {c.key: c for c in linkgen.referee(asm, table, epsilon=epsilon).columns}
        for s in members:
            c = by_key[s.key]
            if c.routes["closed_form"].agrees:
                continue  # the mistake changes nothing in this column at these angles
            seen.add(s.kind)
            assert c.diagnosis is not None and c.diagnosis.kind == s.expected, (s.kind, s.key, c.diagnosis)
    assert seen >= {"sign", "branch", "offset", "centripetal"}, seen


def test_a_six_bar_solver_that_is_not_linkgen_gets_the_right_verdict():
    solver = SixBar()
    mech = linkgen.load(SIXBAR)
    phi = np.radians(np.arange(0.0, 360.0, 5.0))
    right = linkgen.referee(mech, solver.solve(phi, 10.0, 30.0), epsilon=30.0)
    assert right.ok and max(c.routes["closed_form"].error for c in right.columns) < SOLVER_TOL
    assert {c.agrees for c in right.columns} == {"closed form"}
    # the same solver without the θ̇² and ω² terms of its acceleration loop
    wrong = linkgen.referee(mech, solver.solve(phi, 10.0, 0.0, centripetal=False))
    diag = {c.key: c.diagnosis for c in wrong.columns if c.diagnosis}
    assert set(diag) == {c.key for c in wrong.columns if "acceleration" in c.key}
    assert {d.kind for d in diag.values()} == {"omega_squared"}
    # its Newton iteration restarted on the mirrored dyad from 137° on
    flipped = linkgen.referee(mech, solver.solve(phi, 10.0, 0.0, flip_from=math.radians(137)))
    bad = [c for c in flipped.columns if not c.routes["closed_form"].agrees]
    assert {c.key.split(".")[0] for c in bad} == {"E", "link4", "link5"}
    for c in bad:
        assert c.diagnosis.kind == "branch", c.diagnosis
        assert c.diagnosis.text.startswith("from φ = 140° on your values follow the other assembly mode of group "
                                           "II(4,5) RRR [link4, link5]"), c.diagnosis.text


def test_headers_with_other_units_and_a_map():
    asm = _asm(FOURBAR)
    phi = np.radians(np.arange(0.0, 360.0, 10.0))
    k = linkgen.kinematics(asm, phi).columns()
    table = {"theta [deg]": np.degrees(phi), "xB": 1000 * k["B.position.x [m]"],
             "rocker.angular_velocity [rpm]": k["rocker.angular_velocity [rad/s]"] * 60 / (2 * math.pi),
             "iterations": np.ones_like(phi)}
    v = linkgen.referee(asm, table, mapping={"theta [deg]": "phi [deg]", "xB": "B.position.x [mm]", "iterations": ""})
    assert v.ok and [c.header for c in v.columns] == ["xB", "rocker.angular_velocity [rpm]"]
    assert [c.key for c in v.columns] == ["B.position.x [m]", "rocker.angular_velocity [rad/s]"]


@pytest.mark.parametrize("table,message", [
    ({"B.position.x [m]": [1.0]}, "phi: the table needs the crank-angle column, headed \"phi [rad]\" or \"phi [deg]\""),
    ({"phi [rad]": [0.0], "B.position.x": [1.0]}, "B.position.x: no unit: write it in brackets"),
    ({"phi [rad]": [0.0], "B.position.x [N]": [1.0]}, "B.position.x [N]: B.position.x is in m in linkgen's results; "
                                                       "'N' is N, not that kind of unit"),
    ({"phi [rad]": [0.0], "B.positon.x [m]": [1.0]}, "B.positon.x [m]: not a quantity linkgen computes for this "
                                                      "mechanism (close: B.position.x"),
    ({"phi [rad]": [0.0], "B.position.x [furlong]": [1.0]}, "unknown unit symbol 'furlong'"),
    ({"phi [rad]": [0.0], "B.position.x [m]": [float("nan")]}, "row 2: nan is not a finite number"),
])
def test_a_table_that_cannot_be_refereed_says_why(table, message):
    with pytest.raises(linkgen.DescriptionError) as exc:
        linkgen.referee(linkgen.load(FOURBAR), table)
    assert message in str(exc.value)


def test_the_command_prints_the_verdict_writes_the_report_and_exits_by_it(tmp_path, capsys):
    asm = _asm(FOURBAR)
    phi = np.radians(np.arange(0.0, 360.0, 10.0))
    k = linkgen.kinematics(asm, phi).columns()
    good, bad = tmp_path / "good.csv", tmp_path / "bad.csv"
    _write(good, {"phi [deg]": np.degrees(phi), "rocker.angle [rad]": k["rocker.angle [rad]"]})
    _write(bad, {"phi [deg]": np.degrees(phi), "rocker.angle [rad]": np.degrees(k["rocker.angle [rad]"])})
    assert main(["referee", str(FOURBAR), str(good)]) == 0
    assert "1 agree, 0 differ" in capsys.readouterr().out
    assert main(["referee", str(FOURBAR), str(bad), "-o", str(tmp_path / "rep")]) == 1
    out = capsys.readouterr().out
    assert "→ your values are (180/π) × linkgen's: degrees where the header says radians" in out
    assert sorted(p.name for p in (tmp_path / "rep").iterdir()) == ["README.md", "rocker.angle_rad.png", "verdict.json"]
    d = json.loads((tmp_path / "rep" / "verdict.json").read_text(encoding="utf-8"))
    assert d["ok"] is False and d["columns"][0]["diagnosis"]["kind"] == "unit"
    assert d["columns"][0]["diagnosis"]["parameters"]["factor"] == pytest.approx(180 / math.pi, rel=1e-15)
    assert main(["referee", str(FOURBAR), str(bad), "--json"]) == 1
    assert json.loads(capsys.readouterr().out) == d
    assert main(["referee", str(FOURBAR), str(tmp_path / "none.csv")]) == 2
    assert capsys.readouterr().err == f"linkgen: error: {tmp_path / 'none.csv'}: cannot be read (No such file or directory)\n"


def _write(path: Path, cols: dict) -> None:
    lines = [",".join(cols)] + [",".join(repr(float(x)) for x in row) for row in zip(*cols.values())]
    path.write_text("\n".join(lines) + "\n", encoding="utf-8")


def test_mujoco_routes_agree_with_a_correct_table_and_not_with_a_flipped_reaction():
    asm = _asm(FOURBAR)
    phi = np.radians(np.arange(0.0, 360.0, 30.0))
    f = linkgen.forces(asm, phi).columns()
    k = linkgen.kinematics(asm, phi).columns()
    table = {"phi [rad]": phi, "B.position.x [m]": k["B.position.x [m]"], "B.force.x [N]": -f["B.force.x [N]"],
             "balancing_torque [N·m]": f["balancing_torque [N·m]"]}
    v = linkgen.referee(asm, table, mujoco=True)
    by = {c.key: c for c in v.columns}
    assert by["B.position.x [m]"].agrees == "both" and by["balancing_torque [N·m]"].agrees == "both"
    assert set(by["balancing_torque [N·m]"].routes) == {"closed_form", "mujoco_forward", "mujoco_inverse"}
    assert by["B.force.x [N]"].agrees == "neither" and by["B.force.x [N]"].diagnosis.kind == "sign"


def test_a_suite_is_exported_and_its_answers_refereed(tmp_path, capsys):
    suite, answers = tmp_path / "suite", tmp_path / "answers"
    assert main(["suite", "export", str(suite), "--count", "3", "--seed", "4", "--no-mujoco"]) == 0
    manifest = json.loads((suite / "manifest.json").read_text(encoding="utf-8"))
    assert manifest["tolerance"]["relative"] == 1e-6
    folders = [m["folder"] for m in manifest["mechanisms"]]
    assert [m["family"] for m in manifest["mechanisms"]] == ["planar", "cam", "spatial"]
    for m in manifest["mechanisms"]:
        for rel in (m["description"], m["mjcf"], *m["tables"].values()):
            assert (suite / rel).is_file(), rel
    (answers / folders[0]).mkdir(parents=True)
    shutil.copy(suite / manifest["mechanisms"][0]["tables"]["kinematics"], answers / folders[0] / "mine.csv")
    (answers / folders[2]).mkdir()
    text = (suite / manifest["mechanisms"][2]["tables"]["kinematics"]).read_text(encoding="utf-8").splitlines()
    header = text[0].split(",")
    j = next(i for i, h in enumerate(header) if h.endswith(".angle [rad]") and "ground" not in h)
    rows = [r.split(",") for r in text[1:]]
    wrong = [header[0] + "," + header[j]] + [f"{r[0]},{-float(r[j])!r}" for r in rows]
    (answers / folders[2] / "mine.csv").write_text("\n".join(wrong) + "\n", encoding="utf-8")
    assert main(["referee", "--suite", str(suite), str(answers)]) == 1
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith(f"ok   {folders[0]}: mine.csv: ") and out[1] == f"{folders[1]}: no answer"
    assert out[2] == f"DIFF {folders[2]}: mine.csv: 0 of 1 columns agree"
    assert "your values are −1 × linkgen's: the sign flipped" in out[3]


@pytest.mark.parametrize("key", ["rocker.angle [rad]", "B.position.x [m]", "B.force.y [N]"])
def test_values_unlike_any_mistake_stay_unexplained(key):
    # before: an angle column of any values in degrees-sized numbers was "explained" as π/180 or
    # 0.001 × linkgen's, the differences being wrapped by 2π × that factor
    asm = _asm(FOURBAR)
    phi = np.radians(np.arange(0.0, 360.0, 10.0))
    noise = np.random.default_rng(3).uniform(0.0, 100.0, phi.shape)
    c = linkgen.referee(asm, {"phi [rad]": phi, key: noise}).columns[0]
    assert c.diagnosis.kind == "unexplained", c.diagnosis


def test_the_docs_example_prints_what_the_docs_show(tmp_path, monkeypatch, capsys):
    import re

    text = (ROOT / "docs" / "referee.md").read_text(encoding="utf-8")
    section = text[text.index("## An example"):text.index("## A reference suite")]
    (code,) = re.findall(r"```python\n(.*?)```", section, flags=re.S)
    shown = re.search(r"```\n(.*?)```", section.split("It prints")[1], flags=re.S).group(1)
    (tmp_path / "models").mkdir()
    shutil.copy(FOURBAR, tmp_path / "models")
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "docs/referee.md", "exec"), {})
    assert capsys.readouterr().out == shown
    assert "other assembly mode of group II(2,3) RRR [coupler, rocker]" in shown and "degrees where the header" in shown


def test_an_offset_is_found_across_a_loads_stroke():
    # before: the press's force acts over a stroke; its jump made the offset's slope huge there
    # and every force column of a table shifted by +1° was "unexplained"
    asm = _asm(ROOT / "models" / "press.toml")
    phi = np.radians(np.arange(0.0, 360.0, 5.0))
    f = linkgen.forces(asm, phi + math.radians(1.0)).columns()
    keys = [k for k in f if k.startswith(("A.force", "B.force", "balancing_torque"))]
    v = linkgen.referee(asm, {"phi [rad]": phi} | {k: f[k] for k in keys})
    assert [c.diagnosis.kind for c in v.columns] == ["offset"] * len(keys)
    assert v.columns[0].diagnosis.parameters["delta_rad"] == pytest.approx(math.radians(1.0), rel=1e-6)
