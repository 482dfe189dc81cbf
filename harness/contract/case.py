"""The case records and their JSON codec: what flows from the case generators to the checks.

A :class:`Case` is one named scene plus the facts about it that are known exactly; a
:class:`MotionCase` is a named frame sequence. Both are stored as JSON with every float
written exactly: as its decimal where that is short (``0.375``), else by ``float.hex``,
so that a replay sees exactly the same floats
(:func:`case_to_json`, :func:`case_from_json`, :func:`save_case`, :func:`load_case`).
"""

from __future__ import annotations

import functools
import json
import math
import os
import re
import sys
from dataclasses import dataclass, field
from decimal import Decimal, InvalidOperation
from pathlib import Path
from typing import Any, cast

import numpy as np
from numpy.typing import NDArray

from harness.contract.scenes import MAX_VIEWPORT, AnyScene, LineScene, PathScene, Scene
from harness.kinds import KINDS, TRIANGLES, PrimitiveKind, kind_of, kind_of_json
from harness.kinds.base import JSON_NUMBER, JSON_POINT
from harness.kinds.points import PointScene
from harness.results.files import atomic_write_text, read_input
from harness.results.schemas import first_error
from harness.results.schemas import what as problem
from harness.results.schemas import where as field_path

__all__ = ["Case", "MotionCase", "case_to_json", "case_from_json", "save_case", "load_case", "read_case_file", "SCHEMA",
           "CASE_SCHEMA", "MAX_CASE_PIXELS"]

SCHEMA = 1


@dataclass(frozen=True, slots=True, eq=False)
class Case:
    """A named scene and the facts the checks may rely on.

    Parameters
    ----------
    id : str
        Stable hierarchical id, ``family/variant/detail``; the first part is the family.
    scene : Scene, PathScene or LineScene
        Triangles, paths under a fill rule, or lines; a rasterizer is handed the case only when
        it takes the scene's kind (:func:`harness.contract.protocol.takes`).
    lattice : bool
        Every coordinate lies on a coarse dyadic lattice: float arithmetic is exact there,
        so no deviation from the oracle is excused as rounding.
    region : (M, 2) float64 or None
        For a planar partition, the convex outline (clockwise or not) of the union of
        its triangles (or paths), known exactly: pixels wholly inside must be hit exactly once,
        pixels wholly outside never, and no pixel twice.
    closed : bool
        The triangles form a closed mesh wholly in front of the camera: at every pixel,
        hits by clockwise triangles equal hits by counter-clockwise ones.
    refusable : tuple of int
        Triangles (paths) with finite but huge coordinates that a rasterizer may refuse by
        raising ValueError naming them (reported as skip, with its reason).
    """

    id: str
    scene: AnyScene
    lattice: bool = False
    region: NDArray[np.float64] | None = None
    closed: bool = False
    refusable: tuple[int, ...] = field(default=())

    @property
    def family(self) -> str:
        return self.id.split("/", 1)[0]

    @property
    def non_finite(self) -> tuple[int, ...]:
        """Primitives (triangles or paths) with a NaN or infinite coordinate."""
        return self.scene.non_finite()


@dataclass(frozen=True, slots=True, eq=False)
class MotionCase:
    """A named frame sequence.

    Parameters
    ----------
    id : str
        ``motion/<geometry>/<movement>``.
    frames : tuple of Scene
        One scene per frame, same triangles in the same order (lines under motion are
        moved by the line checks themselves, :mod:`harness.checks.lines`).
    texels : int or None
        T for textured sequences: attribute columns 0 and 1 are (u, v) on a T x T grid.
    perspective : bool
        Whether the frames carry clip-space w (perspective-correct interpolation).
    """

    id: str
    frames: tuple[Scene, ...]
    texels: int | None = None
    perspective: bool = False

    @property
    def family(self) -> str:
        return "motion"


# The largest viewport a case file may ask for: the checks hold per-pixel counts of the
# whole screen, and 2**26 pixels (8192 x 8192) is 256 MiB of them.
MAX_CASE_PIXELS = 1 << 26

_SIDE = {"type": "integer", "minimum": 1, "maximum": MAX_VIEWPORT}
_FRAME = {"type": "object", "required": ["width", "height", "positions"],
          "properties": {"width": _SIDE, "height": _SIDE, **TRIANGLES.json_fields}}


