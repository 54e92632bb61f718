"""Outputs written atomically and never through a planted symlink; folder runs go on past a bad
file; conflicting options are errors; a closed pipe ends quietly."""

import os
import shutil
import subprocess
import sys

import numpy as np
import pytest

from conftest import ROOT
from linkgen import DescriptionError
from linkgen.cli.main import main
from linkgen.cli.files import atomic_open, atomic_output, atomic_write_text, run_each

MODELS = ROOT / "models"
FOURBAR = MODELS / "fourbar.toml"


def test_atomic_write_refuses_a_symlink(tmp_path):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    link = tmp_path / "out.txt"
    link.symlink_to(victim)
    with pytest.raises(OSError, match="is a symbolic link"):
        atomic_write_text(link, "new")
    assert victim.read_text() == "precious"
    assert link.is_symlink()


def test_failed_write_leaves_the_old_file_and_no_temporary(tmp_path):
    out = tmp_path / "out.csv"
    out.write_text("old")
    with pytest.raises(RuntimeError):
        with atomic_open(out) as f:
            f.write("half")
            raise RuntimeError("disk full")
    assert out.read_text() == "old"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out.csv"]


def test_atomic_output_keeps_the_suffix_for_path_writers(tmp_path):
    out = tmp_path / "run.npz"
    with atomic_output(out) as tmp:
        assert tmp.parent == tmp_path and tmp.suffix == ".npz"
        np.savez(tmp, x=np.arange(3))
    assert np.load(out)["x"].tolist() == [0, 1, 2]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.npz"]


def test_new_file_gets_the_usual_permissions(tmp_path):
    plain, atomic = tmp_path / "plain", tmp_path / "atomic"
    plain.write_text("x")
    atomic_write_text(atomic, "x")
    assert atomic.stat().st_mode & 0o777 == plain.stat().st_mode & 0o777


def test_run_each_goes_on_and_names_each_bad_file(tmp_path, capsys):
    def fn(p):
        if p.name == "b":
            raise DescriptionError("drive.omega", "must be finite, got nan", str(p))
        if p.name == "c":
            raise OSError(13, "Permission denied", str(p))
        return p.name.upper()

    paths = [tmp_path / n for n in "abcd"]
    outcomes = run_each(paths, fn)
    assert [(o.ok, o.value) for o in outcomes] == [(True, "A"), (False, None), (False, None), (True, "D")]
    assert capsys.readouterr().err.splitlines() == [
        f"linkgen: error: {tmp_path / 'b'}: drive.omega: must be finite, got nan",
        f"linkgen: error: {tmp_path / 'c'}: Permission denied",
    ]


def test_run_each_reports_a_bug_and_goes_on(tmp_path, capsys):
    outcomes = run_each([tmp_path / "a", tmp_path / "b"], lambda p: 1 / 0 if p.name == "a" else "B")
    assert [(o.ok, o.value) for o in outcomes] == [(False, None), (True, "B")]
    assert capsys.readouterr().err == (f"linkgen: error: {tmp_path / 'a'}: internal error (ZeroDivisionError: "
                                       "division by zero); please report it with this file\n")
    with pytest.raises(KeyboardInterrupt):
        run_each([tmp_path / "a"], lambda p: (_ for _ in ()).throw(KeyboardInterrupt))


def test_build_folder_with_a_bad_file_in_the_middle(tmp_path, capsys):
    shutil.copy(FOURBAR, tmp_path / "a.toml")
    (tmp_path / "b.toml").write_bytes(b"\xff\xfe binary")
    shutil.copy(MODELS / "slider_crank_offset.toml", tmp_path / "c.toml")
    assert main(["build", str(tmp_path)]) == 2
    err = capsys.readouterr().err.splitlines()
    assert err == [
        f"wrote {tmp_path / 'a.xml'}",
        f"linkgen: error: {tmp_path / 'b.toml'}: is not UTF-8 text (byte 0xff at line 1, offset 0); "
        "a description is a UTF-8 TOML file",
        f"wrote {tmp_path / 'c.xml'}",
        "linkgen: 1 of 3 descriptions failed",
    ]
    assert (tmp_path / "a.xml").read_text().startswith("<mujoco")
    assert (tmp_path / "c.xml").read_text().startswith("<mujoco")
    assert not (tmp_path / "b.xml").exists()


def test_build_does_not_write_through_a_symlink(tmp_path, capsys):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    out = tmp_path / "fourbar.xml"
    out.symlink_to(victim)
    assert main(["build", str(FOURBAR), "-o", str(out)]) == 2
    assert victim.read_text() == "precious"
    assert out.is_symlink() and "is a symbolic link" in capsys.readouterr().err


def test_build_output_option_with_a_folder(tmp_path, capsys):
    assert main(["build", str(MODELS), "-o", str(tmp_path / "x.xml")]) == 2
    assert capsys.readouterr().err == (
        f"linkgen build: error: -o/--out {tmp_path / 'x.xml'}: {str(MODELS)!r} is a folder of descriptions; its models "
        "are written into a folder (-o DIR), or each beside its description (no -o)\n")
    assert not (tmp_path / "x.xml").exists()


