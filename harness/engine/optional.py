"""The optional libraries, each named once with how to install it.

rastercheck itself needs only what ``pip install -e .`` brings. The real-rasterizer
adapters, the bench's library peers and some tests need more (pycairo needs cairo's
Debian headers to build; moderngl needs Mesa's EGL at run time). Whatever needs one asks
:func:`missing` and, when it answers, skips with that sentence: what is missing and how to
install it, and why ``make`` could not install it on this machine if it tried.

>>> INSTALLS["cairo"].extra
'cairo'
>>> missing("numpy") is None
True
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path

__all__ = ["Install", "INSTALLS", "missing", "install_failure"]


@dataclass(frozen=True, slots=True)
class Install:
    """How to install an optional module.

    Attributes
    ----------
    extra : str or None
        The pip extra of rastercheck that installs it (``pip install -e '.[extra]'``);
        ``make`` installs each extra on its own and keeps pip's log as
        ``.venv/install-<extra>.log``.
    hint : str
        The command(s) that install it, Debian packages first where it needs some.
    """

    extra: str | None
    hint: str


INSTALLS: dict[str, Install] = {
    "cairo": Install("cairo", "apt-get install libcairo2-dev pkg-config && pip install -e '.[cairo]'   (pycairo; or '.[real]')"),
    "skia": Install("skia", "pip install -e '.[skia]'   (skia-python; or '.[real]')"),
    "moderngl": Install("gl", "pip install -e '.[gl]'   (moderngl; or '.[real]'), with Mesa's EGL: "
                              "apt-get install libegl1 libgl1-mesa-dri"),
    "wgpu": Install("vulkan", "pip install -e '.[vulkan]'   (wgpu), with Mesa's Vulkan driver lavapipe: "
                              "apt-get install mesa-vulkan-drivers"),
    "freetype": Install("freetype", "pip install -e '.[freetype]'   (freetype-py)"),
    "aggdraw": Install("agg", "pip install -e '.[agg]'   (aggdraw)"),
    "matplotlib": Install(None, "pip install matplotlib   (a dependency of rastercheck's own)"),
    "PyQt6": Install("qt", "pip install -e '.[qt]'   (PyQt6)"),
    "blend2d": Install("blend2d", "pip install -e '.[blend2d]'   (blend2d-python)"),
    "resvg_py": Install("tiny_skia", "pip install -e '.[tiny_skia]'   (resvg-py: tiny-skia through resvg)"),
    "pygame": Install("pygame", "pip install -e '.[pygame]'"),
    "PIL": Install(None, "pip install pillow"),
    "skimage": Install(None, "pip install scikit-image"),
}


def install_failure(module: str) -> str:
    """Why ``make`` could not install ``module`` here (the first error line of its pip log),
    as a clause to append to a message; ``""`` when it did not try or left no log."""
    install = INSTALLS.get(module)
    if install is None or install.extra is None:
        return ""
    log = Path(sys.prefix) / f"install-{install.extra}.log"
    try:
        text = log.read_text(errors="replace").splitlines()
    except OSError:
        return ""
    # the build's own error (e.g. meson's "ERROR: Dependency "cairo" not found") says most
    lines = [line.strip() for line in text if "ERROR:" in line] or [line.strip() for line in text if "rror" in line]
    return f"; its install failed on this machine ({lines[0][:160]}; see {log})" if lines else ""


def missing(module: str) -> str | None:
    """``None`` when ``module`` imports here; otherwise one sentence saying it is missing,
    how to install it, and why ``make``'s install of it failed here, if it did."""
    try:
        __import__(module)
    except Exception as exc:  # noqa: BLE001 - not installed, or installed and broken: either way not usable
        install = INSTALLS.get(module)
        hint = install.hint if install is not None else f"pip install {module}"
        return f"{module} is not installed ({type(exc).__name__}): {hint}{install_failure(module)}"
    return None
