"""Diagnosis of failures: signatures that name a failure's cause, the grouping by cause,
minimal repros, and comparisons between rasterizers."""
