"""Hostile input to every family (linkages, cam files, machines, spatial mechanisms), as a new
user and a hostile one would write it: each file loads, or every command that takes it fails
with one line naming the file, the field, the value and what is allowed — never a traceback,
a hang or a non-finite number in an output."""

import math
import re
import os
import signal
import socket
from contextlib import contextmanager

import pytest

from conftest import ROOT
from linkgen import DescriptionError
from linkgen.cli.main import main

MODELS = ROOT / "models"
# Seconds a refused file may take: the refusal reads nothing; a command that waits on a pipe
# or reads a device to its end never returns, and the alarm ends it.
REFUSAL_SECONDS = 20


class _Hang(BaseException):
    """Raised by the alarm: not an OSError, which the code under test may catch."""


@contextmanager
def _deadline(seconds: int):
    def expired(signum, frame):
        raise _Hang(f"no answer in {seconds} s")

    old = signal.signal(signal.SIGALRM, expired)
    signal.alarm(seconds)
    try:
        yield
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, old)


def _mutant(tmp_path, model: str, old: str, new: str, name: str = "m.toml"):
    text = (MODELS / model).read_text(encoding="utf-8")
    assert old in text, (model, old)
    path = tmp_path / name
    path.write_text(text.replace(old, new, 1), encoding="utf-8")
    return path


def _special(tmp_path, kind: str) -> str:
    if kind == "fifo":
        path = tmp_path / "model.toml"
        os.mkfifo(path)
        return str(path)
    if kind == "socket":
        path = tmp_path / "model.toml"
        sock = socket.socket(socket.AF_UNIX)
        sock.bind(str(path))
        return str(path)
    return kind  # a device


@pytest.mark.parametrize("kind", ["fifo", "socket", "/dev/null"])
@pytest.mark.parametrize("command", [["analyze"], ["build"], ["validate"], ["structure"], ["forces"],
                                     ["profile"], ["dynamics"], ["draw", "-o", "{tmp}/x.svg"]])
def test_not_a_regular_file_is_refused_by_every_command(tmp_path, capsys, kind, command):
    model = _special(tmp_path, kind)
    with _deadline(REFUSAL_SECONDS):
        status = main([command[0], model, *(a.format(tmp=tmp_path) for a in command[1:])])
    assert status == 2
    assert capsys.readouterr().err == (f"linkgen: error: {model}: is not a regular file (a device, pipe or socket); "
                                       "give a description file\n")


def _load_error(path) -> str:
    from linkgen import load
    with pytest.raises(DescriptionError) as info:
        load(path)
    return str(info.value)


# A list or a table where a name, a kind or a number is expected, in every family: each is named
# with its field, its value and the type expected (before: TypeError: unhashable type: 'list').
@pytest.mark.parametrize("model, old, new, message", [
    ("rssp.toml", 'slider = "slider"', 'slider = ["slider"]', "prismatic.guide.slider: must be a string, got ['slider']"),
    ("rssp.toml", 'points = ["B"]', 'points = [["B"]]', "links.slider.points[0]: must be a string, got ['B']"),
    ("rssp.toml", 'guide = "ground"', "guide = {a = 1}", "prismatic.guide.guide: must be a string, got {'a': 1}"),
    ("rssp.toml", 'kind = "spherical"', "kind = []", "joints.A.kind: must be a string, got []"),
    ("rssp.toml", "omega = 10.0", "omega = [10.0]",
     "drive.omega: must be an angular speed: a number in SI or a string like '100rpm' or '10rad/s', got [10.0]"),
    ("motor_startup.toml", 'kind = "linear"', 'kind = ["linear"]', "machine.motor.kind: must be a string, got ['linear']"),
    ("motor_startup.toml", "stall_torque = 2000.0", "stall_torque = {value = 2000.0}",
     "machine.motor.stall_torque: must be a number, got {'value': 2000.0}"),
    ("slider_crank_offset.toml", 'slider = "slider"', 'slider = ["slider"]',
     "prismatic.slider.slider: must be a string, got ['slider']"),
    ("slider_crank_offset.toml", 'joint = "O"', "joint = {O = 1}", "drive.joint: must be a string, got {'O': 1}"),
    ("planetary_lever.toml", 'planet = "satellite"', 'planet = ["satellite"]',
     "gear.mesh.planet: must be a string, got ['satellite']"),
    ("cam_rocker_slider.toml", 'roller = "C"', 'roller = ["C"]', "cam.disc.roller: must be a string, got ['C']"),
    ("press.toml", 'link = "ram"', 'link = ["ram"]', "force[0].link: must be a string, got ['ram']"),
    ("cam_translating.toml", 'kind = "translating"', 'kind = ["translating"]',
     "follower.kind: must be a string, got ['translating']"),
    ("cam_translating.toml", 'law = "harmonic"', 'law = {name = "harmonic"}',
     "segment[0].law: must be a string, got {'name': 'harmonic'}"),
])
def test_a_value_of_the_wrong_type_is_named(tmp_path, model, old, new, message):
    path = _mutant(tmp_path, model, old, new)
    assert _load_error(path) == f"{path}: {message}"