def _one_kind(kind: PrimitiveKind[Any]) -> dict[str, Any]:
    """The schema's test that a case holds this kind's scene and no other's."""
    others = [{"required": [other.json_key]} for other in KINDS.values() if other is not kind]
    return {"required": list(kind.json_required), "not": {"anyOf": others}}


# The JSON schema of a case file (a JSON Schema 2020-12 document): a still case, or a
# motion case (``"kind": "motion"``) with its frames. Other fields (the check that
# failed, the rasterizer, a message) ride along unchecked.
CASE_SCHEMA: dict[str, Any] = {
    "$schema": "https://json-schema.org/draft/2020-12/schema",
    "type": "object",
    "required": ["schema", "id"],
    "properties": {
        "schema": {"const": SCHEMA},
        "kind": {"enum": ["case", "motion"]},
        "id": {"type": "string", "minLength": 1, "maxLength": 1000},
        "check": {"type": "string"},
    },
    "if": {"properties": {"kind": {"const": "motion"}}, "required": ["kind"]},
    "then": {
        "required": ["frames"],
        "properties": {"frames": {"type": "array", "items": _FRAME, "minItems": 1},
                       "texels": {"type": ["integer", "null"], "minimum": 1},
                       "perspective": {"type": "boolean"}},
    },
    "else": {
        "required": ["width", "height"],
        "properties": {
            "width": _SIDE, "height": _SIDE, **{f: schema for kind in KINDS.values() for f, schema in kind.json_fields.items()},
            "lattice": {"type": "boolean"}, "closed": {"type": "boolean"},
            "region": {"type": ["array", "null"], "items": JSON_POINT, "minItems": 3},
            "refusable": {"type": "array", "items": {"type": "integer", "minimum": 0}},
        },
        # one kind of scene: triangles, paths with their fill rule, lines, ... (harness.kinds)
        "oneOf": [_one_kind(kind) for kind in KINDS.values()],
    },
}


def _text(value: float) -> str:
    """A coordinate as text: its exact decimal when that is short (``0.375``, ``-12.5``),
    else ``float.hex`` -- exact either way, and readable where it can be."""
    if math.isfinite(value):
        exact = format(Decimal(value), "f")
        if len(exact) <= 14:
            return exact
    return float.hex(value)


def _hex(array: NDArray | None) -> Any:
    if array is None:
        return None
    # each distinct float written once (a path of 65,536 copies of a square has 4): by bit
    # pattern, so that -0.0 and 0.0 stay apart
    values = np.ascontiguousarray(array, dtype=np.float64)
    bits, inverse = np.unique(values.view(np.uint64), return_inverse=True)
    texts = np.array([_text(v) for v in bits.view(np.float64).tolist()], dtype=object)
    return texts[inverse.reshape(values.shape)].tolist()


def _number(value: Any) -> float:
    """A coordinate back, exactly; ValueError when the text or number is not exactly a
    float: inexact, beyond float64's range (it would silently be an infinity: ``"inf"``
    says so), or no number at all."""
    if isinstance(value, str) and value.lstrip("-") in ("inf", "nan"):
        return float(value)
    if isinstance(value, str) and "x" in value:
        try:
            return float.fromhex(value)
        except OverflowError:
            raise ValueError(f"{value} is beyond float64's range (its largest is {float.hex(sys.float_info.max)}); "
                             "write \"inf\" for an infinity") from None
        except ValueError:
            raise ValueError(f"{value!r} is not a float.hex number") from None
    if isinstance(value, bool) or not isinstance(value, (str, Decimal, int, float)):
        raise ValueError(f"{value!r} is not a number")
    try:
        exact = Decimal(value)
    except (InvalidOperation, ValueError):
        raise ValueError(f"{value!r} is not a number") from None
    if not exact.is_finite():  # a JSON NaN or Infinity literal (not JSON): the words say it
        raise ValueError(f"{value} is not a JSON number: write \"nan\", \"inf\" or \"-inf\"")
    number = float(exact)
    if not math.isfinite(number):
        raise ValueError(f"{value} is beyond float64's range (it would be read as {number}); write \"inf\" for an infinity")
    if Decimal(number) != exact:
        raise ValueError(f"{value} is not exactly a float64 (the nearest is {float.hex(number)}): write it exactly")
    return number


