"""The package's layout: one subpackage per pipeline stage in the order data flows (families
inside the stages), packages import only downward, no import cycles, small modules.

Import edges are read from the source (``ast``), counting imports inside functions too;
imports under ``if TYPE_CHECKING:`` are annotations only and do not count."""

from __future__ import annotations

import ast
from pathlib import Path

import linkgen

PACKAGE = Path(linkgen.__file__).parent
# The stages, lowest first (docs/architecture.md): a package may import only packages before it.
# ``families`` holds one closed form per family; a family imports only those before it in
# FAMILIES (a planar linkage's cam pair moves by the cam family's motion programs). ``pipeline`` is the registry of families, written against every stage
# below it; the CLI and the API are written once against it; ``studies`` sweeps and optimises
# designs through it; ``referee`` judges a solver's results through it.
STAGES = ("model", "families", "machine", "mujoco", "crosscheck", "draw", "report", "pipeline", "studies", "referee", "cli")
FAMILIES = ("cam", "spatial", "planar")
# A module past ~300 lines is asking to be split (the project's style guide); 450 leaves room
# for a generator of test mechanisms (planar/corpus.py), the largest module, and no more.
MAX_LINES = 450


def _modules() -> dict[str, Path]:
    out = {}
    for p in PACKAGE.rglob("*.py"):
        parts = p.relative_to(PACKAGE.parent).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        out[name] = p
    return out


def _type_checking_nodes(tree: ast.AST) -> set[int]:
    skip = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.If) and getattr(node.test, "id", None) == "TYPE_CHECKING":
            skip |= {id(n) for n in ast.walk(node)}
    return skip


def _edges(mods: dict[str, Path]) -> dict[str, set[str]]:
    edges = {m: set() for m in mods}
    for m, p in mods.items():
        tree = ast.parse(p.read_text(encoding="utf-8"))
        skip = _type_checking_nodes(tree)
        for node in ast.walk(tree):
            if id(node) in skip:
                continue
            if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("linkgen"):
                assert node.level == 0, f"{p}: relative import; the package uses absolute imports"
                targets = {f"{node.module}.{a.name}" for a in node.names} | {node.module}
                edges[m] |= {t for t in targets if t in mods and t not in ("linkgen", m)}
            elif isinstance(node, ast.Import):
                edges[m] |= {a.name for a in node.names if a.name in mods and a.name != m}
    return edges


def _cycle(edges: dict[str, set[str]]) -> list[str] | None:
    state: dict[str, int] = {}
    path: list[str] = []

    def visit(v: str) -> list[str] | None:
        state[v] = 1
        path.append(v)
        for w in sorted(edges[v]):
            if state.get(w) == 1:
                return path[path.index(w):] + [w]
            if w not in state and (found := visit(w)):
                return found
        state[v] = 2
        path.pop()
        return None

    for v in sorted(edges):
        if v not in state and (found := visit(v)):
            return found
    return None


def test_stages_are_subpackages():
    for stage in STAGES:
        assert (PACKAGE / stage / "__init__.py").is_file(), stage
    for family in FAMILIES:
        assert (PACKAGE / "families" / family / "__init__.py").is_file(), family
    loose = sorted(p.name for p in PACKAGE.glob("*.py"))
    assert loose == ["__init__.py", "__main__.py", "api.py", *sorted(f"{m}.py" for m in BOTTOM)], loose


# Modules beside the stages, below all of them: the error hierarchy, the one output writer and
# the one extremum finder every stage uses. They import no stage (only each other).
BOTTOM = ("errors", "outputs", "extrema")


def test_bottom_modules_import_no_stage():
    edges = _edges(_modules())
    for m in BOTTOM:
        above = sorted(e for e in edges[f"linkgen.{m}"] if e.removeprefix("linkgen.") not in BOTTOM)
        assert not above, (m, above)


def _package(module: str) -> str:
    parts = module.split(".")
    if len(parts) > 2 and parts[1] == "families":
        return f"families.{parts[2]}"
    return parts[1] if len(parts) > 1 else "linkgen"


def _rank(package: str) -> int:
    if package in BOTTOM:
        return -1
    if package in ("api", "linkgen", "__main__"):
        return len(STAGES)  # the top: the API and the command line
    return STAGES.index(package.split(".")[0])


def test_every_module_belongs_to_a_stage():
    for m in _modules():
        p = _package(m)
        assert p in ("linkgen", "api", "__main__") or p in BOTTOM or p.split(".")[0] in STAGES, m
    assert sorted(p.name for p in (PACKAGE / "families").iterdir() if (p / "__init__.py").is_file()) == sorted(FAMILIES)


def test_packages_import_only_downward():
    """A stage imports only the stages before it (and the bottom modules); a family's closed form
    imports no other family's."""
    edges = _edges(_modules())
    upward = []
    for m, targets in edges.items():
        a = _package(m)
        for t in targets:
            b = _package(t)
            if a == b:
                continue
            if a.startswith("families.") and b.startswith("families."):
                if FAMILIES.index(b.split(".")[1]) > FAMILIES.index(a.split(".")[1]):
                    upward.append(f"{m} -> {t} (a family into one after it)")
            elif _rank(b) > _rank(a) or (_rank(b) == _rank(a) and -1 < _rank(a) < len(STAGES) - 1):
                upward.append(f"{m} -> {t}")
    assert not upward, "\n".join(sorted(upward))


def test_the_order_check_finds_an_upward_import():
    assert _rank("mujoco") > _rank("families.planar") > _rank("model") > _rank("errors")
    assert _package("linkgen.families.cam.laws") == "families.cam" and _package("linkgen.report.report") == "report"


def test_no_import_cycles():
    assert _cycle(_edges(_modules())) is None


def test_the_cycle_finder_finds_a_cycle():
    assert _cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert _cycle({"a": {"b"}, "b": set()}) is None


def test_no_module_is_too_long():
    long = {str(p.relative_to(PACKAGE)): n for p in PACKAGE.rglob("*.py")
            if (n := len(p.read_text(encoding="utf-8").splitlines())) > MAX_LINES}
    assert not long, long


def test_the_model_stage_does_not_reach_mujoco_or_the_cli():
    edges = _edges(_modules())
    for m, targets in edges.items():
        if m.startswith(("linkgen.model", "linkgen.families.planar")):
            bad = {t for t in targets if t.startswith(("linkgen.mujoco", "linkgen.crosscheck", "linkgen.cli"))}
            assert not bad, (m, bad)


def test_the_api_does_not_reach_into_the_command_line():
    """The API and the CLI are both written against the registry; neither is built on the other."""
    edges = _edges(_modules())
    for m in ("linkgen", "linkgen.api"):
        assert not {t for t in edges[m] if t.startswith("linkgen.cli")}, m