@pytest.mark.parametrize("model", ["cam_translating.toml", "fourbar.toml", "rssr.toml"])
@pytest.mark.parametrize("title, code, position", [
    ("Disc\\u0007cam", "0007", 5), ("\\u001b[31mred", "001B", 1), ("two\\nlines", "000A", 4), ("tab\\there", "0009", 4),
    ("del\\u007f", "007F", 4), ("c1\\u0085", "0085", 3),
])
def test_a_title_with_a_control_character_is_refused_at_load(tmp_path, model, title, code, position):
    text = (MODELS / model).read_text(encoding="utf-8")
    path = tmp_path / "m.toml"
    path.write_text(text.replace("[mechanism]\n", f'[mechanism]\ntitle = "{title}"\n', 1)
                    .replace("\ntitle = ", "\n# title = ", 2).replace("# title = ", "title = ", 1), encoding="utf-8")
    assert _load_error(path) == (f"{path}: mechanism.title: must be one line of printable text; it holds the control "
                                 f"character U+{code} at position {position}")


# two titles (each run builds a cam MJCF, some 3 s): '--' inside, '-' at the end, a run of '-',
# comment delimiters and XML's special characters
@pytest.mark.parametrize("title", ["Disc -- cam ---", "<!-- a & b < c -->-"])
def test_any_title_makes_a_valid_cam_mjcf(tmp_path, title):
    """The MJCF comment quoting the title: '--' and a final '-' (which XML forbids in a comment)
    are broken by a space; before, lxml raised ValueError."""
    import mujoco
    from lxml import etree

    from linkgen import load
    from linkgen.mujoco.cam import cam_mjcf

    path = _mutant(tmp_path, "cam_translating.toml", 'title = "Disc cam', f'title = "{title}" # "Disc cam')
    xml = cam_mjcf(load(path))
    mujoco.MjModel.from_xml_string(xml)
    first = etree.fromstring(xml.encode()).xpath("//comment()")[0].text
    assert first.startswith(f" {title.replace('--', '- -').replace('--', '- -')}: written by linkgen")


def test_a_title_given_in_python_is_written_safely():
    """A CamMechanism built in Python skips the loader: its MJCF writes what XML cannot carry as
    character codes."""
    from dataclasses import replace

    from linkgen import load
    from linkgen.mujoco.cam import cam_mjcf

    cm = replace(load(MODELS / "cam_translating.toml"), title="bell\x07 -- end-")
    assert "<!-- bellU+0007 - - end-: written by linkgen" in cam_mjcf(cm)


@pytest.mark.parametrize("name", ["A0", "A", "B"])
def test_a_spatial_prismatic_pair_named_like_a_pair_is_refused(tmp_path, name):
    """MuJoCo names each joint after its pair: a prismatic pair named like the pair at a point
    (before: MuJoCo's "repeated name 'A0' in joint" from build)."""
    path = _mutant(tmp_path, "rssp.toml", "[prismatic.guide]", f"[prismatic.{name}]")
    assert _load_error(path) == (f"{path}: prismatic.{name}: duplicate pair name: the pair at point {name} is named "
                                 "after its point; give the prismatic pair another name")


