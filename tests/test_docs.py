"""The format reference says what the loader does: the complete examples load, every fragment
uses only keys the loader allows, and every key the loader allows is documented."""

import re
import tomllib
from pathlib import Path

import pytest

from linkgen import from_dict
from linkgen.families.cam import description as cam_description
from linkgen.families.planar import reader
from linkgen.model.machine import MOTOR_KEYS, _MACHINE, machine_from_dict

DOCS = Path(__file__).resolve().parents[1] / "docs"
FORMAT = (DOCS / "format.md").read_text()
MACHINE = (DOCS / "machine.md").read_text()


def blocks(text: str) -> list[dict]:
    return [tomllib.loads(b) for b in re.findall(r"```toml\n(.*?)```", text, flags=re.S)]


def test_the_complete_example_loads():
    full = [b for b in blocks(FORMAT) if "mechanism" in b]
    assert len(full) == 1
    mech = from_dict(full[0])
    assert mech.name == "press" and mech.drive.omega == pytest.approx(4 * 3.141592653589793)


def test_every_fragment_uses_allowed_keys():
    allowed = {"links": reader._LINK | {"inertial"}, "prismatic": reader._PRISMATIC,
               "drive": reader._DRIVE | reader._SLIDE_DRIVE,  # a crank's, or a prismatic drive's
               "force": reader._FORCE, "torque": reader._TORQUE, "mechanism": reader._MECH, "gear": reader._GEAR,
               "cam": reader._CAM, "spring": reader._SPRING, "torsion_spring": reader._TORSION,
               "friction": reader._FRICTION}
    for b in blocks(FORMAT):
        for table, content in b.items():
            assert table in reader._TOP or table == "points", table
            items = content if isinstance(content, list) else (
                list(content.values()) if table in ("links", "prismatic", "gear", "cam") else [content])
            if table == "points":
                continue
            for item in items:
                assert set(item) <= allowed[table], (table, set(item) - allowed[table])
                if "inertial" in item:
                    assert set(item["inertial"]) <= reader._INERTIAL
                if table == "cam" and "law" in item:
                    assert set(item["law"]) <= cam_description._LAW


def test_every_key_is_documented():
    for keys in (reader._MECH, reader._LINK, reader._INERTIAL, reader._PRISMATIC, reader._DRIVE, reader._SLIDE_DRIVE,
                 reader._FORCE,
                 reader._TORQUE, reader._GEAR, reader._CAM, reader._SPRING, reader._TORSION, reader._FRICTION):
        for k in keys:
            assert f"`{k}`" in FORMAT or f"[links.NAME.{k}]" in FORMAT or f"cam.NAME.{k}]" in FORMAT, k
    for k in _MACHINE:
        assert k in MACHINE, k
    for kind, keys in MOTOR_KEYS.items():
        assert f"`{kind}`" in MACHINE and all(f"`{k}`" in MACHINE for k in keys), kind


def test_the_machine_example_reads():
    (b,) = blocks(MACHINE)
    m = machine_from_dict(b)
    assert m.motor.kind == "linear" and m.shaft.stiffness == 2.0e5 and len(m.process_load.angles) == 4


def test_the_readme_python_example_runs(monkeypatch):
    root = DOCS.parent
    (code,) = re.findall(r"```python\n(.*?)```", (root / "README.md").read_text(), flags=re.S)
    monkeypatch.chdir(root)
    exec(compile(code, "README.md", "exec"), {})
