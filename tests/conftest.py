from pathlib import Path

import pytest

import linkgen
from linkgen.pipeline.registry import family_of_file

ROOT = Path(__file__).resolve().parent.parent


def _models(family: str) -> list[Path]:
    """The bundled models of one family, as the registry tells them apart."""
    return [p for p in sorted((ROOT / "models").glob("*.toml")) if family_of_file(p).name == family]


MODELS = _models("planar")
CAM_MODELS = _models("cam")
SPATIAL_MODELS = _models("spatial")
# Linkages whose crank carries a cam: MuJoCo holds them to the cam contact's tolerances, not 1e-6.
CAM_LINKAGE_MODELS = [p for p in MODELS if linkgen.load(p).cams]
RIGID_MODELS = [p for p in MODELS if p not in CAM_LINKAGE_MODELS]


def input_values(mech, phi):
    """Crank angles over one turn [0, 2π] mapped onto a spatial model's input: the angles
    themselves for a crank, the same fractions of the range for a slider input (PSSR, PSSP)."""
    import numpy as np

    phi = np.asarray(phi, dtype=float)
    if not mech.drive.slides:
        return phi
    lo, hi = mech.drive.range
    return lo + (hi - lo) * phi / (2 * np.pi)


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