def test_a_spatial_prismatic_pair_named_like_its_link_builds(tmp_path):
    """Bodies and joints have their own names in MuJoCo: a pair may share its link's name."""
    text = (MODELS / "rssp.toml").read_text(encoding="utf-8")
    path = tmp_path / "m.toml"
    path.write_text(text.replace("[prismatic.guide]", "[prismatic.slider]"), encoding="utf-8")
    assert main(["build", str(path), "-o", str(tmp_path / "m.xml")]) == 0


_LIMITS = "(linkgen's limits, see the README)"


@pytest.mark.parametrize("model, old, new, message", [
    ("planetary_lever.toml", "teeth = [60, 20]", "teeth = [1" + "0" * 400 + ", 20]",
     "gear.mesh.teeth: must be at most 9007199254740992 teeth each (the largest count float64 carries exactly; "
     "linkgen's limits, see the README), got [100000000000000000...0000000000000000000, 20]"),
    ("planetary_lever.toml", "teeth = [60, 20]", "teeth = [9007199254740993, 20]",
     "gear.mesh.teeth: must be at most 9007199254740992 teeth each (the largest count float64 carries exactly; "
     "linkgen's limits, see the README), got [9007199254740993, 20]"),
    ("planetary_lever.toml", "module = 0.05", "module = 1e300",
     f"gear.mesh.module: must be within ±1e+12 m {_LIMITS}, got 1e+300"),
    ("planetary_lever.toml", "module = 0.05", "module = 1e11",
     f"gear.mesh: a pitch radius m·z/2 = 3e+12 m is beyond ±1e+12 m {_LIMITS}"),
    ("cam_translating.toml", "base_radius = 0.25", "base_radius = 1e300",
     f"cam.base_radius: must be within ±1e+12 m {_LIMITS}, got 1e+300"),
    ("cam_translating.toml", "base_radius = 0.25", "base_radius = 1e-300",
     f"cam.base_radius: must be at least 1e-90 m {_LIMITS}, got 1e-300"),
    ("cam_translating.toml", "height = 0.05", "height = 1e300",
     f"segment[0].height: must be within ±1e+12 m {_LIMITS}, got 1e+300"),
    ("cam_translating.toml", "omega = 10.0", "omega = 1e31",
     f"cam.omega: must be within ±1e+30 rad/s {_LIMITS}, got 1e+31"),
    ("cam_translating.toml", "mass = 2.0", "mass = 1e31", f"follower.mass: must be within ±1e+30 kg {_LIMITS}, got 1e+31"),
    ("cam_translating.toml", "spring_rate = 2000.0", "spring_rate = 1e103",
     f"follower.spring_rate: must be within ±1e+102 N/m or N·m/rad {_LIMITS}, got 1e+103"),
    ("cam_translating.toml", "offset = 0.1", "offset = -1e13",
     f"follower.offset: must be within ±1e+12 m {_LIMITS}, got -10000000000000.0"),
    ("motor_startup.toml", "stall_torque = 2000.0", "stall_torque = 1e300",
     f"machine.motor.stall_torque: must be within ±1e+114 N·m {_LIMITS}, got 1e+300"),
    ("motor_startup.toml", "no_load_speed = 6.0", "no_load_speed = 1e31",
     f"machine.motor.no_load_speed: must be within ±1e+30 rad/s {_LIMITS}, got 1e+31"),
    ("motor_startup.toml", "[machine]", "[machine]\ngear_ratio = 1e300",
     f"machine.gear_ratio: must be within ±1e+30 as a ratio {_LIMITS}, got 1e+300"),
    ("motor_startup.toml", "[machine]", "[machine]\nrotor_inertia = 1e55",
     f"machine.rotor_inertia: must be within ±1e+54 kg·m² {_LIMITS}, got 1e+55"),
    ("cam_oscillating.toml", "arm_length = ", "arm_length = 1e13 # ",
     f"follower.arm_length: must be within ±1e+12 m {_LIMITS}, got 10000000000000.0"),
])
def test_magnitudes_beyond_the_limits_in_every_family(tmp_path, model, old, new, message):
    path = _mutant(tmp_path, model, old, new)
    got = _load_error(path)
    assert got.startswith(f"{path}: {message}"), got


