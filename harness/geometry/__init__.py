"""Exact geometry and the compiled-kernel toolkit: exact predicates on float64 input, span
arithmetic, sorted keys, sorts inside kernels, and numba's cache made safe. The floor
everything else stands on."""
