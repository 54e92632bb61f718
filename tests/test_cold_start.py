"""Cold start: a closed-form command imports only what it needs (issue 23: ``linkgen analyze
models/fourbar.toml --angle 30deg`` to its first result in <= 0.25 s). Wall time on a shared
machine is no test; the modules a command pulls in are, and MuJoCo's import alone is a fifth of
a second here (``python -X importtime``)."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
HEAVY = ("mujoco", "matplotlib", "scipy", "lxml", "PIL", "imageio")

# Runs one command in a fresh interpreter and prints, as JSON, its exit status and which of the
# heavy packages it imported.
PROBE = """
import json, sys
from linkgen.cli.main import main
status = main(sys.argv[1:])
print(json.dumps([status, sorted(m for m in {heavy!r} if m in sys.modules)]), file=sys.stderr)
"""


def probe(*args: str, env: dict | None = None) -> tuple[int, list[str]]:
    p = subprocess.run([sys.executable, "-c", PROBE.format(heavy=HEAVY), *args], capture_output=True, text=True,
                       timeout=120, cwd=ROOT, env=env)
    return tuple(json.loads(p.stderr.strip().splitlines()[-1]))


@pytest.mark.parametrize("args", [
    ("analyze", "models/fourbar.toml", "--angle", "30deg"),
    ("analyze", "models/press.toml", "--json"),
    ("forces", "models/fourbar.toml", "--angle", "30deg"),
    ("structure", "models/g123.toml"),
    ("analyze", "models/cam_translating.toml", "--angle", "30deg"),
    ("analyze", "models/bennett.toml", "--angle", "30deg"),
])
def test_closed_form_commands_import_no_simulator_nor_plotting(args):
    status, heavy = probe(*args)
    assert status == 0 and heavy == [], (status, heavy)


def test_a_broken_opengl_backend_does_not_stop_the_closed_form(tmp_path):
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "WAYLAND_DISPLAY")}
    env["MUJOCO_GL"] = "no-such-backend"
    p = subprocess.run([sys.executable, "-m", "linkgen", "analyze", "models/fourbar.toml", "--angle", "30deg"],
                       capture_output=True, text=True, timeout=120, cwd=ROOT, env=env)
    assert p.returncode == 0 and "B" in p.stdout, p.stderr
    out = tmp_path / "fourbar.xml"
    p = subprocess.run([sys.executable, "-m", "linkgen", "build", "models/fourbar.toml", "-o", str(out)],
                       capture_output=True, text=True, timeout=120, cwd=ROOT, env=env)
    assert p.returncode == 2 and "MUJOCO_GL" in p.stderr and "Traceback" not in p.stderr, p.stderr
    assert not out.exists()
