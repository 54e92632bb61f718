"""Names in a description: the ground link's name and the rule every name follows."""

from __future__ import annotations

import re

from linkgen.errors import DescriptionError
from linkgen.model.units import shown, shown_field

GROUND = "ground"
_NAME = re.compile(r"^[A-Za-z_][A-Za-z0-9_]*$")
# Longest name [characters]: a mechanism's name starts the names of the files written for it
# ("<name>_acceleration_plan.png", at most 127 more characters), and a file name may hold at most
# 255 bytes (Linux's NAME_MAX); names are ASCII, so characters are bytes.
MAX_NAME_LENGTH = 128


def check_name(name: object, where: str) -> str:
    if not isinstance(name, str) or not _NAME.match(name):
        raise DescriptionError(
            shown_field(where), f"must be a name of letters, digits and '_' not starting with a digit, got "
            f"{shown(name)}" + (f" ({len(name)} characters)" if isinstance(name, str) and shown(name) != repr(name)
                                else "")
        )
    if len(name) > MAX_NAME_LENGTH:
        raise DescriptionError(shown_field(where), f"must be at most {MAX_NAME_LENGTH} characters (names start the names "
                                                   f"of the files written for the mechanism), got {len(name)}")
    return name
