"""The Python API for every family: one rule for φ, ω, ε and the options, checked where the API
receives them; the planar family's own functions refusing another family in one line; the
family interface (pipeline/family.py STAGES) as every family implements it."""

from __future__ import annotations

import inspect
import re
from pathlib import Path

import numpy as np
import pytest

import linkgen
from linkgen.pipeline.family import BY_STAGE, STAGES, Family
from linkgen.pipeline.registry import FAMILIES

ROOT = Path(__file__).resolve().parents[1]
MODELS = {name: linkgen.load(ROOT / "models" / f"{name}.toml") for name in ("fourbar", "rssr", "cam_translating")}
# A unit string gives the float it stands for to float64 rounding of the conversion.
UNIT_REL = 1e-15


# -- the planar family's own functions ---------------------------------------------------------

PLANAR_ONLY = {
    "assemble": lambda m: linkgen.assemble(m),
    "decompose": lambda m: linkgen.decompose(m),
    "solve": lambda m: linkgen.solve(m, 0.1),
    "solve_motion": lambda m: linkgen.solve_motion(m, 0.1, 1.0),
}
TAKES = {"rssr": "spatial four-bars take linkgen.structure, linkgen.kinematics, linkgen.forces, linkgen.summary, "
                 "linkgen.write_mjcf, linkgen.validate",
         "cam_translating": "stand-alone cams take linkgen.kinematics, linkgen.summary, linkgen.profile, "
                            "linkgen.write_mjcf, linkgen.validate"}


@pytest.mark.parametrize("function", sorted(PLANAR_ONLY))
@pytest.mark.parametrize("model", ["rssr", "cam_translating"])
def test_the_planar_functions_refuse_another_family_in_one_line(function, model):
    # before: AttributeError: 'SpatialMechanism' object has no attribute 'revolutes'
    with pytest.raises(linkgen.UnsupportedError) as info:
        PLANAR_ONLY[function](MODELS[model])
    assert str(info.value) == f"{model}: linkgen.{function} is for planar linkages; {TAKES[model]}"


def test_the_planar_functions_take_the_apis_angles_and_rates():
    # before: ValueError: could not convert string to float: '30deg'
    four = MODELS["fourbar"]
    k = linkgen.solve(four, "30deg")
    assert k.phi[0] == pytest.approx(np.pi / 6, rel=UNIT_REL)
    mo = linkgen.solve_motion(four, ["30deg", 0.6], "120rpm", "60rpm/s")
    ref = linkgen.solve_motion(four, np.array([np.pi / 6, 0.6]), 4 * np.pi, 2 * np.pi)
    np.testing.assert_allclose(mo.points["B"][1], ref.points["B"][1], rtol=UNIT_REL)
    with pytest.raises(linkgen.ArgumentError, match=r"^phi: an angle needs its unit"):
        linkgen.solve(four, "30")


def test_decompose_is_the_structure_and_analyze_names_its_successor():
    four = MODELS["fourbar"]
    assert linkgen.decompose(four).formula == linkgen.structure(four).formula
    assert linkgen.decompose(linkgen.assemble(four)).formula == linkgen.structure(four).formula
    with pytest.raises(AttributeError, match=r"^linkgen.analyze is now linkgen.decompose"):
        linkgen.analyze  # noqa: B018
    assert "analyze" not in linkgen.__all__


def test_every_error_of_the_hierarchy_is_exported():
    from linkgen import errors

    classes = {n for n, c in vars(errors).items() if isinstance(c, type) and issubclass(c, errors.LinkgenError)}
    assert "UnsupportedError" in classes
    assert classes <= set(linkgen.__all__), sorted(classes - set(linkgen.__all__))
    assert all(getattr(linkgen, n) is getattr(errors, n) for n in classes)


# -- one rule for the arguments, in every family ---------------------------------------------

def _one_value(name: str, unit: str, example: str) -> str:
    return (f"{name}: expected one value for every drive angle (a number in {unit} or a string like {example}), got "
            f"a sequence of 2; for values that vary with the angle, call once per angle")


