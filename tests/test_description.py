"""Strict loading: every error names the field, the value and what is allowed."""

import math
import textwrap

import pytest

from linkgen import DescriptionError, StructureError, decompose, from_dict, load

FOURBAR = """
[mechanism]
name = "fb"
[points]
O = [0.0, 0.0]
A = [0.3, 0.0]
B = [1.0143, 0.6999]
C = [1.0, 0.0]
[links.ground]
points = ["O", "C"]
[links.crank]
points = ["O", "A"]
length = 0.3
[links.coupler]
points = ["A", "B"]
length = 1.0
[links.rocker]
points = ["C", "B"]
length = 0.7
[drive]
joint = "O"
omega = 1.0
"""


def _load(tmp_path, text):
    f = tmp_path / "m.toml"
    f.write_text(textwrap.dedent(text))
    return load(f)


def test_fourbar_loads(tmp_path):
    m = _load(tmp_path, FOURBAR)
    assert [(j.name, j.links) for j in m.revolutes] == [
        ("O", ("ground", "crank")), ("C", ("ground", "rocker")), ("A", ("crank", "coupler")),
        ("B", ("coupler", "rocker"))]
    assert m.crank == "crank"


@pytest.mark.parametrize(
    "edit, message",
    [
        (("length = 1.0", "length = -1.0"), "links.coupler.length: must be > 0 m, got -1.0"),
        (("length = 1.0", "length = nan"), "links.coupler.length: must be finite, got nan"),
        (('points = ["A", "B"]', 'points = ["A", "Q"]'),
         "links.coupler.points[1]: unknown point 'Q'; known points: ['A', 'B', 'C', 'O']"),
        (("omega = 1.0", "omega = 1.0\nspin = 2"),
         "drive.spin: unknown key; allowed keys: ['epsilon', 'joint', 'omega', 'range']"),
        (('joint = "O"', 'joint = "Z"'), "drive.joint: unknown revolute 'Z'; revolutes: ['O', 'C', 'A', 'B']"),
        (('joint = "O"', 'joint = "A"'),
         "drive.joint: 'A' must join 'ground' and the crank, joins ('crank', 'coupler')"),
        (('[links.rocker]\npoints = ["C", "B"]\nlength = 0.7', '[links.rocker]\npoints = ["C", "B"]\nlength = 0.7\n'
          '[links.extra]\npoints = ["B", "C"]\nlength = 0.7'),
         "mechanism: mobility W = 3·n - 2·p5 = 3·4 - 2·6 = 0; linkgen needs exactly 1 degree of freedom "
         "(one driven crank)"),
        (("[links.ground]", "[links.frame]"), "links: a link named 'ground' (the frame) is required"),
        (('[drive]', '[prismatic.p]\nslider = "coupler"\nguide = "nowhere"\npoint = "A"\nthrough = "O"\n[drive]'),
         "prismatic.p.guide: unknown link 'nowhere'; known links: ['ground', 'crank', 'coupler', 'rocker']"),
        (("omega = 1.0", 'omega = 1.0\nrange = ["10deg", "5deg"]'),
         "drive.range: must be [from, to] with from < to <= from + 360deg, got [0.17453292519943295, "
         "0.08726646259971647] rad"),
        (("omega = 1.0", 'omega = 1.0\nrange = ["10 grad", "5deg"]'),
         "drive.range[0]: must be an angle: a number in rad or a string like '30deg', '30°' or '0.5rad', got '10 grad'"),
        (("B = [1.0143, 0.6999]", "B = [1.0143, -0.3]"),
         "points.B: the sketch puts it at (1.0143, -0.3) m but link 'coupler' assembles it at (1.01429, -0.699854) m "
         "on the nearest branch, 0.4 m away (allowed 0.0212 m = 0.02 of the sketch's size); correct the sketch or "
         "the link lengths, or let `linkgen assemble --write` place the points"),
        (("omega = 1.0", 'omega = 1.0\n[[force]]\nlink = "rocker"\npoint = "A"\nforce = [1.0, 0.0]'),
         "force[0].point: 'A' is not a point of link 'rocker'"),
        (("omega = 1.0", 'omega = 1.0\n[[force]]\nlink = "rocker"\npoint = "B"\nforce = [1.0, 0.0]\n'
          'stroke = ["90deg", "30deg"]'),
         "force[0].stroke: must be [from, to] crank angles with from < to <= from + 360deg, got "
         "[1.5707963267948966, 0.5235987755982988] rad"),
        (("omega = 1.0", 'omega = 1.0\n[[torque]]\nlink = "wheel"\ntorque = 1.0'),
         "torque[0].link: unknown link 'wheel'; known links: ['ground', 'crank', 'coupler', 'rocker']"),
    ],
)
def test_errors_name_field_value_and_rule(tmp_path, edit, message):
    text = textwrap.dedent(FOURBAR).replace(*edit)
    assert text != textwrap.dedent(FOURBAR), "the edit must apply"
    with pytest.raises(DescriptionError) as info:
        from linkgen import assemble

        assemble(_load(tmp_path, text))
    # errors found while loading name the file; the sketch check runs later, on assembly
    from_sketch = message.startswith("points.B: the sketch puts it")
    assert str(info.value) == (message if from_sketch else f"{tmp_path / 'm.toml'}: {message}")
    assert info.value.source == (None if from_sketch else str(tmp_path / "m.toml"))


def test_missing_file_is_a_description_error(tmp_path):
    with pytest.raises(DescriptionError) as info:
        load(tmp_path / "nope.toml")
    assert str(info.value) == f"{tmp_path / 'nope.toml'}: no such description file"


def test_angles_in_degrees_become_radians(tmp_path):
    m = _load(tmp_path, FOURBAR.replace("omega = 1.0", 'omega = 1.0\nrange = ["-90deg", "1.5rad"]'))
    assert m.drive.start == pytest.approx(-math.pi / 2, abs=1e-15) and m.drive.stop == 1.5


def test_python_api_builds_the_same_mechanism(tmp_path):
    import tomllib

    assert from_dict(tomllib.loads(FOURBAR)) == _load(tmp_path, FOURBAR)


def test_higher_class_group_is_not_supported():
    # A class-III group: a ternary link (tri) with three binary links to ground and crank; W = 1.
    data = {
        "mechanism": {"name": "c3"},
        "points": {"O": [0, 0], "A": [0.1, 0], "P": [0.5, 0.3], "Q": [0.9, 0.3], "R": [0.7, 0.6],
                   "G1": [0.5, -0.5], "G2": [1.3, 0.9]},
        "links": {"ground": {"points": ["O", "G1", "G2"]}, "crank": {"points": ["O", "A"]},
                  "l1": {"points": ["A", "P"]}, "tri": {"points": ["P", "Q", "R"]},
                  "l2": {"points": ["G1", "Q"]}, "l3": {"points": ["R", "G2"]}},
        "drive": {"joint": "O", "omega": 1.0},
    }
    with pytest.raises(StructureError, match=r"links \['l1', 'tri', 'l2', 'l3'\] do not decompose"):
        decompose(from_dict(data))
