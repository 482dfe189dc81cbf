"""Deliberately broken rasterizers: each check must fail on at least one of them."""