OMEGA = _one_value("omega", "rad/s", "120rpm")
EPSILON = _one_value("epsilon", "rad/s²", "60rpm/s")
CALLS = [
    # before: planar ArgumentError, spatial "ValueError: need at least one array to stack", cam an empty result
    (lambda m: linkgen.kinematics(m, []), "phi: expected a number or a non-empty 1-D array of them, got an empty list"),
    (lambda m: linkgen.kinematics(m, np.array([])),
     "phi: expected a number or a non-empty 1-D array of them, got an empty ndarray"),
    # before: a bare TypeError for the spatial and the cam (planar accepted it)
    (lambda m: linkgen.kinematics(m, [0.1, 0.2], omega=[1.0, 2.0]), OMEGA),
    # before: the cam "ValueError: The truth value of an array…"
    (lambda m: linkgen.kinematics(m, [0.1, 0.2], epsilon=[0, 1]), EPSILON),
    # before: a bare TypeError in all three
    (lambda m: linkgen.summary(m, omega=[1.0, 2.0]), OMEGA),
    # before: AttributeError: 'str' object has no attribute 'timestep'
    (lambda m: linkgen.write_mjcf(m, settings="x"),
     "settings: expected None (derived from the mechanism) or a linkgen.mujoco.options.Settings, got 'x' (str)"),
    # before: TypeError for the planar four-bar; the spatial and the cam ran, ignoring it
    (lambda m: linkgen.validate(m, bogus=1),
     "bogus: not an option of linkgen.validate; its options are practical, nthread, max_steps, progress, source, "
     "machine_progress"),
]


@pytest.mark.parametrize("call, message", CALLS)
@pytest.mark.parametrize("model", sorted(MODELS))
def test_one_rule_for_the_arguments_in_every_family(model, call, message):
    with pytest.raises(linkgen.ArgumentError) as info:
        call(MODELS[model])
    assert str(info.value) == message


def test_forces_take_one_omega_like_kinematics():
    for model in ("fourbar", "rssr"):
        with pytest.raises(linkgen.ArgumentError) as info:
            linkgen.forces(MODELS[model], [0.1, 0.2], omega=[1.0, 2.0])
        assert str(info.value) == OMEGA


def test_simulate_refuses_an_unknown_option_naming_its_options():
    with pytest.raises(linkgen.ArgumentError) as info:
        linkgen.simulate(MODELS["fourbar"], bogus=1)
    assert str(info.value) == ("bogus: not an option of linkgen.simulate; its options are revolutions, omega, epsilon, "
                               "settings, samples, nthread, progress, max_steps, settle, notice")


def test_a_cam_given_settings_is_told_about_settings_not_a_cli_flag():
    # before: "--practical is for linkages", a flag the API user never passed
    from linkgen.crosscheck.practical import USER

    with pytest.raises(linkgen.ArgumentError) as info:
        linkgen.write_mjcf(MODELS["cam_translating"], settings=USER)
    assert str(info.value) == ("settings: a stand-alone cam's MJCF carries its own contact settings, derived from its "
                               "motion; leave settings out (None)")


# -- the family interface --------------------------------------------------------------------

def _call(fn) -> str:
    sig = inspect.signature(fn)
    params = [p.replace(annotation=p.empty) for p in sig.parameters.values()]
    return str(sig.replace(parameters=params, return_annotation=sig.empty))


@pytest.mark.parametrize("family", FAMILIES, ids=lambda f: f.name)
def test_every_stage_has_the_interfaces_call(family):
    for name, fn in family.stages.items():
        assert _call(fn) == BY_STAGE[name].call, (family.name, name)


def _family(**changes) -> Family:
    planar = next(f for f in FAMILIES if f.name == "planar")
    fields = {k: getattr(planar, k) for k in ("name", "title", "plural", "doc", "description", "detects", "from_dict",
                                              "commands", "stages")}
    return Family(**(fields | changes))


def test_a_family_without_a_stage_its_commands_need_is_refused():
    stages = {k: v for k, v in _family().stages.items() if k != "report"}
    with pytest.raises(TypeError) as info:
        _family(name="new", stages=stages)
    assert str(info.value) == "Family('new'): takes validate but has no report stage (pipeline/family.py STAGES)"
    with pytest.raises(TypeError, match=r"^Family\('new'\): unknown stages \['reprot'\]"):
        _family(name="new", stages=_family().stages | {"reprot": print})


def test_the_report_of_a_family_without_the_stage_is_a_one_line_refusal(monkeypatch):
    # before: KeyError: 'report'
    from linkgen.pipeline import registry

    stages = {k: v for k, v in _family().stages.items() if k not in ("report", "validate", "figures")}
    new = _family(name="new", plural="new mechanisms", commands=("build",), stages=stages)
    monkeypatch.setattr(registry, "BY_NAME", {**registry.BY_NAME, "new": new})
    with pytest.raises(linkgen.UnsupportedError) as info:
        registry.report_parts({"family": "new", "model": "m", "ok": True})
    assert str(info.value) == "m: new mechanisms have no report stage; it is for spatial four-bars and stand-alone " \
                              "cams and planar linkages"


def test_the_stages_are_the_interfaces_names():
    assert [s.name for s in STAGES] == list(BY_STAGE)
    with pytest.raises(linkgen.UnsupportedError) as info:
        from linkgen.pipeline.registry import stage

        stage(MODELS["fourbar"], "kinematic")
    assert str(info.value) == "fourbar: 'kinematic' is not a stage; the stages are " + ", ".join(BY_STAGE)


# -- only the registry tells one kind of description from another -----------------------------

