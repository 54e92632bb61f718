import os
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


# Every-model checks (one property through one code path on each bundled model) run in `make test`
# on one model per family and feature, REPRESENTATIVE below, and on every bundled model in
# `make every-model` (which `make demo` runs): LINKGEN_EVERY_MODEL=1 and the `every_model` mark.
EVERY_MODEL = os.environ.get("LINKGEN_EVERY_MODEL", "") == "1"
REPRESENTATIVE = {
    "fourbar": "an RRR group: the crank-rocker",
    "g123": "RRR, RRP and RPR groups in series; two blocks on one pin",
    "scotch_yoke": "an RPP group",
    "tangent_prp": "a PRP group; a crank range short of a turn",
    "hydraulic_boom": "a prismatic drive",
    "planetary_lever": "gears",
    "cam_rocker_slider": "a cam on the crank (a profile mesh)",
    "slider_crank_friction": "springs and friction",
    "fourbar_torsion": "a torsion spring",
    "machine_press": "a machine: motor, gearbox, flywheel; a stroke-switched force",
    "cam_translating": "a cam, translating roller follower",
    "cam_oscillating": "a cam, oscillating follower",
    "cam_flat_face": "a cam, flat-faced follower",
    "rssr": "a spatial chain driven by a crank",
    "pssp": "a spatial chain driven by a slider",
    "bennett": "a spatial chain of hinges alone (statically indeterminate)",
    "rccc": "a spatial chain with cylindrical pairs",
}


def every_model(paths: list[Path]) -> list[Path]:
    """``paths`` in `make every-model`, else those of them that are REPRESENTATIVE."""
    return list(paths) if EVERY_MODEL else [p for p in paths if p.stem in REPRESENTATIVE]


@pytest.fixture(scope="session")
def validated():
    """``validated(stem)``: the MuJoCo validation of a bundled model without the practical-settings
    runs (a planar linkage's option; other families have none), made once a session for the tests
    that only read it."""
    done = {}

    def get(stem: str):
        if stem not in done:
            done[stem] = linkgen.validate(linkgen.load(ROOT / "models" / f"{stem}.toml"), practical=False)
        return done[stem]

    return get


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