def _unhex(data: Any, field: str = "") -> NDArray | None:
    if data is None:
        return None
    try:
        array = np.array(data, dtype=object)
        ragged = any(isinstance(v, list) for v in array.ravel())
    except ValueError:
        ragged = True
    if ragged:
        raise ValueError(f"case JSON is malformed at {field}: its rows are of different lengths")
    if array.size == 0:
        return array.astype(np.float64)
    flat = array.ravel().tolist()
    try:
        try:
            number = {value: _number(value) for value in set(flat)}  # each distinct text read once
        except TypeError:  # an unhashable value (a dict): _number names it
            numbers: NDArray[np.float64] = np.vectorize(_number, otypes=[float])(array)
            return numbers
    except ValueError as exc:
        raise ValueError(f"case JSON is malformed at {field}: {exc}" if field else str(exc)) from None
    return np.array([number[value] for value in flat], dtype=np.float64).reshape(array.shape)


def _scene_to_json(scene: AnyScene) -> dict[str, Any]:
    fields: dict[str, Any] = kind_of(scene).hook("to_json")(scene)
    return {"width": scene.width, "height": scene.height, **fields}


def lines_to_json(scene: LineScene) -> dict[str, Any]:
    """A line scene's case-JSON fields (the kind's codec, :data:`harness.kinds.LINES`)."""
    return {"line_width": _text(scene.line_width), "lines": [_hex(strip) for strip in scene.strips()]}


def points_to_json(scene: PointScene) -> dict[str, Any]:
    """A point scene's case-JSON fields (the kind's codec)."""
    return {"point_size": _text(scene.point_size), "points": _hex(scene.vertices)}


def points_from_json(data: dict[str, Any], width: int, height: int, where: str = "") -> PointScene:
    """A point scene from its case-JSON fields; ``where`` leads an error."""
    try:
        centres = _unhex(data["points"], "points")
        try:
            size = _number(data.get("point_size", 1))
        except ValueError as exc:
            raise ValueError(f"case JSON is malformed at point_size: {exc}") from None
        return PointScene(width, height, np.zeros((0, 2)) if centres is None else centres, size)
    except ValueError as exc:
        raise ValueError(f"{where}{exc}") from None


def point_sizes(data: dict[str, Any]) -> dict[str, int]:
    """What a point case's fields hold: points."""
    return {"points": len(data["points"])}


def paths_to_json(scene: PathScene) -> dict[str, Any]:
    """A path scene's case-JSON fields (the kind's codec, :data:`harness.kinds.PATHS`)."""
    return {"fill_rule": scene.fill_rule, "paths": [[_hex(c) for c in scene.contours_of(p)] for p in range(len(scene))]}


def triangles_to_json(scene: Scene) -> dict[str, Any]:
    """A triangle scene's case-JSON fields (the kind's codec, :data:`harness.kinds.TRIANGLES`)."""
    return {"positions": _hex(scene.positions), "attributes": _hex(scene.attributes), "w": _hex(scene.w)}


def case_to_json(case: Case | MotionCase, **extra: Any) -> dict[str, Any]:
    """A JSON-ready dict with every float as ``float.hex``; ``extra`` fields ride along.

    >>> from harness.contract.scenes import MAX_VIEWPORT, Scene
    >>> data = case_to_json(Case("lattice/one", Scene(4, 4, [[[0, 0], [4, 0], [0, 4]]])), check="conformance")
    >>> data["positions"][0][1], data["check"]
    (['4', '0'], 'conformance')
    >>> _text(0.1), _text(-12.375)
    ('0x1.999999999999ap-4', '-12.375')
    >>> case_from_json(data).scene.positions[0, 1].tolist()
    [4.0, 0.0]
    """
    if isinstance(case, MotionCase):
        return {"schema": SCHEMA, "kind": "motion", "id": case.id, "frames": [_scene_to_json(f) for f in case.frames],
                "texels": case.texels, "perspective": case.perspective, **extra}
    return {
        "schema": SCHEMA,
        "kind": "case",
        "id": case.id,
        **_scene_to_json(case.scene),
        "lattice": case.lattice,
        "region": _hex(case.region),
        "closed": case.closed,
        "refusable": list(case.refusable),
        **extra,
    }


