"""Names in a description: the ground link's name and the rule every name follows."""

from __future__ import annotations

import re

from linkgen.errors import DescriptionError
from linkgen.model.units import shown, shown_field

GROUND = "ground"
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")


def check_name(name: object, where: str) -> str:
    if not isinstance(name, str) or not _NAME.match(name):
        raise DescriptionError(
            shown_field(where), f"must be a name of letters, digits and '_' not starting with a digit, got "
            f"{shown(name)}" + (f" ({len(name)} characters)" if isinstance(name, str) and shown(name) != repr(name)
                                else "")
        )
    return name
