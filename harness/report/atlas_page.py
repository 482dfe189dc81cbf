"""The atlas page: :mod:`harness.results.atlas`'s document as one HTML page, written
atomically beside the run report it links to (``atlas.html`` in the same folder)."""

from __future__ import annotations

from pathlib import Path
from typing import Any

from harness.contract.conventions import FILL_RULES
from harness.report.pages import _environment, page_meta
from harness.results.atlas import ATLAS_KINDS
from harness.results.files import atomic_write_text

__all__ = ["ATLAS_PAGE", "MODES", "write_atlas_page"]

ATLAS_PAGE = "atlas.html"
# the coverage kinds as the atlas's modes
MODES = {"single": "aliased", "multisample": "multisample", "area": "anti-aliased"}
NEAREST = 30  # pairs listed, the nearest first


def write_atlas_page(out_dir: Path | str, document: dict[str, Any]) -> Path:
    """Write ``atlas.html`` into ``out_dir``; returns its path."""
    pairs = sorted(document["pairs"], key=lambda p: (p["differing"] / max(p["pixels"], 1), p["kind"], p["a"], p["b"]))
    adapters = sum(len(lib["adapters"]) for lib in document["libraries"])
    meta = page_meta(document["suite"], document["seed"], document["seconds"])
    html = _environment().get_template("atlas.html").render(doc=document, kinds=ATLAS_KINDS, modes=MODES, adapters=adapters,
                                                            nearest=pairs[:NEAREST], meta=meta,
                                                            all_rules=FILL_RULES)
    path = Path(out_dir) / ATLAS_PAGE
    atomic_write_text(path, html)
    return path