def test_output_pointing_at_a_folder(tmp_path, capsys):
    folder = tmp_path / "out.csv"  # a folder named like a file: never replaced
    folder.mkdir()
    assert main(["analyze", str(FOURBAR), "--samples", "4", "--csv", str(folder)]) == 2
    assert capsys.readouterr().err == (f"linkgen: error: {folder}: is a folder; give a file name to write\n")
    assert main(["analyze", str(FOURBAR), "--samples", "4", "-o", str(tmp_path)]) == 2
    assert capsys.readouterr().err.endswith(f"writes .csv (the samples over the drive range) or .json (the JSON "
                                            "object, as --json prints it); got a folder\n")
    assert list(folder.iterdir()) == []
    assert main(["build", str(FOURBAR), "-o", str(tmp_path)]) == 0  # build writes into a folder: NAME.xml
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fourbar.xml", "out.csv"]


@pytest.mark.parametrize("command", ["analyze", "forces"])
@pytest.mark.parametrize("options, message", [
    (["--angle", "1rad", "--samples", "3"], "--angle cannot be combined with --samples: --angle evaluates one crank "
                                         "angle (printed, --json, or -o FILE.json); --samples N and -o FILE.csv "
                                         "evaluate samples over the drive range"),
    (["--angle", "1rad", "--csv", "x.csv"], "--angle cannot be combined with --csv x.csv: --angle evaluates one crank "
                                         "angle (printed, --json, or -o FILE.json); --samples N and -o FILE.csv "
                                         "evaluate samples over the drive range"),
    (["--json", "--csv", "x.csv"], "--json prints what --csv x.csv writes: give one of them"),
    (["--keep-singular"], "--keep-singular is for samples (--samples, -o FILE.csv); at one crank angle a "
                          "singular position is an error"),
])
def test_conflicting_options(tmp_path, capsys, monkeypatch, command, options, message):
    monkeypatch.chdir(tmp_path)
    assert main([command, str(FOURBAR), *options]) == 2
    captured = capsys.readouterr()
    assert captured.err == f"linkgen {command}: error: {message}\n" and captured.out == ""
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("command", ["analyze", "forces"])
def test_closed_pipe_ends_quietly(command):
    proc = subprocess.Popen([sys.executable, "-m", "linkgen", command, str(FOURBAR), "--samples", "5000"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=ROOT)
    first = proc.stdout.readline()  # 5000 rows: megabytes, far more than a pipe holds (64 KiB)
    proc.stdout.close()  # as `| head -1` does
    err = proc.stderr.read()
    assert proc.wait(timeout=120) == 141
    assert first.startswith(b"phi [rad],")
    assert err == b""


def test_csv_written_atomically_through_no_symlink(tmp_path, capsys):
    victim = tmp_path / "victim.txt"
    victim.write_text("precious")
    out = tmp_path / "fb.csv"
    out.symlink_to(victim)
    assert main(["forces", str(FOURBAR), "--samples", "8", "--csv", str(out)]) == 2
    assert victim.read_text() == "precious" and out.is_symlink()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fb.csv", "victim.txt"]
    out.unlink()
    assert main(["forces", str(FOURBAR), "--samples", "8", "--csv", str(out)]) == 0
    assert len(out.read_text().splitlines()) == 9 and os.access(out, os.R_OK)


def test_missing_output_folder(tmp_path):
    with pytest.raises(OSError) as info:
        atomic_write_text(tmp_path / "nope" / "x.xml", "x")
    assert str(info.value) == f"{tmp_path / 'nope' / 'x.xml'}: the folder {str(tmp_path / 'nope')!r} does not exist"


def test_csv_in_chunks_is_the_whole_table(tmp_path, monkeypatch, capsys):
    import linkgen.cli.common as cli

    monkeypatch.setattr(cli, "CSV_CHUNK_ROWS", 7)  # 20 rows: two full chunks and a partial one
    x = np.linspace(-1.0, 1.0, 20) / 3.0
    cli.write_rows(["a", "b"], [x, x**2], tmp_path / "t.csv")
    lines = (tmp_path / "t.csv").read_text().splitlines()
    assert lines[0] == "a,b"
    assert lines[1:] == [f"{a!r},{b!r}" for a, b in zip(x.tolist(), (x**2).tolist())]


def test_validate_folder_reports_every_bad_file(tmp_path, capsys):
    # `validate DIR` once stopped at the first bad file; now each is reported and the status is 2.
    # (Two bad files keep the test fast: a good one costs a MuJoCo run; `build DIR` above shows
    # the good files around a bad one being processed.)
    models = tmp_path / "models"
    models.mkdir()
    (models / "a.toml").write_bytes(b"\xff\xfe binary")
    (models / "b.toml").write_text("[mechanism]\nname = 'x'\n")
    assert main(["validate", str(models), "--report", str(tmp_path / "report")]) == 2
    out = capsys.readouterr().out
    assert f"{models / 'a.toml'}: is not UTF-8 text (byte 0xff at line 1, offset 0)" in out
    assert f"{models / 'b.toml'}: description.drive: is required" in out