@pytest.mark.parametrize("bad", [math.inf, -math.inf, math.nan])
@pytest.mark.parametrize("to_file", [True, False])
def test_no_command_writes_a_non_finite_number(tmp_path, capsys, bad, to_file):
    """The one CSV writer of every command refuses a NaN or an infinity, naming the column and
    the row, and writes nothing (before: profile and analyze of a huge cam exited 0 with them)."""
    import numpy as np

    from linkgen.cli.common import write_rows
    from linkgen.errors import LinkgenError

    out = tmp_path / "out.csv" if to_file else None
    with pytest.raises(LinkgenError) as info:
        write_rows(["theta", "x"], [np.array([0.0, 1.0, 2.0]), np.array([0.0, 1.0, bad])], out)
    assert str(info.value) == ("the result is not finite in column 'x' at row 3 (the computation overflowed or hit a "
                               "singular position); nothing was written")
    assert capsys.readouterr().out == ""
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("model, old, new, counts", [
    # a bar hung on the planet: n = 3 moving links, p5 = 3 (O, C, B), p4 = 1 (the mesh)
    ("planetary_lever.toml", "[gear.mesh]", '[links.bar]\npoints = ["B", "D"]\n[points]\nD = [1.55, 0.5]\n[gear.mesh]',
     "3·3 - 2·3 - 1 = 2"),
    # a bar hung on the ram: n = 5, p5 = 6, p4 = 1 (the cam)
    ("cam_rocker_slider.toml", "[links.rod]", '[links.extra]\npoints = ["E", "X"]\n[points]\nX = [0.9, 0.9]\n[links.rod]',
     "3·5 - 2·6 - 1 = 2"),
])
def test_the_mobility_formula_names_p4_once(tmp_path, model, old, new, counts):
    path = _mutant(tmp_path, model, old, new)
    if "[points]\n" in new:  # TOML takes one [points] table: move the added point into it
        text = path.read_text(encoding="utf-8")
        extra = new.split("[points]\n")[1].split("\n")[0]
        text = text.replace(f"[points]\n{extra}\n", "").replace("[points]", f"[points]\n{extra}", 1)
        path.write_text(text, encoding="utf-8")
    assert _load_error(path) == (f"{path}: mechanism: mobility W = 3·n - 2·p5 - p4 = {counts}; linkgen needs exactly "
                                 "1 degree of freedom (one driven crank)")


@pytest.mark.parametrize("lowest, centre", [("5deg", "0.0218097"), ("0deg", "0"), ("9.17deg", "0.039969")])
def test_a_cam_without_base_radius_is_told_what_is_wrong_with_its_lowest_angle(tmp_path, lowest, centre):
    """The follower's pivot 0.25 m from the cam's axis, its arm 0.25 m, its roller 0.04 m (the centre
    at 2·0.25·sin(ψ/2) from the axis, 0.5·sin 2.5° = 0.0218097 m at ψ = 5°): the
    roller's centre clears the roller's radius when ψ > acos((0.25² + 0.25² − 0.04²)/(2·0.25·0.25))
    = acos(0.9872) = 9.17713°. Before: "cam.base_radius: must be > 0 m, got -0.0181903", a
    radius the user never gave."""
    path = _mutant(tmp_path, "cam_oscillating.toml", 'lowest_angle = "27deg"', f'lowest_angle = "{lowest}"')
    assert _load_error(path) == (
        f"{path}: follower.lowest_angle: puts the roller's centre {centre} m from the cam's axis, within the roller's "
        "radius 0.04 m: the cam would have no base circle; give a larger lowest_angle (the arm's angle at the pivot "
        "from the line to the cam's axis) or a smaller roller_radius; with this roller it must exceed 9.17713°")


