"""What the report drew, read back in tests: the SVG attributes and titles a test needs,
which must be there (an assertion names the one missing), as ``str`` and ``float``; a
failure's drawn case and its repro picture, which must exist."""

from __future__ import annotations

import xml.etree.ElementTree as ET

from harness.checks import Result
from harness.contract.case import Case

SVG = "{http://www.w3.org/2000/svg}"


def attr(element: ET.Element, name: str) -> str:
    """The attribute ``name`` of ``element``, which must have it."""
    value = element.get(name)
    assert value is not None, f"<{element.tag}> has no {name}"
    return value


def number(element: ET.Element, name: str) -> float:
    """The attribute ``name`` of ``element`` as a number."""
    return float(attr(element, name))


def titled(element: ET.Element) -> ET.Element:
    """The <title> child of ``element``, which must have one."""
    title = element.find(SVG + "title")
    assert title is not None, f"<{element.tag}> has no <title>"
    return title


def title_text(element: ET.Element) -> str:
    """The text of the <title> of ``element`` ("" when empty)."""
    return titled(element).text or ""


def drawn_case(result: Result) -> Case:
    """The still case a failure's drawing shows."""
    assert result.drawing is not None and isinstance(result.drawing.case, Case), result
    return result.drawing.case


def repro_picture(result: Result) -> tuple[str, str]:
    """The repro picture of a failure (its data URI and caption), which must have one."""
    from harness.report import pictures

    drawn = pictures.draw_repro(result)
    assert drawn is not None and drawn[0] is not None, result
    return drawn[0], drawn[1]


def repro_drawn(result: Result) -> tuple[str | None, str]:
    """What the report says of a failure's repro: its picture (None when too large to draw)
    and the caption; the failure must have a repro."""
    from harness.report import pictures

    drawn = pictures.draw_repro(result)
    assert drawn is not None, result
    return drawn
