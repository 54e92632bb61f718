"""Units in descriptions: every form gives the same Mechanism as the SI numbers; a bad unit is
named with its field and value."""

import math
from pathlib import Path

import pytest

from linkgen import DescriptionError, load
from linkgen.pipeline.registry import loads

ROOT = Path(__file__).resolve().parents[1]
FOURBAR = (ROOT / "models" / "fourbar.toml").read_text()


def with_units(text: str) -> str:
    return (text.replace("A = [0.3, 0.0]", 'A = ["300mm", "0 cm"]')
                .replace("length = 0.3\n", 'length = "30cm"\n')
                .replace("length = 1.0\n", 'length = "1000 mm"\n')
                .replace("omega = 10.0 ", 'omega = "95.49296585513720rpm" ')
                .replace("[drive]\n", '[drive]\nepsilon = "0rad/s2"\n'))


def test_lengths_and_speeds_with_units_give_the_same_mechanism():
    si = loads(FOURBAR)
    text = with_units(FOURBAR)
    assert text.count("mm") >= 2 and "rpm" in text
    other = loads(text)
    assert other.points == si.points and other.links == si.links
    assert other.drive.omega == pytest.approx(si.drive.omega, rel=1e-15)


@pytest.mark.parametrize("value,si", [('"100rpm"', 100 * 2 * math.pi / 60), ('"10 rad/s"', 10.0),
                                      ('"180deg/s"', math.pi)])
def test_angular_speeds(value, si):
    text = FOURBAR.replace("omega = 10.0 ", f"omega = {value} ")
    assert loads(text).drive.omega == pytest.approx(si, rel=1e-15)


@pytest.mark.parametrize("value,si", [('"2rad/s2"', 2.0), ('"2rad/s²"', 2.0), ('"60rpm/s"', 2 * math.pi)])
def test_angular_accelerations(value, si):
    text = FOURBAR.replace("[drive]\n", f"[drive]\nepsilon = {value}\n")
    assert loads(text).drive.epsilon == pytest.approx(si, rel=1e-15)


def test_degree_sign_is_an_angle_unit():
    text = FOURBAR.replace("[drive]\n", '[drive]\nrange = ["0°", "90°"]\n')
    assert loads(text).drive.stop == pytest.approx(math.pi / 2, rel=1e-15)


@pytest.mark.parametrize("old,new,field,shown", [
    ("length = 0.3\n", 'length = "30 inch"\n', "links.crank.length", "'30 inch'"),
    ("omega = 10.0 ", 'omega = "10 Hz" ', "drive.omega", "'10 Hz'"),
    ("A = [0.3, 0.0]", 'A = ["0.3", 0.0]', "points.A[0]", "'0.3'")])
def test_a_bad_unit_names_the_field_and_the_value(tmp_path, old, new, field, shown):
    bad = tmp_path / "bad.toml"
    bad.write_text(FOURBAR.replace(old, new))
    with pytest.raises(DescriptionError) as info:
        load(bad)
    text = str(info.value)
    assert field in text and "bad.toml" in text and f"got {shown}" in text and "like" in text