def test_the_numeric_pose_reports_a_singular_position_with_its_reason(monkeypatch):
    """The numeric pose's singularity (a Jacobian conditioned beyond MAX_CONDITION): a
    SingularityError with its reason (before: TypeError, a missing constructor argument).
    MAX_CONDITION set to 1 makes every pose count as singular."""
    from linkgen import load
    from linkgen.errors import SingularityError
    from linkgen.families.planar import pose

    monkeypatch.setattr(pose, "MAX_CONDITION", 1.0)
    with pytest.raises(SingularityError) as info:
        pose.state(load(MODELS / "fourbar.toml"), [0.5], 1.0)
    assert info.value.group == "[coupler, rocker] (numeric)"
    assert "the pair constraints' Jacobian has condition number" in info.value.reason
    assert str(info.value).endswith("beyond MAX_CONDITION = 1: a dead centre or lock-up position, where the "
                                    "velocities are not determined")


def _subcommands():
    import argparse

    from linkgen.cli.main import build_parser

    parser = build_parser()
    return next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction)).choices


def test_help_texts_are_plain_and_complete():
    """Every positional argument says what it is; a flag (on or off) never claims "(no unit)";
    no help carries reStructuredText markup (``...``) meant for the source."""
    for name, sub in _subcommands().items():
        assert "``" not in (sub.description or ""), name
        for action in sub._actions:
            if not action.option_strings:
                assert action.help, (name, action.dest)
            if action.nargs == 0 and action.help:
                assert "no unit" not in action.help, (name, action.option_strings)
            assert "``" not in (action.help or ""), (name, action.dest)


# Options a command needs before it reads its model (argparse checks them first).
_REQUIRED = {"flywheel": ["--delta", "0.02"], "draw": ["-o", "{tmp}/x.svg"], "animate": ["-o", "{tmp}/x.gif"],
             "render": ["-o", "{tmp}/x.png"], "sweep": ["--vary", "drive.omega=1:2:2", "-o", "{tmp}/s"],
             "optimize": ["--vary", "drive.omega=1:2", "--minimize", "peak_balancing_torque", "-o", "{tmp}/b.toml"]}


def test_every_command_that_refuses_a_cam_file_names_exactly_those_that_take_it(tmp_path, capsys):
    from linkgen.pipeline.registry import BY_NAME

    CAM_COMMANDS = BY_NAME["cam"].commands

    cam = MODELS / "cam_translating.toml"
    listed = "analyze, profile, build, validate, draw, page, animate, render"
    from linkgen.cli.main import EVERY_FAMILY_COMMANDS

    refusing = [c for c in _subcommands() if c not in CAM_COMMANDS and c not in EVERY_FAMILY_COMMANDS]
    assert sorted(refusing) == ["assemble", "check-settings", "dynamics", "flywheel", "forces", "optimize", "simulate",
                                "structure", "sweep"]
    for command in refusing:
        extra = [a.format(tmp=tmp_path) for a in _REQUIRED.get(command, [])]
        assert main([command, str(cam), *extra]) == 2, command
        err = capsys.readouterr().err
        assert err.startswith(f"linkgen: error: {cam}: a stand-alone cam (docs/cams.md); `linkgen {command}` is for "), err
        assert err.endswith(f"; stand-alone cams take {listed}\n") and err.count("\n") == 1, err
    # the quick ones among those listed take it
    for command in ("analyze", "profile", "draw", "build"):
        extra = [a.format(tmp=tmp_path) for a in _REQUIRED.get(command, [])]
        extra += ["-o", str(tmp_path / "c.xml")] if command == "build" else []
        assert main([command, str(cam), *extra]) == 0, command
    capsys.readouterr()


@pytest.mark.parametrize("model, old, key, field", [
    ("fourbar.toml", "[links.rocker]", "ro\\u001b[2Jcker", "links.ro\\x1b[2Jcker"),
    ("rssr.toml", "[links.coupler]", "cou\\u0007pler", "links.cou\\x07pler"),
    ("cam_translating.toml", "[follower]", "fol\\u009blower", "fol\\x9blower"),
])
def test_a_key_with_control_characters_is_shown_by_their_codes(tmp_path, model, old, key, field):
    """A hostile key carrying a terminal escape: the message shows its codes, never the raw
    characters (which would act on the user's terminal)."""
    path = _mutant(tmp_path, model, old, f'[{old[1:-1].rsplit(".", 1)[0]}."{key}"]' if "." in old else f'["{key}"]')
    message = _load_error(path)
    assert field in message and not any(c in message for c in "\x07\x1b\x9b"), message


