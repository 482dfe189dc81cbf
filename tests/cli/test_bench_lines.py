"""The bench's line workloads at a tiny size: their structure, the three line oracles'
answers (Bresenham's in closed form; diamond-exit's and the rectangle's pinned, checked once
against the rational brute force, diamond_exit_spans_rational and rectangle_spans_rational,
segment by segment), the library peers drawing the same segments, and each line-taking
rasterizer measured. No timing assertion."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

from harness.cli.bench import (
    LINE_ORACLES,
    _contenders,
    format_table,
    line_workloads,
    missing_peers,
    run_bench,
    write_json,
)
from harness.cli.bench_peers import _line_peers, _pillow_lines, _Surface
from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import LineScene
from harness.oracle.coverage import exact_coverage
from tests.narrow import lines

SCALE = 0.01  # 1,000 short segments, 10 long ones

# The oracles' fragments on the 1,000 short segments; each confirmed by the rational
# reference on every segment in a viewport of its own (moved by whole pixels: exact).
SHORT_PIXELS = {"oracle_diamond_exit": 8_051, "oracle_rectangle": 9_005}


def test_the_line_workloads_are_short_and_long_segments_inside_the_screen() -> None:
    short, long = line_workloads(SCALE)
    assert (short.name, long.name) == ("L1", "L2")
    for work, count in ((short, 1000), (long, 10)):
        scene = work.scene
        assert isinstance(scene, LineScene) and (scene.width, scene.height) == (1024, 1024) and scene.line_width == 1.0
        assert len(scene) == count and scene.strip_sizes.tolist() == [2] * count  # separate segments
        a, b = scene.segments()
        ends = np.concatenate([a, b])
        assert (ends >= 0.5).all() and (ends <= 1023.5).all()  # no peer clips
        assert work.mean_area == pytest.approx(np.hypot(*(b - a).T).mean()) and f"{count:,} " in work.description
    lengths = [np.hypot(*np.subtract(*lines(w.scene).segments()).T) for w in (short, long)]
    assert lengths[0].min() >= 2.0 and lengths[0].max() <= 16.0 and lengths[1].min() >= 256.0
    full = line_workloads(1.0)
    assert [len(w.scene) for w in full] == [100_000, 1_000]


def _bresenham_fragments(scene: LineScene) -> int:
    """Bresenham draws K + 1 pixels, K the larger of |di| and |dj| between the end pixels
    (the pixel whose centre is nearest each end point; no end point here lies on a pixel
    border, so the rounding of ties does not matter)."""
    a, b = scene.segments()
    pa, pb = np.floor(a), np.floor(b)
    return int((np.abs(pb - pa).max(axis=1) + 1).sum())


@pytest.mark.parametrize("work", [0, 1])
def test_the_bresenham_oracle_draws_one_pixel_per_major_step(work: int) -> None:
    scene = lines(line_workloads(SCALE)[work].scene)
    a, b = scene.segments()
    assert not (np.concatenate([a, b]) == np.floor(np.concatenate([a, b]))).any()
    assert exact_coverage(scene, LINE_ORACLES["oracle_bresenham"]).n_pixels == _bresenham_fragments(scene)


@pytest.mark.parametrize("label", list(SHORT_PIXELS))
def test_the_oracles_on_the_short_segments_equal_the_reference_counts(label: str) -> None:
    scene = line_workloads(SCALE)[0].scene
    assert exact_coverage(scene, LINE_ORACLES[label]).n_pixels == SHORT_PIXELS[label]


def test_run_bench_measures_the_line_workloads_against_pillow() -> None:
    results = run_bench([], scale=SCALE, budget=0.0, paths=False, triangles=False)
    by_work: dict[str, list[Any]] = {}
    for m in results:
        by_work.setdefault(m.workload, []).append(m)
    assert list(by_work) == ["L1", "L2"]
    peers = [label for label, _ in _line_peers()]
    for ms in by_work.values():
        labels = [m.contender for m in ms]
        assert labels == ["pillow", "oracle_diamond_exit", "oracle_bresenham", "oracle_rectangle", *peers]
        assert ms[0].ratio_to_pillow == 1.0
        assert all(m.unit == "segments" and m.description and m.seconds > 0 and m.pixels > 0 for m in ms)
        assert all(m.ratio_to_pillow == pytest.approx(ms[0].seconds / m.seconds) for m in ms)
    scene = lines(line_workloads(SCALE)[0].scene)
    oracle = {m.contender: m.pixels for m in by_work["L1"]}
    assert oracle["oracle_diamond_exit"] == SHORT_PIXELS["oracle_diamond_exit"]
    assert oracle["oracle_bresenham"] == _bresenham_fragments(scene)
    table = format_table(results, {})
    assert "L1: 1,000 short segments, mean length" in table and "segments/s" in table


def test_the_json_carries_the_line_workloads(tmp_path: Path) -> None:
    results = run_bench([], scale=SCALE, budget=0.0, paths=False, triangles=False)
    write_json(results, tmp_path / "b.json")
    rows = json.loads((tmp_path / "b.json").read_text())["results"]
    assert {(r["workload"], r["unit"]) for r in rows} == {("L1", "segments"), ("L2", "segments")}


class TakesLines:
    name = "takes-lines"
    convention = Convention(line="bresenham")
    scene_kinds = ("lines",)

    def rasterize(self, scene: LineScene) -> Any:
        return exact_coverage(scene, self.convention)


class TrianglesOnly:
    name = "triangles-only"
    convention = Convention()

    def rasterize(self, scene: Any) -> Any:
        return exact_coverage(scene, self.convention)


def test_a_rasterizer_is_measured_on_the_line_workloads_when_it_takes_lines() -> None:
    short = line_workloads(SCALE)[0]
    labels = [label for label, _ in _contenders(short, [TakesLines(), TrianglesOnly()])]
    assert "takes-lines" in labels and "triangles-only" not in labels
    drawn = dict(_contenders(short, [TakesLines()]))["takes-lines"]()
    assert isinstance(drawn, Coverage)
    assert drawn.n_pixels == _bresenham_fragments(lines(short.scene))


def _drawn(result: object) -> np.ndarray:
    image = result.read() if isinstance(result, _Surface) else np.asarray(result)
    return image > 0


# The oracle each library's aliased lines come nearest to on these segments: Pillow and
# scikit-image run integer Bresenham between the end points' pixels (exactly the oracle's
# pixels here: no end point on a border, the same tie rule); cairo strokes a 1-px-wide
# rectangle (the rectangle oracle but for its own sampling at a few pixels); skia's
# hairlines step like the diamond-exit rule (but for some end pixels).
NEAREST = {"pillow": ("oracle_bresenham", True), "skimage_line": ("oracle_bresenham", True),
           "cairo_line": ("oracle_rectangle", False), "skia_hairline": ("oracle_diamond_exit", False)}


@pytest.mark.parametrize("peer", list(NEAREST))
def test_the_library_peers_draw_the_same_segments(peer: str) -> None:
    draws = {"pillow": _pillow_lines, **dict(_line_peers())}
    if peer not in draws:
        pytest.skip(f"{peer}: {missing_peers().get(peer, 'its library is not installed')}")
    for work in line_workloads(SCALE):
        scene = lines(work.scene)
        drawn = _drawn(draws[peer](scene))
        differ = {label: int((drawn != (exact_coverage(scene, c).counts(1024, 1024) > 0)).sum())
                  for label, c in LINE_ORACLES.items()}
        nearest, exactly = NEAREST[peer]
        assert min(differ, key=differ.__getitem__) == nearest, (work.name, differ)
        if exactly:
            assert differ[nearest] == 0, (work.name, differ)
        else:  # clearly nearer to it than to the others (skia: 752 pixels against 1,186 and 4,202 on L1)
            assert all(differ[nearest] * 1.5 < v for label, v in differ.items() if label != nearest), (work.name, differ)
