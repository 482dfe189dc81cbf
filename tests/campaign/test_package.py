"""``harness.campaign``: a light package whose names resolve lazily to their modules."""

from __future__ import annotations

import importlib
import subprocess
import sys

import harness.campaign


def test_importing_the_package_imports_none_of_its_modules() -> None:
    """A fresh interpreter: ``import harness.campaign`` loads no submodule (no Dask, no diagnosis)."""
    probe = ("import sys, harness.campaign\n"
             "print(sorted(m for m in sys.modules if m.startswith('harness.campaign.') or m == 'distributed'))")
    shown = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, check=True).stdout.strip()
    assert shown == "[]", shown


def test_every_exported_name_is_its_modules_own() -> None:
    for name in harness.campaign.__all__:
        module = importlib.import_module(f"harness.campaign.{harness.campaign._HOME[name]}")
        assert getattr(harness.campaign, name) is getattr(module, name), name
    assert harness.campaign.run_campaign.__module__ == "harness.campaign.coordinator"


def test_an_unknown_name_is_an_attribute_error() -> None:
    try:
        harness.campaign.Finding  # noqa: B018 - the old name is gone: SceneFinding says what it is
    except AttributeError as exc:
        assert "Finding" in str(exc)
    else:
        raise AssertionError("harness.campaign.Finding resolved")