@pytest.mark.parametrize("model", ["fourbar.toml", "cam_translating.toml", "rssr.toml"])
def test_a_title_with_dollar_signs_is_drawn_as_written(tmp_path, capsys, model):
    """matplotlib reads text between '$' as a formula and fails on a malformed one (before:
    ParseSyntaxException from draw); a title is drawn as written."""
    title = r"a $\\frac{$ b $$"
    text = (MODELS / model).read_text(encoding="utf-8")
    path = tmp_path / "m.toml"
    head, _, rest = text.partition("\ntitle = ")
    path.write_text(head + f'\ntitle = "{title}"' + "\n" + rest.partition("\n")[2], encoding="utf-8")
    assert main(["draw", str(path), "-o", str(tmp_path / "m.svg")]) == 0
    assert (tmp_path / "m.svg").stat().st_size > 0
    from linkgen import load
    from linkgen.draw.plan import title_of

    # what matplotlib is given: every '$' escaped, so it draws the text as written
    assert title_of(load(path)) == r"a \$\frac{\$ b \$\$"


def test_a_non_finite_vector_column_is_named_by_its_row():
    """simulate's columns are (n, 2) vectors: the row named is the sample's."""
    import numpy as np

    from linkgen.cli.common import check_finite_columns
    from linkgen.errors import LinkgenError

    xy = np.zeros((4, 2))
    xy[2, 1] = math.inf
    with pytest.raises(LinkgenError, match=r"^the result is not finite in column 'B\.position' at row 3 "):
        check_finite_columns(["time", "B.position"], [np.arange(4.0), xy])


def test_a_cam_that_cannot_drive_its_follower_is_refused_not_infinite():
    """An oscillating follower pivoted on the cam's axis (pivot_distance 2.5e-101 m, fuzz
    campaign seed 2027): the profile's normal is square to the follower's motion, so the
    contact force would be infinite; the closed form says so instead of returning inf."""
    import tempfile
    from pathlib import Path

    import numpy as np

    from linkgen import load
    from linkgen.families.cam.kinetics import state
    from linkgen.errors import SingularityError

    text = (MODELS / "cam_oscillating.toml").read_text()
    assert "pivot_distance = 0.25" in text
    with tempfile.TemporaryDirectory() as d:
        path = Path(d) / "c.toml"
        path.write_text(text.replace("pivot_distance = 0.25", "pivot_distance = 2.5e-101"))
        cm = load(path)
        with pytest.raises(SingularityError, match="square to the follower's motion"):
            state(cm, np.linspace(0.0, 2 * np.pi, 72, endpoint=False))


@pytest.mark.parametrize("model", ["flywheel_sine", "cam_translating", "rssr"])
def test_a_name_too_long_for_a_file_name_is_refused_at_load(tmp_path, model):
    """A mechanism's name starts the names of its figures; 250 characters plus "_flywheel.png"
    passed the loader and ended in "File name too long" after the run (fuzz campaign seed 2031)."""
    from linkgen.errors import DescriptionError
    from linkgen.model.names import MAX_NAME_LENGTH
    from linkgen.pipeline.registry import load

    text = (MODELS / f"{model}.toml").read_text()
    long, ok = "x" * 250, "y" * MAX_NAME_LENGTH
    src = tmp_path / "m.toml"
    src.write_text(re.sub(r'(?m)^name = "[^"]*"', f'name = "{long}"', text, count=1))
    with pytest.raises(DescriptionError, match="mechanism.name: must be at most 128 characters"):
        load(src)
    src.write_text(re.sub(r'(?m)^name = "[^"]*"', f'name = "{ok}"', text, count=1))
    assert load(src).name == ok
