"""Faithful ports of peers' rasterizers (dEQP's reference renderer, stb_truetype, FreeType's
smooth rasterizer), each checked against its original C or C++ compiled here
(:mod:`tests.peers.compiled`), and judged by the harness against its own convention."""
