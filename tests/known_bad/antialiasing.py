"""Known-bad multisample and anti-aliasing rasterizers (issue 14): each gets one classic
thing wrong -- the sample table, the sample bits, the tie rule at the samples, the 8-bit
conversion, the method per edge (cairo's 2010 seam), the promise of analytic coverage, the
precision of an edge stepped down the rows -- and must fail the check that judges it, for
that reason.

The exact oracles are the building blocks where the bug lies elsewhere (a mirrored table
is the exact coverage of the mirrored pattern; a coarse supersampler is the exact share of
a 4 x 4 grid); the tie and per-edge bugs have kernels of their own.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from harness.contract.conventions import Convention
from harness.contract.coverage import Coverage
from harness.contract.scenes import Scene
from harness.geometry.exact import frozen
from harness.oracle.area import area_coverage
from harness.oracle.area import edge_integral as _exact_integral  # the area oracle's exact edge integral (Green's theorem)
from harness.oracle.coverage import exact_coverage, sample_shares
from rasterizers._common import screen_triangles
from rasterizers.area_scanline import _accumulate_piece, emit_row, first_capacity

__all__ = ["MirroredPattern", "SwappedSampleBits", "InclusiveSampleTies", "InclusiveSupersampledTies", "BiasedArea",
           "PerEdgeMethodSwitch", "CoarseSupersampleClaimsAnalytic", "Float32EdgeStepping", "GRID_4X4",
           "GammaEncodedArea", "HalfPixelShiftedArea", "TruncatedArea", "FourBitArea", "DriftingStepArea",
           "RejectsNearEdges", "CentreSamples"]

# the largest |coordinate| the per-edge kernel accepts (a float kernel's limit, as area_scanline's)
MAX_COORDINATE = 2.0**24
# the 4 x 4 grid's sample offsets, row by row: ((i + 0.5) / 4, (j + 0.5) / 4), exact floats
GRID_4X4 = tuple(((i + 0.5) / 4, (j + 0.5) / 4) for j in range(4) for i in range(4))


def _geometry(scene: Scene) -> Scene:
    """The scene without attributes: these rasterizers interpolate nothing, and the
    oracle need not either."""
    return Scene(scene.width, scene.height, scene.positions)


def _eight_bit(alpha: np.ndarray) -> np.ndarray:
    """An alpha in [0, 1] rounded to the nearest of 256 levels."""
    rounded: np.ndarray = np.rint(np.clip(alpha, 0.0, 1.0) * 255.0) / 255.0
    return rounded


class MirroredPattern:
    """Declares the standard 4x pattern, samples it mirrored in x (a sample table indexed
    for the other x direction): sample s at (1 - x_s, y_s). Each sample's coverage is
    exact -- at the wrong offset."""

    name = "bad_mirrored_pattern"
    convention = Convention(samples=4)
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        mirrored = Convention(samples=[(1.0 - x, y) for x, y in self.convention.samples])
        cov = exact_coverage(_geometry(scene), mirrored)
        return Coverage(cov.triangle, cov.y, cov.x0, cov.x1, sample=cov.sample)


class SwappedSampleBits:
    """Declares the standard 4x pattern and tests each sample at its offset, but reports
    sample index s with its two bits swapped (1 <-> 2): a coverage mask packed in the
    wrong bit order."""

    name = "bad_swapped_sample_bits"
    convention = Convention(samples=4)
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        cov = exact_coverage(_geometry(scene), self.convention)
        assert cov.sample is not None
        swapped = ((cov.sample & 1) << 1) | ((cov.sample & 2) >> 1)
        return Coverage(cov.triangle, cov.y, cov.x0, cov.x1, sample=swapped)


@numba.njit(cache=True)
def _inclusive_kernel(positions, offsets, width, height):
    """(triangle, sample, x, y) of every sample an edge-function test with ``>= 0`` puts
    inside: each edge takes the samples exactly on it (no tie rule)."""
    out_t = []
    out_s = []
    out_x = []
    out_y = []
    for t in range(positions.shape[0]):
        p = positions[t].copy()
        if not np.all(np.isfinite(p)):
            continue
        area = (p[1, 0] - p[0, 0]) * (p[2, 1] - p[0, 1]) - (p[1, 1] - p[0, 1]) * (p[2, 0] - p[0, 0])
        if area == 0:
            continue
        if area < 0:  # the interior to the right of every edge
            p = p[np.array([0, 2, 1])]
        # clamp in floats before any integer (huge coordinates)
        x0 = int(max(np.floor(p[:, 0].min()) - 1.0, 0.0))
        x1 = int(min(np.ceil(p[:, 0].max()) + 1.0, float(width)))
        y0 = int(max(np.floor(p[:, 1].min()) - 1.0, 0.0))
        y1 = int(min(np.ceil(p[:, 1].max()) + 1.0, float(height)))
        for s in range(offsets.shape[0]):
            for yy in range(y0, y1):
                py = yy + offsets[s, 1]
                for xx in range(x0, x1):
                    px = xx + offsets[s, 0]
                    inside = True
                    for k in range(3):
                        ax, ay = p[k, 0], p[k, 1]
                        bx, by = p[(k + 1) % 3, 0], p[(k + 1) % 3, 1]
                        if (bx - ax) * (py - ay) - (by - ay) * (px - ax) < 0:  # the bug: == 0 counts as inside
                            inside = False
                            break
                    if inside:
                        out_t.append(t)
                        out_s.append(s)
                        out_x.append(xx)
                        out_y.append(yy)
    return (np.array(out_t, dtype=np.int64), np.array(out_s, dtype=np.int64), np.array(out_x, dtype=np.int64),
            np.array(out_y, dtype=np.int64))


class InclusiveSampleTies:
    """Declares the standard 4x pattern with top-left ties, tests every sample with
    ``E >= 0``: a sample exactly on an edge is inside both triangles sharing it (double
    hits on partitions whose shared edges pass through sample points)."""

    name = "bad_inclusive_sample_ties"
    convention = Convention(samples=4)
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        offsets = frozen(np.array(self.convention.samples, dtype=np.float64))
        with np.errstate(all="ignore"):
            t, s, x, y = _inclusive_kernel(frozen(scene.positions), offsets, scene.width, scene.height)
        if not t.size:
            return Coverage.empty()
        return Coverage.from_pixels(t, x, y, sample=s)


class InclusiveSupersampledTies:
    """Declares anti-aliased coverage as the share of a 4 x 4 grid's samples (top-left
    ties), counts every sample with ``E >= 0``: a sample exactly on an edge is inside, and
    a pixel's alpha is off by 1/16 for each (the issue's supersampled plugin with every edge
    made inclusive)."""

    name = "bad_inclusive_supersampled_ties"
    convention = Convention(coverage="area", samples=GRID_4X4, levels=17)  # alphas k/16
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        offsets = frozen(np.array(GRID_4X4, dtype=np.float64))
        with np.errstate(all="ignore"):
            t, s, x, y = _inclusive_kernel(frozen(scene.positions), offsets, scene.width, scene.height)
        if not t.size:
            return Coverage.empty()
        key = (t * scene.height + y) * scene.width + x
        keys, counts = np.unique(key, return_counts=True)
        triangle, pixel = np.divmod(keys, scene.height * scene.width)
        row, column = np.divmod(pixel, scene.width)
        return Coverage.from_pixels(triangle, column, row, alpha=counts / len(GRID_4X4))


class BiasedArea:
    """Declares analytic area coverage on 256 levels; converts the exact area to 8 bits as
    ``int(a * 255 + 2.5)`` (a rounding offset of 2.5 where 0.5 was meant): two levels too
    much on every pixel it touches, clamped to 255."""

    name = "bad_biased_area"
    convention = Convention(coverage="area")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        exact = area_coverage(scene, self.convention)
        assert exact.alpha is not None
        levels = np.minimum(np.floor(exact.alpha * 255.0 + 2.5), 255.0)
        return Coverage(exact.triangle, exact.y, exact.x0, exact.x1, alpha=levels / 255.0)


@numba.njit(cache=True, inline="always")
def _sampled_integral(ax, ay, bx, by):
    """The same signed area by 4 x 4 point sampling: the share of the grid's samples
    (x in the edge's half-open x-range, y above the edge)."""
    if ax == bx:
        return 0.0
    sign = 1.0
    if bx < ax:
        ax, ay, bx, by = bx, by, ax, ay
        sign = -1.0
    count = 0
    for i in range(4):
        sx = (i + 0.5) * 0.25
        if sx < ax or sx >= bx:
            continue
        height = ay + ((sx - ax) / (bx - ax)) * (by - ay)
        for j in range(4):
            if (j + 0.5) * 0.25 < height:
                count += 1
    return sign * count / 16.0


@numba.njit(cache=True)
def _switch_kernel(positions, width, height):
    """(triangle, x, y, area) per pixel of each triangle's bounding box: |sum of the edge
    terms|, each edge integrated exactly when it runs down the screen (or level) and by
    4 x 4 point sampling when it runs up."""
    out_t = []
    out_x = []
    out_y = []
    out_a = []
    for t in range(positions.shape[0]):
        p = positions[t]
        if not np.all(np.isfinite(p)):
            continue
        area = (p[1, 0] - p[0, 0]) * (p[2, 1] - p[0, 1]) - (p[1, 1] - p[0, 1]) * (p[2, 0] - p[0, 0])
        if area == 0:
            continue
        x0 = int(max(np.floor(p[:, 0].min()), 0.0))
        x1 = int(min(np.ceil(p[:, 0].max()), float(width)))
        y0 = int(max(np.floor(p[:, 1].min()), 0.0))
        y1 = int(min(np.ceil(p[:, 1].max()), float(height)))
        for yy in range(y0, y1):
            for xx in range(x0, x1):
                total = 0.0
                for k in range(3):
                    ax, ay = p[k, 0] - xx, p[k, 1] - yy
                    bx, by = p[(k + 1) % 3, 0] - xx, p[(k + 1) % 3, 1] - yy
                    if by >= ay:  # the bug: the method depends on the edge's direction
                        total += _exact_integral(ax, ay, bx, by)
                    else:
                        total += _sampled_integral(ax, ay, bx, by)
                a = min(abs(total), 1.0)
                if a > 0:
                    out_t.append(t)
                    out_x.append(xx)
                    out_y.append(yy)
                    out_a.append(a)
    return (np.array(out_t, dtype=np.int64), np.array(out_x, dtype=np.int64), np.array(out_y, dtype=np.int64),
            np.array(out_a, dtype=np.float64))


class PerEdgeMethodSwitch:
    """cairo's image backend in 2010 ("Seams with image backend again"): the coverage of a
    pixel is the signed sum of per-edge areas (Green's theorem), but an edge running down
    the screen is integrated analytically and one running up is point-sampled on a 4 x 4
    grid. Each alpha is within the generous tolerance it declares; the two sides of a
    shared edge use different methods, so on a partition their errors no longer cancel
    (seams), and flipping a triangle's winding swaps its methods (invariance)."""

    name = "bad_per_edge_method_switch"
    # A point-sampled edge term errs by up to 3/8 (1/8 at each end of its x-range, where
    # a sample column's centre decides a quarter-wide column, and 1/8 from the heights'
    # quarter steps); the analytic terms not at all. 3/8 holds the mixed sums of the quick
    # suite's triangles (0.26 at most): a generous promise each alpha keeps.
    convention = Convention(coverage="area", tolerance=0.375)
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        with np.errstate(invalid="ignore"):
            huge = np.flatnonzero(np.any(np.abs(scene.positions) > MAX_COORDINATE, axis=(1, 2)))
        if huge.size:  # pixel-local coordinates of such vertices lose the pixel: declined
            raise ValueError(f"{self.name}: triangle {int(huge[0])} has a coordinate beyond {MAX_COORDINATE:g}")
        with np.errstate(all="ignore"):
            t, x, y, area = _switch_kernel(frozen(scene.positions), scene.width, scene.height)
        alpha = _eight_bit(area)
        keep = alpha > 0
        if not keep.any():
            return Coverage.empty()
        return Coverage.from_pixels(t[keep], x[keep], y[keep], alpha=alpha[keep])


class CoarseSupersampleClaimsAnalytic:
    """A 4 x 4 supersampler (the exact share of a regular grid's 16 samples, top-left ties,
    written as 8-bit alpha) that declares analytic area coverage: its alphas stray from the
    area by up to a pixel's worth along edges (accuracy), and change in steps of 1/16 as a
    shape moves by tiny amounts (popping)."""

    name = "bad_coarse_supersample"
    convention = Convention(coverage="area")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        shares = sample_shares(_geometry(scene), Convention(coverage="area", samples=GRID_4X4, levels=17))
        assert shares.alpha is not None
        alpha = _eight_bit(shares.alpha)
        return Coverage(shares.triangle, shares.y, shares.x0, shares.x1, alpha=alpha)



@numba.njit(cache=True)
def _stepped_x(state, k, xa, ya, xb, yb, line):
    """Edge k's x on the band line y = ``line`` as a float32 DDA has it: the exact
    crossing of the first line asked for, rounded to float32, then ``x += dxdy`` in
    float32 once per row (``state[k]``: x, the line it is on, dxdy); kept within the
    edge's x range as the reference keeps its crossings."""
    if state[k, 1] > line:  # first line of this edge: start exactly (to float32)
        state[k, 0] = np.float32(xa + (line - ya) * ((xb - xa) / (yb - ya)))
        state[k, 1] = line
        state[k, 2] = np.float32((xb - xa) / (yb - ya))
    while state[k, 1] < line:  # BUG: one float32 rounding per row, accumulated down the edge
        state[k, 0] = np.float32(np.float32(state[k, 0]) + np.float32(state[k, 2]))
        state[k, 1] += 1.0
    return min(max(float(state[k, 0]), min(xa, xb)), max(xa, xb))


@numba.njit(cache=True, error_model="numpy")
def _drift_kernel(positions, sign, width, height, steps, block, alpha):
    """:mod:`rasterizers.area_scanline`'s kernel with its band crossings stepped in
    float32 (:func:`_stepped_x`) instead of computed afresh in float64 on every row."""
    cells = np.zeros(width + 2)
    values = np.zeros(width)
    edges = np.empty((3, 5))
    state = np.empty((3, 3))
    n = 0
    m = 0
    for t in range(positions.shape[0]):
        if sign[t] == 0:
            continue
        p = positions[t]
        count = 0
        for k in range(3):
            ax, ay, bx, by = p[k, 0], p[k, 1], p[(k + 1) % 3, 0], p[(k + 1) % 3, 1]
            if ay == by:
                continue
            if ay < by:
                edges[count, 0], edges[count, 1], edges[count, 2], edges[count, 3], edges[count, 4] = ax, ay, bx, by, 1.0
            else:
                edges[count, 0], edges[count, 1], edges[count, 2], edges[count, 3], edges[count, 4] = bx, by, ax, ay, -1.0
            state[count, 1] = math.inf
            count += 1
        ymin = min(p[0, 1], p[1, 1], p[2, 1])
        ymax = max(p[0, 1], p[1, 1], p[2, 1])
        if ymax <= 0.0 or ymin >= height:
            continue
        r0 = int(math.floor(max(ymin, 0.0)))
        r1 = int(math.ceil(min(ymax, float(height)))) - 1
        for j in range(r0, r1 + 1):
            top = float(j)
            lo = math.inf
            hi = -math.inf
            for k in range(count):
                xa, ya, xb, yb, d = edges[k, 0], edges[k, 1], edges[k, 2], edges[k, 3], edges[k, 4]
                if yb <= top or ya >= top + 1.0:
                    continue
                if ya >= top:
                    x0, y0 = xa, ya - top
                else:
                    x0, y0 = _stepped_x(state, k, xa, ya, xb, yb, top), 0.0
                if yb <= top + 1.0:
                    x1, y1 = xb, yb - top
                else:
                    x1, y1 = _stepped_x(state, k, xa, ya, xb, yb, top + 1.0), 1.0
                _accumulate_piece(cells, x0, y0, x1, y1, d, width)
                lo = min(lo, x0, x1)
                hi = max(hi, x0, x1)
            if lo > hi:
                continue
            c0 = int(math.floor(min(max(lo, 0.0), width - 1.0)))
            c1 = int(math.floor(min(max(hi, 0.0), width - 1.0)))
            acc = 0.0
            for i in range(c0, c1 + 1):
                acc += cells[i]
                values[i] = np.rint(min(abs(acc), 1.0) * steps) / steps
            for i in range(c0, c1 + 2):
                cells[i] = 0.0
            block, alpha, n, m = emit_row(t, j, values, c0, c1, block, alpha, n, m)
    return block, alpha, n, m


class Float32EdgeStepping:
    """stb_truetype's (v2) drift: the signed-area accumulation of
    :mod:`rasterizers.area_scanline`, but each edge's x on the next row is the last
    row's plus dx/dy, in float32 (a DDA down the edge), as a rasterizer written for
    glyphs steps it. Far right on a tall screen (x about 1,000 px, a float32 step of
    2**-14 px) every row adds up to half that in rounding, the same way each row: down
    2,000 rows an edge lies a tenth of a pixel off, a few dozen levels of alpha. On small
    scenes near the origin it stays well within a level."""

    name = "bad_float32_edge_stepping"
    convention = Convention(coverage="area")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        sign = screen_triangles(scene, MAX_COORDINATE, self.name, "float32 holds a pixel's fraction only that far")
        positions = frozen(scene.positions)
        spans, pixels = first_capacity(positions, sign, scene.width, scene.height)
        block, alpha = np.empty((4, spans), dtype=np.int64), np.empty(pixels)
        block, alpha, n, m = _drift_kernel(positions, sign, scene.width, scene.height, 255.0, block, alpha)
        return Coverage(block[0, :n], block[1, :n], block[2, :n], block[3, :n], alpha=alpha[:m])


# -- area coverage with one classic cause each (issue 29 point 4): accuracy names it ---------


def _exact_area(scene: Scene, convention: Convention) -> Coverage:
    """The exact area of each (triangle, pixel) under ``convention``'s snapping (unquantised)."""
    return area_coverage(_geometry(scene), convention)


class GammaEncodedArea:
    """Declares analytic area coverage on 256 levels; writes each alpha gamma-encoded, as
    a colour value would be: round(255 * area^(1/2.2)) -- an edge pixel half covered
    reads 186, not 128."""

    name = "bad_gamma_encoded_area"
    convention = Convention(coverage="area")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        exact = _exact_area(scene, self.convention)
        assert exact.alpha is not None
        return Coverage(exact.triangle, exact.y, exact.x0, exact.x1, alpha=_eight_bit(exact.alpha ** (1.0 / 2.2)))


class HalfPixelShiftedArea:
    """Declares analytic area coverage; takes pixel (x, y) to be the square centred on
    (x, y) instead of [x, x + 1] x [y, y + 1]: every alpha is the area of the triangle moved
    by (+1/2, +1/2) px."""

    name = "bad_half_pixel_shifted_area"
    convention = Convention(coverage="area")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        moved = Scene(scene.width, scene.height, scene.positions + 0.5)
        exact = _exact_area(moved, self.convention)
        assert exact.alpha is not None
        return Coverage(exact.triangle, exact.y, exact.x0, exact.x1, alpha=_eight_bit(exact.alpha))


class TruncatedArea:
    """Declares analytic area coverage rounded to 256 levels (half a level's tolerance);
    converts with ``int(a * 255)``: truncates, up to a level low."""

    name = "bad_truncated_area"
    convention = Convention(coverage="area")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        exact = _exact_area(scene, self.convention)
        assert exact.alpha is not None
        alpha = np.floor(exact.alpha * 255.0) / 255.0
        keep = alpha > 0
        if not keep.any():
            return Coverage.empty()
        t, x, y = exact.pixels()
        return Coverage.from_pixels(t[keep], x[keep], y[keep], alpha=alpha[keep])


class FourBitArea:
    """Declares analytic area coverage on 256 levels; computes it on 16 (a 4-bit coverage
    buffer scaled up): every alpha a multiple of 17/255, up to half of that off."""

    name = "bad_four_bit_area"
    convention = Convention(coverage="area")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        exact = _exact_area(scene, self.convention)
        assert exact.alpha is not None
        alpha = np.rint(exact.alpha * 15.0) / 15.0
        keep = alpha > 0
        if not keep.any():
            return Coverage.empty()
        t, x, y = exact.pixels()
        return Coverage.from_pixels(t[keep], x[keep], y[keep], alpha=alpha[keep])


# the drifting stepper's error per row stepped: a slope kept in too few fractional bits
DRIFT_PER_ROW = 2.0**-9


class DriftingStepArea:
    """Declares analytic area coverage; steps each triangle's edges down from its top row
    with an increment 2^-9 px too large (a slope kept in too few fractional bits, as a
    float32 or fixed-point stepper accumulates): row k of a triangle (counted from its first row
    on screen) is drawn as the triangle moved right by k * 2^-9 px. Right at its top, a level or more off some
    rows down, and worse the further down."""

    name = "bad_drifting_step_area"
    convention = Convention(coverage="area")
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        geometry = _geometry(scene)
        with np.errstate(invalid="ignore"):
            # stepping starts at the first row drawn: the triangle's top, or the screen's
            top = np.maximum(np.floor(np.nanmin(geometry.positions[:, :, 1], axis=1, initial=np.inf)), 0.0)
        finite = np.isfinite(top)
        parts = []
        for k in range(scene.height):
            moved = Scene(scene.width, scene.height, geometry.positions + np.array([k * DRIFT_PER_ROW, 0.0]))
            cov = _exact_area(moved, self.convention)
            t, x, y = cov.pixels()
            assert cov.alpha is not None
            mine = finite[t] & (y - np.where(finite[t], top[t], 0.0) == k)
            if mine.any():
                parts.append((t[mine], x[mine], y[mine], cov.alpha[mine]))
        if not parts:
            return Coverage.empty()
        t, x, y, a = (np.concatenate([p[i] for p in parts]) for i in range(4))
        alpha = _eight_bit(a)
        keep = alpha > 0
        if not keep.any():
            return Coverage.empty()
        return Coverage.from_pixels(t[keep], x[keep], y[keep], alpha=alpha[keep])


# -- multisample: samples dropped near edges, all samples at the centre (issue 29 point 4) ---

# the near-edge rejecter's margin: a pixel whose centre lies farther than this outside an
# edge is rejected whole; every sample of the standard 4x pattern is within 0.28 px of the
# centre along a normal, and sqrt(2)/2 covers any
REJECT_MARGIN = 0.125


class RejectsNearEdges:
    """Declares the standard 4x pattern and tests each sample exactly -- but first rejects
    a pixel whole when its centre lies more than 1/8 px outside an edge (a trivial-reject
    margin too small for the samples' reach): samples inside the triangle in pixels just
    past an edge are dropped; the pattern itself is right."""

    name = "bad_rejects_near_edges"
    convention = Convention(samples=4)
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        cov = exact_coverage(_geometry(scene), Convention(samples=4))
        if not cov.n_pixels:
            return cov
        t, x, y = cov.pixels()
        s = cov.fragment_samples()
        p = scene.positions[t]  # (F, 3, 2)
        with np.errstate(all="ignore"):
            area = (p[:, 1, 0] - p[:, 0, 0]) * (p[:, 2, 1] - p[:, 0, 1]) - (p[:, 1, 1] - p[:, 0, 1]) * (p[:, 2, 0] - p[:, 0, 0])
            sign = np.where(area < 0, -1.0, 1.0)
            centre = np.stack([x + 0.5, y + 0.5], axis=-1).astype(np.float64)
            rejected = np.zeros(t.size, dtype=bool)
            for k in range(3):
                a, b = p[:, k], p[:, (k + 1) % 3]
                d = b - a
                e = (d[:, 0] * (centre[:, 1] - a[:, 1]) - d[:, 1] * (centre[:, 0] - a[:, 0])) * sign
                rejected |= e < -REJECT_MARGIN * np.hypot(d[:, 0], d[:, 1])  # the centre that far outside
        keep = ~rejected
        if not keep.any():
            return Coverage.empty()
        return Coverage.from_pixels(t[keep], x[keep], y[keep], sample=s[keep])


class CentreSamples:
    """Declares the standard 4x pattern; puts all four samples at the pixel centre (a
    sample table of zeros): each pixel's four samples are covered together or not at all."""

    name = "bad_centre_samples"
    convention = Convention(samples=4)
    interpolates = False

    def rasterize(self, scene: Scene) -> Coverage:
        cov = exact_coverage(_geometry(scene), Convention())
        if not cov.n_pixels:
            return Coverage.empty()
        t, x, y = cov.pixels()
        return Coverage.from_pixels(np.repeat(t, 4), np.repeat(x, 4), np.repeat(y, 4), sample=np.tile(np.arange(4), t.size))