# The most a case file may hold, so that a file's cost is bounded before any of it is used
# (a million contours, or 200,000 paths, ran past two minutes on one rasterizer; 65,536 paths
# take half a minute): triangles, paths, their contours and vertices, line strips and their
# vertices. RASTERCHECK_MAX_CASE_SCALE=k multiplies every limit by k.
MAX_CASE_SIZES = {what: most for kind in KINDS.values() for what, most in kind.size_limits.items()}


def _case_sizes(data: dict[str, Any]) -> dict[str, int]:
    """What the scene in ``data`` holds, counted from its lists before any is read."""
    sizes: dict[str, int] = kind_of_json(data).hook("json_sizes")(data)
    return sizes


def line_sizes(data: dict[str, Any]) -> dict[str, int]:
    """What a line case's fields hold: strips and vertices."""
    return {"line strips": len(data["lines"]), "line vertices": sum(len(strip) for strip in data["lines"])}


def path_sizes(data: dict[str, Any]) -> dict[str, int]:
    """What a path case's fields hold: paths, contours and vertices."""
    contours = [c for path in data["paths"] for c in path]
    return {"paths": len(data["paths"]), "contours": len(contours), "path vertices": sum(len(c) for c in contours)}


def triangle_sizes(data: dict[str, Any]) -> dict[str, int]:
    """What a triangle case's fields hold: triangles."""
    return {"triangles": len(data["positions"])}


def _check_sizes(data: dict[str, Any], where: str) -> None:
    raw = os.environ.get("RASTERCHECK_MAX_CASE_SCALE", "")
    try:
        scale = max(int(raw), 1) if raw else 1
    except ValueError:
        raise ValueError(f"RASTERCHECK_MAX_CASE_SCALE={raw!r} is not a whole number") from None
    for what, count in _case_sizes(data).items():
        if count > MAX_CASE_SIZES[what] * scale:
            raise ValueError(f"{where}the case holds {count:,} {what}, more than the {MAX_CASE_SIZES[what] * scale:,} a case "
                             "may hold (RASTERCHECK_MAX_CASE_SCALE=k allows k times more)")


def _scene_from_json(data: dict[str, Any], where: str) -> AnyScene:
    width, height = int(data["width"]), int(data["height"])
    if width * height > MAX_CASE_PIXELS:
        raise ValueError(f"{where}a {width} x {height} viewport is more than the {MAX_CASE_PIXELS} pixels (8192 x 8192) "
                         "a case may cover: the checks count hits on every pixel of the screen")
    _check_sizes(data, where)
    scene: AnyScene = kind_of_json(data).hook("from_json")(data, width, height, where)
    return scene


def lines_from_json(data: dict[str, Any], width: int, height: int, where: str = "") -> LineScene:
    """A line scene from its case-JSON fields (the kind's codec); ``where`` leads an error."""
    try:
        strips = [_unhex(strip, f"lines[{k}]") for k, strip in enumerate(data["lines"])]
        try:
            line_width = _number(data.get("line_width", 1))
        except ValueError as exc:
            raise ValueError(f"case JSON is malformed at line_width: {exc}") from None
        return LineScene.from_strips(width, height, cast(list[NDArray], strips), line_width)
    except ValueError as exc:
        raise ValueError(f"{where}{exc}") from None


def paths_from_json(data: dict[str, Any], width: int, height: int, where: str = "") -> PathScene:
    """A path scene from its case-JSON fields (the kind's codec); ``where`` leads an error."""
    try:
        paths = [[_unhex(c, f"paths[{p}][{k}]") for k, c in enumerate(path)] for p, path in enumerate(data["paths"])]
        return PathScene.from_paths(width, height, cast(list[list[NDArray]], paths), data["fill_rule"])
    except ValueError as exc:
        raise ValueError(f"{where}{exc}") from None


