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
