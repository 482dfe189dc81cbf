"""Campaigns: search many generated scenes for failures, on one machine or a Dask cluster."""
