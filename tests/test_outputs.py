"""Nothing written where the user did not ask: every output refuses a symlink planted at its
name, keeps the mode of the file it replaces and leaves no temporary file when interrupted; a
description written back follows its symlink; drawings are the same bytes on every run."""

import os
import signal
import stat
import subprocess
import sys
import time

import numpy as np
import pytest

from conftest import ROOT
from linkgen.cli.main import main
from linkgen.outputs import OutputError, atomic_write_text, output_folder

MODELS = ROOT / "models"
FOURBAR = MODELS / "fourbar.toml"
PRECIOUS = "precious\n"
# Samples for the interrupted CSV: ~120 MB of text, several seconds of writing on this machine,
# so the signal arrives while the temporary file is being filled.
INTERRUPT_SAMPLES = 200_000
# Longest wait for the temporary file to appear / for the interrupted process to end [s].
WAIT_S = 60.0


def _plant(tmp_path, name):
    """A symlink ``name`` in tmp_path pointing at a file holding PRECIOUS; returns (link, target)."""
    victim = tmp_path / "victim.txt"
    victim.write_text(PRECIOUS)
    link = tmp_path / name
    link.symlink_to(victim)
    return link, victim


def _refused(capsys, link, victim):
    err = capsys.readouterr().err
    assert f"{link}: is a symbolic link" in err, err
    assert victim.read_text() == PRECIOUS and link.is_symlink()


@pytest.mark.parametrize("name", ["run.npz", "run.csv"])
def test_simulate_out_refuses_a_symlink(tmp_path, capsys, name):
    link, victim = _plant(tmp_path, name)
    assert main(["simulate", str(FOURBAR), "--revolutions", "0.05", "--samples", "10", "--out", str(link)]) == 2
    _refused(capsys, link, victim)


def test_analyze_csv_refuses_a_symlink(tmp_path, capsys):
    link, victim = _plant(tmp_path, "fb.csv")
    assert main(["analyze", str(FOURBAR), "--samples", "8", "--csv", str(link)]) == 2
    _refused(capsys, link, victim)


def test_flywheel_report_refuses_a_symlink_inside(tmp_path, capsys):
    link, victim = _plant(tmp_path, "flywheel_sine_flywheel.png")
    assert main(["flywheel", str(MODELS / "flywheel_sine.toml"), "--delta", "0.02", "--report", str(tmp_path)]) == 2
    _refused(capsys, link, victim)


def test_dynamics_report_refuses_a_symlink_inside(tmp_path, capsys):
    link, victim = _plant(tmp_path, "motor_startup_machine.png")
    assert main(["dynamics", str(MODELS / "motor_startup.toml"), "--report", str(tmp_path)]) == 2
    _refused(capsys, link, victim)


def test_validate_report_folder_that_is_a_symlink_is_refused_before_the_run(tmp_path, capsys, monkeypatch):
    import linkgen.pipeline.registry as registry

    real = tmp_path / "real"
    real.mkdir()
    link = tmp_path / "report"
    link.symlink_to(real, target_is_directory=True)
    stages = []
    original = registry.stage
    monkeypatch.setattr(registry, "stage", lambda desc, name: stages.append(name) or original(desc, name))
    assert main(["validate", str(FOURBAR), "--report", str(link)]) == 2
    assert f"{link}: is a symbolic link" in capsys.readouterr().err
    assert list(real.iterdir()) == []
    assert "validate" not in stages  # refused up front: no MuJoCo run was started


def test_report_files_inside_the_folder_refuse_symlinks(tmp_path):
    from linkgen.report.report import plot_mechanism, write_index
    from linkgen.pipeline.registry import load
    from linkgen.families.planar.assembly import assemble

    link, victim = _plant(tmp_path, "fourbar_plan.png")
    with pytest.raises(OutputError, match="is a symbolic link"):
        plot_mechanism(assemble(load(FOURBAR)), tmp_path)
    assert victim.read_text() == PRECIOUS
    folder = output_folder(tmp_path / "r")
    (folder / "README.md").symlink_to(victim)
    with pytest.raises(OutputError, match="is a symbolic link"):
        write_index([], folder, 0.0, 0.0, lambda entry: None)
    assert victim.read_text() == PRECIOUS


def test_replaced_output_keeps_its_mode(tmp_path, capsys):
    out = tmp_path / "fb.csv"
    out.write_text("old")
    out.chmod(0o600)
    assert main(["analyze", str(FOURBAR), "--samples", "8", "--csv", str(out)]) == 0
    assert stat.S_IMODE(out.stat().st_mode) == 0o600
    assert len(out.read_text().splitlines()) == 9


def test_writer_refuses_a_device(tmp_path):
    with pytest.raises(OutputError, match="not a regular file"):
        atomic_write_text("/dev/null", "x")


