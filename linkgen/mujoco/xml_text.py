"""Text in the MJCF files linkgen writes: every comment goes through ``comment``, which makes any
text (a description's title included) one that XML carries. A comment may not hold ``--`` or end
with ``-``, and XML 1.0 carries no control character but tab and line ends; lxml raises on both."""

from __future__ import annotations

import re

from lxml import etree

# Characters XML 1.0 cannot carry: C0 controls but tab, LF and CR; surrogates; U+FFFE and U+FFFF.
_NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ud800-\udfff\ufffe\uffff]")


def xml_safe(text: str) -> str:
    """``text`` with each character XML 1.0 cannot carry written as its code (``U+0007``)."""
    return _NOT_XML.sub(lambda m: f"U+{ord(m.group()):04X}", text)


def comment(text: str) -> etree._Comment:
    """An XML comment holding ``text``: characters XML cannot carry written as their codes, each
    ``--`` broken by a space and a space after a final ``-``."""
    body = xml_safe(text)
    while "--" in body:
        body = body.replace("--", "- -")
    if body.endswith("-"):
        body += " "
    return etree.Comment(body)


__all__ = ["comment", "xml_safe"]
