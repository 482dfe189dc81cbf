"""Checked by mypy in tests/acceptance/test_typing.py: this must be rejected."""

from harness import Rasterizer


class NoRasterize:
    name = "incomplete"
    convention = None


wrong: Rasterizer = NoRasterize()