def _default_signals() -> None:
    """In the child: SIGINT and SIGTERM as a terminal leaves them (a test runner's worker may
    ignore SIGINT, and an ignored signal stays ignored across exec: Python then installs no
    KeyboardInterrupt handler and the interrupt never arrives)."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.signal(signal.SIGTERM, signal.SIG_DFL)


@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGINT])
def test_interrupted_csv_leaves_no_temporary_file(tmp_path, signum):
    out = tmp_path / "big.csv"
    env = os.environ | {"PYTHONPATH": str(ROOT)}
    proc = subprocess.Popen([sys.executable, "-m", "linkgen", "analyze", str(FOURBAR), "--samples",
                             str(INTERRUPT_SAMPLES), "--csv", str(out)], env=env, cwd=tmp_path,
                            stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, preexec_fn=_default_signals)
    deadline = time.monotonic() + WAIT_S
    while not list(tmp_path.glob(".big.csv.*")):
        assert proc.poll() is None and time.monotonic() < deadline, "the temporary file never appeared"
        time.sleep(0.01)
    proc.send_signal(signum)
    _, err = proc.communicate(timeout=WAIT_S)
    assert proc.returncode == 128 + signum, err
    assert sorted(p.name for p in tmp_path.iterdir()) == []
    assert err.decode().endswith(f"linkgen: interrupted by {signal.Signals(signum).name}; no output is left "
                                 "half-written\n")


def test_assemble_write_keeps_the_mode(tmp_path, capsys):
    desc = tmp_path / "fb.toml"
    desc.write_text(FOURBAR.read_text())
    desc.chmod(0o600)
    assert main(["assemble", str(desc), "--write"]) == 0
    assert stat.S_IMODE(desc.stat().st_mode) == 0o600


def test_assemble_write_updates_a_symlinked_description_at_its_target(tmp_path, capsys):
    real = tmp_path / "real.toml"
    real.write_text(FOURBAR.read_text().replace("[points]", "# a comment kept\n[points]"))
    link = tmp_path / "fb.toml"
    link.symlink_to(real)
    before = real.read_text()
    assert main(["assemble", str(link), "--angle", "10deg", "--write"]) == 0
    assert link.is_symlink() and os.readlink(link) == str(real)
    assert real.read_text() != before and "# a comment kept" in real.read_text()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["fb.toml", "real.toml"]


@pytest.mark.parametrize("suffix", ["svg", "pdf"])
@pytest.mark.parametrize("model", ["fourbar.toml", "cam_translating.toml", "rssr.toml"])
def test_drawing_is_the_same_bytes_on_every_run(tmp_path, monkeypatch, capsys, suffix, model):
    outs = []
    # matplotlib dates svg/pdf from SOURCE_DATE_EPOCH when set: two different dates stand for
    # two runs on different days, without waiting for the clock.
    for i, epoch in enumerate(("1000000000", "1700000000")):
        monkeypatch.setenv("SOURCE_DATE_EPOCH", epoch)
        out = tmp_path / f"{i}.{suffix}"
        assert main(["draw", str(MODELS / model), "-o", str(out)]) == 0
        outs.append(out.read_bytes())
    assert outs[0] == outs[1]


def test_library_animation_writer_refuses_a_symlink(tmp_path):
    from linkgen.draw.animate import save_animation

    link, victim = _plant(tmp_path, "a.gif")
    with pytest.raises(OutputError, match="is a symbolic link"):
        save_animation([np.zeros((4, 4, 3), dtype=np.uint8)] * 2, link)
    assert victim.read_text() == PRECIOUS
    out = tmp_path / "b.gif"
    save_animation([np.zeros((4, 4, 3), dtype=np.uint8)] * 2, out)
    assert out.read_bytes().startswith(b"GIF8")
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.gif", "b.gif", "victim.txt"]


def test_the_library_keeps_mujocos_log_out_of_the_working_folder(tmp_path, monkeypatch):
    """Writing the MJCF from Python (no CLI around it) steps MuJoCo to derive the settings; a
    mechanism MuJoCo warns about (a follower rod of 7e11 m: a singular inertia matrix) must not
    leave MUJOCO_LOG.TXT in the working folder (found by validation/fuzz_commands.py, seed 2027)."""
    import re

    import linkgen
    from linkgen.mujoco.mjcf import write_mjcf

    text = (ROOT / "models" / "cam_rocker_slider.toml").read_text()
    text, n = re.subn(r"(?m)^E = \[[^,]+,", "E = [693814327461.7466,", text)
    assert n == 1
    (tmp_path / "m.toml").write_text(text)
    monkeypatch.chdir(tmp_path)
    write_mjcf(linkgen.assemble(linkgen.load(tmp_path / "m.toml")))
    assert not (tmp_path / "MUJOCO_LOG.TXT").exists()
