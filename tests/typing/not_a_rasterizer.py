"""Checked by mypy in tests/test_typing.py: this must be rejected."""

from harness import Rasterizer


class NoRasterize:
    name = "incomplete"
    convention = None


wrong: Rasterizer = NoRasterize()
