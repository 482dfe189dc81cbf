"""Integrations with other tools: the pytest plugin and helpers for users' own tests."""