# What telling the families apart looks like outside the registry: the removed file helpers, the
# families' detectors, an isinstance on a family's description type, a peek at the text.
KIND_TESTS = re.compile(r"is_cam_file|is_spatial_file|load_cam\b|is_cam_data|is_spatial\(|"
                        r"isinstance\([^)]*\b(SpatialMechanism|CamMechanism)\b|\[machine\" in|"
                        r"get\(\"space\"\)|'space = \"spatial\"' in|\"\\n\[cam[.\]]\" (not )?in")


def test_nothing_outside_the_registry_tells_the_families_apart():
    """Every kind of file goes through ``linkgen.load`` and ``registry.family_of``: in the package
    the detectors live in their family's description module and are called by the registry only;
    validation/ and tests/ ask the registry too."""
    pkg = ROOT / "linkgen"
    own = {pkg / "families" / "cam" / "description.py", pkg / "families" / "spatial" / "description.py"}
    files = [p for p in pkg.rglob("*.py") if "pipeline" not in p.relative_to(pkg).parts and p not in own]
    files += sorted((ROOT / "validation").glob("*.py")) + [p for p in sorted((ROOT / "tests").glob("*.py"))
                                                            if p.name != Path(__file__).name]
    found = [f"{p.relative_to(ROOT)}:{i}: {line.strip()}" for p in files
             for i, line in enumerate(p.read_text(encoding="utf-8").splitlines(), 1) if KIND_TESTS.search(line)]
    assert not found, "\n".join(found)


def test_a_non_finite_entry_is_shown_as_the_number_it_is():
    # before: "phi: expected finite numbers, got np.float64(nan) at index 1"
    with pytest.raises(linkgen.ArgumentError) as info:
        linkgen.kinematics(MODELS["rssr"], np.array([0.0, np.nan]))
    assert str(info.value) == "phi: expected finite numbers, got nan at index 1"


def test_profile_for_the_cam_and_a_one_line_refusal_for_the_others():
    p = linkgen.profile(MODELS["cam_translating"], 36)
    assert p.profile.shape == (36, 2) and p.pitch.shape == (36, 2)
    with pytest.raises(linkgen.UnsupportedError) as info:
        linkgen.profile(MODELS["fourbar"])
    assert str(info.value) == "fourbar: planar linkages have no profile stage; it is for stand-alone cams"
    with pytest.raises(linkgen.ArgumentError) as info:
        linkgen.profile(MODELS["cam_translating"], 0)
    assert str(info.value) == "points: expected a whole number from 1 to 1000000 (as `linkgen profile --points`), got 0"


@pytest.mark.parametrize("options, message", [
    # before: "ValueError: could not convert string to float: '120rpm'" (every other function takes it)
    ({"omega": "fast"}, "omega: expected a number in rad/s or one with its unit (e.g. 100rpm), got 'fast'"),
    ({"omega": [1.0, 2.0]}, OMEGA),
    # before: "TypeError: must be real number, not str"
    ({"revolutions": "2"}, "revolutions: expected a positive number (or None), got '2'"),
    ({"samples": 0}, "samples: expected a whole number from 1 to 1000000 (or None), got 0"),
    ({"nthread": 1.5}, "nthread: expected a whole number from 1 (or None), got 1.5"),
])
def test_simulate_reads_its_options_as_the_api_does(options, message):
    with pytest.raises(linkgen.ArgumentError) as info:
        linkgen.simulate(MODELS["fourbar"], **options)
    assert str(info.value) == message


def test_simulate_takes_a_speed_with_its_unit():
    # 2 rad/s as "2rad/s": the same run; a few samples keep it cheap
    a = linkgen.simulate(MODELS["fourbar"], omega="2rad/s", samples=4)
    b = linkgen.simulate(MODELS["fourbar"], omega=2.0, samples=4)
    np.testing.assert_array_equal(a.samples.time, b.samples.time)


def test_each_api_function_calls_a_stage_of_the_interface_and_is_exported():
    from linkgen.api import FUNCTIONS

    assert set(FUNCTIONS.values()) <= set(BY_STAGE)
    assert set(FUNCTIONS) <= set(linkgen.__all__)
    assert all(f"``{name}``" in linkgen.api.__doc__ for name in FUNCTIONS)


def test_validate_takes_its_documented_source_option():
    """validate(m, source=...) clashed with the function's own parameter name (a bare TypeError,
    found by the second audit); the description is positional-only now. An unknown option beside
    it is still refused by name, before any MuJoCo run."""
    import linkgen
    from linkgen.errors import ArgumentError

    mech = linkgen.load(Path(__file__).resolve().parent.parent / "models" / "fourbar.toml")
    with pytest.raises(ArgumentError, match="bogus: not an option of linkgen.validate"):
        linkgen.validate(mech, source="models/fourbar.toml", bogus=1)
