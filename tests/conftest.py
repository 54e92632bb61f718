from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent


def _spatial(p) -> bool:
    return 'space = "spatial"' in p.read_text(encoding="utf-8")


MODELS = sorted(p for p in (ROOT / "models").glob("*.toml")
                if "\n[cam]" not in p.read_text(encoding="utf-8") and not _spatial(p))
CAM_MODELS = sorted(p for p in (ROOT / "models").glob("*.toml") if "\n[cam]" in p.read_text(encoding="utf-8"))
SPATIAL_MODELS = sorted(p for p in (ROOT / "models").glob("*.toml") if _spatial(p))
# Linkages whose crank carries a cam: MuJoCo holds them to the cam contact's tolerances, not 1e-6.
CAM_LINKAGE_MODELS = [p for p in MODELS if "\n[cam." in p.read_text(encoding="utf-8")]
RIGID_MODELS = [p for p in MODELS if p not in CAM_LINKAGE_MODELS]


@pytest.fixture(params=MODELS, ids=[p.stem for p in MODELS])
def model_path(request) -> Path:
    return request.param


# MuJoCo appends warnings to MUJOCO_LOG.TXT in the working directory unless linkgen turns its log
# file off (linkgen.mujoco.log.no_log_file): a run that forgets it leaves the file behind. The suite
# fails if one appears in the repository or the working directory while it runs.
_LOG_PLACES = {ROOT / "MUJOCO_LOG.TXT", Path.cwd() / "MUJOCO_LOG.TXT"}
_LOGS_BEFORE = {p for p in _LOG_PLACES if p.exists()}


def pytest_sessionfinish(session, exitstatus):
    new = sorted(str(p) for p in _LOG_PLACES - _LOGS_BEFORE if p.exists())
    if new:
        print(f"\nMuJoCo wrote its log file into the working directory during the tests: {', '.join(new)}")
        session.exitstatus = 1