def triangles_from_json(data: dict[str, Any], width: int, height: int, where: str = "") -> Scene:
    """A triangle scene from its case-JSON fields (the kind's codec); ``where`` leads an
    error of the scene's (not one of reading its numbers)."""
    positions = _unhex(data["positions"], "positions")
    assert positions is not None
    try:
        return Scene(width, height, positions.reshape(-1, 3, 2), _unhex(data.get("attributes"), "attributes"),
                     _unhex(data.get("w"), "w"))
    except ValueError as exc:
        raise ValueError(f"{where}{exc}") from None


_HEX_OR_WORD = re.compile(JSON_NUMBER["anyOf"][0]["pattern"])
_DECIMAL = re.compile(JSON_NUMBER["anyOf"][1]["pattern"])


def _is_number(value: Any) -> bool:
    """Whether ``value`` is valid under :data:`harness.kinds.base.JSON_NUMBER` (the same test, without the
    validator's cost per value)."""
    if isinstance(value, str):
        return _HEX_OR_WORD.search(value) is not None or _DECIMAL.search(value) is not None
    return isinstance(value, (int, float, Decimal)) and not isinstance(value, bool)


def _valid_points(points: Any) -> bool:
    """Whether ``points`` is a list of [x, y] pairs valid under :data:`harness.kinds.base.JSON_POINT`."""
    if not (isinstance(points, list) and all(isinstance(p, list) and len(p) == 2 for p in points)):
        return False
    try:
        distinct = {value for p in points for value in p}  # each distinct value tested once
    except TypeError:  # an unhashable value (a list, a dict) is no number
        return False
    return all(_is_number(value) for value in distinct)


def _skeleton(data: dict[str, Any]) -> dict[str, Any]:
    """``data`` with each long run of valid points, and each long list of valid triangles,
    contours, paths or strips, cut to its first three, for the schema validator: what is
    cut is valid by :func:`_valid_points` (the schema's own test of a point) and every
    list keeps at least as many items as the schema's least (three at most), so
    the validator says of the skeleton exactly what it would say of the whole -- in
    milliseconds, where it took 27 s on a path of 196,000 vertices. A run with a fault
    in it is left whole, for the validator to name the fault and where."""
    def cut(points: Any) -> Any:
        return points[:3] if isinstance(points, list) and len(points) > 3 and _valid_points(points) else points

    def whole(run: Any, least: int) -> bool:
        return isinstance(run, list) and len(run) >= least and _valid_points(run)

    def cut_runs(runs: Any, least: int) -> Any:
        """A list of runs of points (contours, strips), each of at least ``least``."""
        if not isinstance(runs, list):
            return runs
        if len(runs) > 3 and all(whole(run, least) for run in runs):
            runs = runs[:3]
        return [cut(run) for run in runs]

    def triangles(positions: Any) -> Any:
        if isinstance(positions, list) and len(positions) > 3 and all(
                isinstance(t, list) and len(t) == 3 and _valid_points(t) for t in positions):
            return positions[:3]
        return positions

    out = dict(data)
    if "paths" in out and isinstance(out["paths"], list):
        paths = out["paths"]
        if len(paths) > 3 and all(isinstance(path, list) and path and all(whole(c, 1) for c in path) for path in paths):
            paths = paths[:3]  # paths of valid contours (a partition's hundreds of triangles)
        out["paths"] = [cut_runs(path, 1) for path in paths]
    if "lines" in out:
        out["lines"] = cut_runs(out["lines"], 2)
    if "region" in out:
        out["region"] = cut(out["region"])
    if "positions" in out:
        out["positions"] = triangles(out["positions"])
    if isinstance(out.get("frames"), list):
        out["frames"] = [dict(f, positions=triangles(f.get("positions"))) if isinstance(f, dict) and "positions" in f else f
                         for f in out["frames"]]
    return out


def _fields_of(kind: PrimitiveKind[Any]) -> str:
    """A kind's required case fields in words: ``'paths' and 'fill_rule'``."""
    return " and ".join(repr(f) for f in kind.json_required)


@functools.cache
def _validator() -> Any:
    """The schema's validator, built once."""
    import jsonschema

    return jsonschema.Draft202012Validator(CASE_SCHEMA)


