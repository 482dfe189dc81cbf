"""Adapters for real rasterizers nobody here wrote: Mesa (llvmpipe, softpipe) through
moderngl's EGL backend, cairo, skia, Pillow and scikit-image.

Install them with ``pip install '.[real]'`` (cairo also needs Debian's libcairo2-dev, Mesa
its EGL packages). None of them declares a convention: ``rastercheck identify`` finds it.
An adapter whose library is missing raises :class:`harness.engine.registry.Unavailable` with the
exact install hint, and the run reports it as skipped.
"""
