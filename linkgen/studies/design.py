"""One variant as a description of its own: the base description with the varied fields set
and its sketch re-assembled from the new lengths (``families.planar.sketch.exact_sketch``: the
old sketch only chooses each group's assembly mode), so that it loads, validates and draws as a
file the user wrote."""

from __future__ import annotations

from linkgen.studies.fields import override


def moved_points(data: dict, source: str, given: dict[str, float]) -> dict[str, list[float]]:
    """The sketch points the variant ``given`` (path → value [SI]) moves, at their exact places
    (a point whose coordinate is itself varied keeps it)."""
    from linkgen.families.planar.sketch import exact_sketch
    from linkgen.pipeline.registry import from_dict

    sketch = exact_sketch(from_dict(override(data, given), source))
    return {name: [x, y] for name, (x, y) in sketch.points.items()
            if sketch.moved[name] > 0.0 and not any(p.startswith((f"points.{name}.", f"points.{name}["))
                                                    for p in given)}


def variant_data(data: dict, source: str, given: dict[str, float]) -> dict:
    """The parsed TOML of the variant ``given``, its sketch re-assembled."""
    out = override(data, given)
    out["points"].update(moved_points(data, source, given))
    return out


__all__ = ["moved_points", "variant_data"]
