"""The ``rastercheck`` command line: one module per job, with ``main`` the entry point."""
