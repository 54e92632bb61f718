"""`make test` runs its every-model checks (marked every_model) on conftest.REPRESENTATIVE, one bundled
model per family and feature, and `make every-model` on all of them: the representatives stay
bundled models and keep covering every family and every feature a bundled linkage has."""

import linkgen
from conftest import CAM_MODELS, EVERY_MODEL, MODELS, REPRESENTATIVE, SPATIAL_MODELS, every_model

# What a linkage's description may hold besides bars and pins: a representative has each one that
# some bundled linkage has.
FEATURES = ("cams", "gears", "planets", "springs", "torsion_springs", "frictions", "forces", "torques", "prismatics",
            "slide_drive")


def _features(path) -> set[str]:
    mech = linkgen.load(path)
    return {f for f in FEATURES if getattr(mech, f)}


def test_every_representative_is_a_bundled_model_and_every_family_has_one():
    assert set(REPRESENTATIVE) <= {p.stem for p in MODELS + CAM_MODELS + SPATIAL_MODELS}
    for family in (MODELS, CAM_MODELS, SPATIAL_MODELS):
        assert every_model(family) == (family if EVERY_MODEL else [p for p in family if p.stem in REPRESENTATIVE])
        assert every_model(family), family


def test_the_representative_linkages_have_every_feature_of_the_bundled_ones():
    bundled = set().union(*(_features(p) for p in MODELS))
    represented = set().union(*(_features(p) for p in MODELS if p.stem in REPRESENTATIVE))
    assert bundled == represented, sorted(bundled - represented)
