"""Campaigns: search many generated scenes for failures, on one machine or a Dask cluster.

The package in four modules, one job each: :mod:`~harness.campaign.state` (the records and
the resumable state folder), :mod:`~harness.campaign.worker` (one batch run on a worker,
a finding shrunk to its repro), :mod:`~harness.campaign.cluster` (the Dask cluster) and
:mod:`~harness.campaign.coordinator` (:func:`run_campaign`'s loop). The names below are
re-exported lazily (PEP 562): importing the package imports none of them, so no layer
below pays for Dask or the diagnosis.
"""

from __future__ import annotations

import importlib
from typing import Any

_HOME = {
    "Batch": "state", "BatchResult": "state", "CampaignError": "state", "CampaignState": "state", "CampaignTask": "state",
    "ProgressEvent": "state", "SceneFinding": "state", "CAMPAIGN_SCHEMA": "state", "SCHEMA": "state",
    "add_interval": "state", "overlap": "state", "state_lock": "state",
    "attribute_causes": "worker", "plain_data": "worker", "run_batch": "worker", "shrink_finding": "worker",
    "QUIET_DASK": "cluster", "connect": "cluster", "local_cluster": "cluster", "scheduler_address": "cluster",
    "run_campaign": "coordinator",
}

__all__ = sorted(_HOME)


def __getattr__(name: str) -> Any:
    """``harness.campaign.run_campaign`` and the rest of :data:`__all__`, imported from their
    module on first use."""
    if name in _HOME:
        return getattr(importlib.import_module(f"harness.campaign.{_HOME[name]}"), name)
    raise AttributeError(f"module 'harness.campaign' has no attribute {name!r}")
