from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parent.parent
MODELS = sorted((ROOT / "models").glob("*.toml"))


@pytest.fixture(params=MODELS, ids=[p.stem for p in MODELS])
def model_path(request) -> Path:
    return request.param
