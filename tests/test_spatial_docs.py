"""The spatial format page says what the spatial loader does: its example loads, every key the
loader allows is documented, and its Python block runs."""

import re
import tomllib
from pathlib import Path

from linkgen.families.spatial import description as d
from linkgen.families.spatial import drive
from linkgen.families.spatial import loads
from linkgen.families.spatial.description import spatial_from_dict

PAGE = (Path(__file__).resolve().parents[1] / "docs" / "spatial.md").read_text()
BLOCKS = re.findall(r"```toml\n(.*?)```", PAGE, flags=re.S)


def test_the_example_and_the_slider_fragment_load():
    full = tomllib.loads(BLOCKS[0])
    mech = spatial_from_dict(full)
    assert mech.name == "rssr" and len(mech.joints) == 4
    # the sliding output replaces the rocker
    slid = dict(full)
    links = dict(full["links"])
    del links["rocker"]
    slid["links"] = links | tomllib.loads(BLOCKS[1])["links"]
    joints = dict(full["joints"])
    del joints["B0"]
    slid["joints"] = joints
    slid["points"] = {k: v for k, v in full["points"].items() if k != "B0"}
    slid["links"]["ground"] = {"points": ["A0"]}
    slid["prismatic"] = tomllib.loads(BLOCKS[1])["prismatic"]
    assert spatial_from_dict(slid).slides[0].slider == "slider"


def test_the_loads_example_loads():
    full = tomllib.loads(BLOCKS[0]) | tomllib.loads(BLOCKS[2])
    mech = spatial_from_dict(full)
    assert [f.force for f in mech.forces] == [(0.0, 40.0, 0.0)] and [t.torque for t in mech.torques] == [(0.0, 0.0, -100.0)]


def test_the_slider_input_fragment_loads():
    """The PSSR made of the example's rocker and the slider-input fragment loads as a PSSR."""
    full = tomllib.loads(BLOCKS[0])
    part = tomllib.loads(BLOCKS[3])
    data = dict(full)
    data["links"] = {k: v for k, v in full["links"].items() if k != "crank"} | part["links"]
    data["links"]["ground"] = {"points": ["B0"]}
    data["joints"] = {k: v for k, v in full["joints"].items() if k != "A0"}
    data["points"] = {k: v for k, v in full["points"].items() if k != "A0"}
    data["prismatic"], data["drive"] = part["prismatic"], part["drive"]
    mech = spatial_from_dict(data)
    assert mech.drive.slides and mech.drive.range == (-0.1, 0.1) and mech.drive.omega == 0.5


def test_every_allowed_key_is_documented():
    for table in (d._MECH, d._LINK, d._JOINT, d._PRISMATIC, drive._DRIVE, drive._SLIDE_DRIVE, loads._FORCE, loads._TORQUE):
        for key in table:
            assert re.search(rf"^{key} =", PAGE, flags=re.M), key


def test_the_python_block_runs():
    code = re.findall(r"```python\n(.*?)```", PAGE, flags=re.S)[0]
    exec(compile(code, "docs/spatial.md", "exec"), {})