def case_from_json(data: Any) -> Case | MotionCase:
    """The exact case back from :func:`case_to_json`, after checking it against
    :data:`CASE_SCHEMA`; ValueError naming the field that is wrong and where."""
    if not isinstance(data, dict) or data.get("schema") != SCHEMA:
        raise ValueError(f"not a rastercheck case (schema {SCHEMA} expected)")
    skeleton = _skeleton(data)
    error = first_error(_validator(), skeleton)
    keys = [kind.json_key for kind in KINDS.values()]
    if error is not None and error.validator == "oneOf" and not error.absolute_path and not set(keys) & set(data):
        raise ValueError(f"case JSON lacks the field {_fields_of(TRIANGLES)} (or "
                         + ", ".join(f"{_fields_of(kind)} for a {kind.case_word} case" for kind in KINDS.values()
                                     if kind is not TRIANGLES)
                         + ")")
    if error is not None and error.validator == "oneOf" and not error.absolute_path:
        given = [f for f in keys if f in data]
        if len(given) > 1:
            raise ValueError(f"case JSON gives {' and '.join(map(repr, given))}: a case holds one kind of scene")
    if error is not None:
        if error.validator == "required":
            missing = [f for f in error.validator_value if isinstance(error.instance, dict) and f not in error.instance]
            if error.instance is skeleton and data.get("kind") != "motion" and not set(keys) & set(data):
                missing.append("positions")  # (or "paths" and "fill_rule", for a path case)
            raise ValueError(f"case JSON lacks the field{'s' if len(missing) > 1 else ''} {', '.join(map(repr, missing))}"
                             + ("" if not error.absolute_path else f" at {field_path(error.absolute_path)}"))
        raise ValueError(f"case JSON is malformed at {field_path(error.absolute_path)}: {problem(error)}")
    if data.get("kind") == "motion":
        frames = tuple(_scene_from_json(f, f"frame {k}: ") for k, f in enumerate(data["frames"]))
        if any(f.kind != TRIANGLES.name for f in frames):
            raise ValueError("case JSON is malformed at frames: a motion case's frames are triangle scenes")
        triangles = tuple(TRIANGLES.narrow(f) for f in frames)
        return MotionCase(data["id"], triangles, texels=data.get("texels"), perspective=bool(data.get("perspective", False)))
    scene = _scene_from_json(data, "")
    region = _unhex(data.get("region"), "region")
    if region is not None and not np.isfinite(region).all():
        raise ValueError("case JSON is malformed at region: the region a partition covers has a non-finite corner")
    if any(t >= len(scene) for t in data.get("refusable", ())):
        raise ValueError(f"case JSON is malformed at refusable: names triangles past the last ({len(scene) - 1})")
    return Case(data["id"], scene, lattice=bool(data.get("lattice", False)), region=region,
                closed=bool(data.get("closed", False)), refusable=tuple(data.get("refusable", ())))


def save_case(path: Path | str, case: Case | MotionCase, **extra: Any) -> Path:
    """Write the case as JSON (atomically: a reader never sees half a file)."""
    path = Path(path)
    atomic_write_text(path, json.dumps(case_to_json(case, **extra), indent=1))
    return path


def load_case(path: Path | str) -> Case | MotionCase:
    """The case saved at ``path``; ValueError naming the file and what is wrong with it."""
    return read_case_file(path)[0]


def read_case_file(path: Path | str) -> tuple[Case | MotionCase, dict[str, Any]]:
    """The case saved at ``path`` and the fields that ride along with it (``check``,
    ``rasterizer``, ``message`` of a repro); ValueError naming the file and the fault."""
    path = Path(path)
    try:
        data = json.loads(read_input(path, "the case").decode("utf-8"), parse_float=Decimal)  # numbers read exactly
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ValueError(f"{path}: cannot read the case ({exc})") from None
    except RecursionError:
        raise ValueError(f"{path}: cannot read the case (JSON nested too deep)") from None
    try:
        case = case_from_json(data)
    except ValueError as exc:
        raise ValueError(f"{path}: {exc}") from None
    known = {"schema", "kind", "id", "width", "height", "lattice", "region", "closed", "refusable", "frames", "texels",
             "perspective", *(f for kind in KINDS.values() for f in kind.json_fields)}
    return case, {k: v for k, v in data.items() if k not in known}
