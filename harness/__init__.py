"""rastercheck: a rasterization conformance and artifact test harness.

>>> from harness import Scene, Coverage, Convention, Rasterizer
"""

from harness.api import Convention, Coverage, Rasterizer, Scene

__all__ = ["Scene", "Coverage", "Convention", "Rasterizer"]
__version__ = "0.1.0"
