"""``python -m harness.cli``: the same as the ``rastercheck`` command."""

from harness.cli.main import main

raise SystemExit(main())
