"""Finding rasterizers: built-in names, entry points, ``module:attr`` and ``file.py:attr``.

Built-ins register through the entry-point group ``rastercheck.rasterizers`` exactly as
third-party plugins do. ``RASTERCHECK_NO_PLUGINS=1`` keeps only the built-ins.
"""

from __future__ import annotations

import importlib
import importlib.util
import json
import os
import sys
from importlib.metadata import EntryPoint, entry_points
from pathlib import Path
from typing import Any

from harness.contract.conventions import Convention
from harness.contract.protocol import Rasterizer

__all__ = ["GROUP", "available", "builtins", "load", "as_rasterizer", "BUILTIN_MODULE", "Unavailable", "distinct_names",
           "Renamed", "registered_twice", "same_names"]

GROUP = "rastercheck.rasterizers"
BUILTIN_MODULE = "rasterizers"


class Unavailable(Exception):
    """A rasterizer whose library or driver is missing; the message is the install hint.
    Runs report it as skipped and go on."""


def _plugins_enabled() -> bool:
    return os.environ.get("RASTERCHECK_NO_PLUGINS", "").strip() not in ("1", "true", "yes")


_SCANS: dict[tuple[Any, ...], tuple[EntryPoint, ...]] = {}


def _scan() -> tuple[EntryPoint, ...]:
    """The group's entry points, sorted by name and value. Scanning reads every installed
    distribution's metadata (tens of milliseconds) and every lookup needs it, so it is done
    once per process for each ``sys.path`` (and each stand-in for ``entry_points`` a test
    installs)."""
    key = (entry_points, tuple(sys.path))
    scan = _SCANS.get(key)
    if scan is None:
        if len(_SCANS) > 16:
            _SCANS.clear()
        scan = _SCANS[key] = tuple(sorted(entry_points(group=GROUP), key=lambda e: (e.name, e.value)))
    return scan


def _enabled_entry_points() -> list[EntryPoint]:
    """The group's entry points, third-party ones only when plugins are enabled."""
    return [ep for ep in _scan()
            if ep.value.split(":")[0].split(".")[0] == BUILTIN_MODULE or _plugins_enabled()]


def _entry_points() -> dict[str, EntryPoint]:
    """Name -> entry point, the first of each name (:func:`registered_twice` names the
    others: loading such a name is refused)."""
    found: dict[str, EntryPoint] = {}
    for ep in _enabled_entry_points():
        found.setdefault(ep.name, ep)
    return found


def registered_twice(name: str) -> list[str]:
    """The distinct targets (``module:attr``) registered under ``name`` when there are
    two or more, else an empty list: a name that means two rasterizers is refused when
    loaded, rather than one of them being run under it silently."""
    values = list(dict.fromkeys(ep.value for ep in _enabled_entry_points() if ep.name == name))
    return values if len(values) > 1 else []


def builtins() -> list[str]:
    """Names of the four reference rasterizers (not the adapters of real libraries)."""
    return sorted(name for name, ep in _entry_points().items()
                  if ep.value.startswith(BUILTIN_MODULE + ".") and not ep.value.startswith(BUILTIN_MODULE + ".real"))


def real_adapters() -> list[str]:
    """Names of the registered adapters of real libraries (``rasterizers.real``), sorted."""
    return sorted(name for name, ep in _entry_points().items() if ep.value.startswith(BUILTIN_MODULE + ".real."))


def available() -> list[str]:
    """Names of the registered rasterizers, sorted: built-ins and enabled plugins."""
    return sorted(_entry_points())


def as_rasterizer(obj: Any, spec: str) -> Rasterizer:
    """Turn what a spec names into a ready rasterizer: an object is used as is, a class or
    a zero-argument factory is called. Raises ValueError naming the spec otherwise, and
    when its declarations contradict each other
    (:func:`harness.contract.declarations.declaration_problem`)."""
    candidate = obj
    if isinstance(candidate, type) or (not hasattr(candidate, "rasterize") and callable(candidate)):
        try:
            candidate = candidate()
        except Unavailable:
            raise
        except (Exception, SystemExit) as exc:
            raise ValueError(f"{spec}: calling it with no arguments failed: {_describe(exc)}") from exc
    problems = []
    if not isinstance(getattr(candidate, "name", None), str):
        problems.append("a str `name`")
    convention = getattr(candidate, "convention", "missing")
    if convention is not None and not isinstance(convention, Convention):
        problems.append("a `convention` that is a harness.Convention or None")
    if not callable(getattr(candidate, "rasterize", None)):
        problems.append("a `rasterize(scene)` method")
    if problems:
        raise ValueError(f"{spec}: {candidate!r} is not a rasterizer: it lacks {', '.join(problems)}")
    from harness.contract.declarations import declaration_problem

    contradiction = declaration_problem(candidate)
    if contradiction is not None:  # refused now, in one line, rather than by an error on every case
        raise ValueError(f"{spec}: {contradiction}")
    return candidate  # type: ignore[no-any-return]


def _describe(exc: BaseException) -> str:
    """``Type: message`` of a plugin's exception, even when its ``__str__`` raises; a
    sys.exit said as such."""
    from harness.engine.isolation import describe

    if isinstance(exc, SystemExit):
        return f"it called sys.exit({exc.code!r}) while being imported"
    return describe(exc)


def _module_name(path: Path) -> str:
    """The name a plugin file is imported under: the same in every process, and the one
    other code imports it by where there is one -- numba's on-disk cache records the
    module of each cached kernel by name, and a process that loads the cache must find
    that module (a name that changed from run to run made a plugin's second run fail
    with ``ModuleNotFoundError``).

    Its dotted name from a ``sys.path`` entry when every folder on the way is a package
    (``tests/known_bad/antialiasing.py`` from the project: ``tests.known_bad.antialiasing``),
    else its stem when no other module answers to it, else a name made from a hash of its
    path."""
    import hashlib

    resolved = path.resolve()
    for entry in sys.path:
        try:
            parts = resolved.relative_to(Path(entry or ".").resolve()).with_suffix("").parts
        except (ValueError, OSError):
            continue
        folders = [resolved.parent.joinpath(*[".."] * k) for k in range(len(parts) - 1)]
        if parts and all(part.isidentifier() for part in parts) and all((f / "__init__.py").is_file() for f in folders):
            name = ".".join(parts)
            known = sys.modules.get(name)
            if known is None or Path(getattr(known, "__file__", "") or "").resolve() == resolved:
                return name
    stem = resolved.stem
    if stem.isidentifier() and stem not in sys.modules:
        try:
            found = importlib.util.find_spec(stem)
        except (ImportError, ValueError):
            found = None
        if found is None or (found.origin is not None and Path(found.origin).resolve() == resolved):
            return stem
    return f"rastercheck_user_{hashlib.sha256(str(resolved).encode()).hexdigest()[:16]}"


def _import_file(path: Path) -> Any:
    if not path.is_file():
        raise ValueError(f"{path}: no such file")
    module_name = _module_name(path)
    known = sys.modules.get(module_name)
    if known is not None and Path(getattr(known, "__file__", "") or "").resolve() == path.resolve():
        return known  # imported already, by this name: the same module, not a second copy of its classes
    spec = importlib.util.spec_from_file_location(module_name, path)
    if spec is None or spec.loader is None:
        raise ValueError(f"{path}: cannot be imported as Python")
    module = importlib.util.module_from_spec(spec)
    sys.modules[module_name] = module
    folder = str(path.resolve().parent)
    if folder not in sys.path:
        sys.path.append(folder)  # so the file can import its neighbours
    try:
        spec.loader.exec_module(module)
    except (Exception, SystemExit) as exc:  # a plugin that calls sys.exit at import ends nothing but itself
        del sys.modules[module_name]
        raise ValueError(f"{path}: importing it failed: {_describe(exc)}") from exc
    return module


def _said(spec: str, exc: BaseException) -> list[str]:  # pragma: no cover - runs in the probe's child
    """What the probe's child says of a plugin that failed to load: ``[kind, text]`` as
    plain strings (``str.__str__``: a text of the plugin's, not a subclass of its)."""
    from harness.engine.isolation import describe

    try:
        if isinstance(exc, Unavailable):
            return ["unavailable", str.__str__(describe(exc, with_type=False))]
        if isinstance(exc, ValueError):
            return ["error", str.__str__(describe(exc, with_type=False))]
        return ["error", str.__str__(f"{spec}: {_describe(exc)}")]
    except BaseException:  # noqa: B036 - a type built to refuse being looked at
        return ["error", f"{spec}: loading the plugin failed with an exception that cannot be described"]


def _heard(spec: str, message: bytes) -> tuple[str, str]:
    """The probe child's ``(kind, text)``, checked: JSON of two strings, a known kind."""
    try:
        said = json.loads(message.decode("utf-8"))
    except (UnicodeDecodeError, ValueError, RecursionError):
        said = None
    if not (isinstance(said, list) and len(said) == 2 and said[0] in ("ok", "unavailable", "error") and isinstance(said[1], str)):
        raise ValueError(f"{spec}: the process loading the plugin sent back something unreadable")
    return said[0], said[1]


def _probe(spec: str, seconds: float = 120.0) -> None:
    """Load ``spec`` once in a forked child first, so that a plugin that ends the process
    while it is imported or built (``os._exit``, a signal, a crash in native code) ends
    the child, not rastercheck -- which would otherwise exit with whatever code the plugin
    chose, 0 included. Raises ValueError (or Unavailable) with what the child saw."""
    import multiprocessing
    import signal

    context = multiprocessing.get_context("fork")
    parent, child = context.Pipe(duplex=False)

    def attempt() -> None:  # pragma: no cover - runs in the child
        # what the child says is plain text sent as JSON: nothing the plugin made is
        # pickled, so nothing of its runs in this process when the answer is read
        try:
            _load(spec)
            said = ["ok", ""]
        except BaseException as exc:  # noqa: B036
            said = _said(spec, exc)
        child.send_bytes(json.dumps(said).encode("utf-8"))

    process = context.Process(target=attempt, daemon=True)
    process.start()
    child.close()
    try:
        if not parent.poll(seconds):
            raise ValueError(f"{spec}: loading the plugin did not finish within {seconds:g} s")
        kind, text = _heard(spec, parent.recv_bytes())
    except EOFError:
        process.join(5)
        code = process.exitcode
        how = (f"signal {signal.Signals(-code).name}" if code is not None and code < 0 else f"exit code {code}")
        raise ValueError(f"{spec}: the plugin ended the process while being loaded ({how})") from None
    finally:
        if process.is_alive():
            process.kill()
        process.join(5)
        parent.close()
    if kind == "unavailable":
        raise Unavailable(text)
    if kind == "error":
        raise ValueError(text)


def load(spec: str, import_timeout: float = 120.0) -> Rasterizer:
    """A ready rasterizer for ``spec``.

    Parameters
    ----------
    spec : str
        A registered name (``centre_scanline``), ``package.module:attr``, or
        ``path/to/file.py:attr``. ``attr`` may be a rasterizer object, a class, or a
        zero-argument factory.
    import_timeout : float
        Seconds a plugin may take to import and build (the commands pass their
        ``--timeout``: a module that hangs at import is given what a call is).

    Raises
    ------
    ValueError
        Naming the spec, when it cannot be found, imported or used.

    Examples
    --------
    >>> load("centre_scanline").convention
    Convention(sample=(0.5, 0.5), tie='top-left', subpixel_bits=None, cull='none')

    A spec that is not one of rastercheck's own rasterizers is loaded in a forked child
    first (:func:`_probe`), so that no plugin can end rastercheck while it loads.
    """
    twice = registered_twice(spec)
    if twice:
        raise ValueError(f"{spec}: registered twice in the entry-point group {GROUP} ({' and '.join(twice)}): "
                         "uninstall one, or give it another name")
    ours = _entry_points().get(spec)
    if ours is None or not ours.value.startswith(BUILTIN_MODULE + "."):
        _probe(spec, import_timeout)
    return _load(spec)


def _load(spec: str) -> Rasterizer:
    registered = _entry_points()
    if spec in registered:
        try:
            obj = registered[spec].load()
        except Unavailable:
            raise
        except (Exception, SystemExit) as exc:
            raise ValueError(f"{spec}: plugin failed to load: {_describe(exc)}") from exc
        return as_rasterizer(obj, spec)
    where, sep, attr = spec.rpartition(":")
    if not sep or not where or not attr:
        known = ", ".join(sorted(registered)) or "none"
        raise ValueError(
            f"{spec}: not a registered rasterizer (known: {known}) nor module:attr or file.py:attr"
        )
    if where.endswith(".py") or os.sep in where or "/" in where:
        module = _import_file(Path(where))
    else:
        try:
            module = importlib.import_module(where)
        except (Exception, SystemExit) as exc:
            raise ValueError(f"{spec}: importing {where} failed: {_describe(exc)}") from exc
    try:
        obj = getattr(module, attr)
    except AttributeError:
        raise ValueError(f"{spec}: {where} has no attribute {attr!r}") from None
    return as_rasterizer(obj, spec)


class Renamed:
    """A rasterizer under another name (its optional members kept)."""

    def __init__(self, inner: Rasterizer, name: str) -> None:
        self.inner, self.name, self.convention = inner, name, inner.convention
        for optional in ("interpolates", "received", "input", "fingerprint", "scene_kinds", "fill_rules", "path_convention",
                         "line_convention"):
            if hasattr(inner, optional):
                setattr(self, optional, getattr(inner, optional))

    def rasterize(self, scene: Any) -> Any:
        return self.inner.rasterize(scene)


def distinct_names(rasterizers: list[Rasterizer]) -> list[Rasterizer]:
    """The rasterizers with every name told apart: a second ``centre_scanline`` (a plugin
    beside the built-in) becomes ``centre_scanline#2``, so that results are never merged."""
    seen: dict[str, int] = {}
    out: list[Rasterizer] = []
    for r in rasterizers:
        count = seen[r.name] = seen.get(r.name, 0) + 1
        out.append(r if count == 1 else Renamed(r, f"{r.name}#{count}"))
    return out


def same_names(rasterizers: list[Rasterizer], specs: list[str]) -> str | None:
    """One line naming the first name two of ``rasterizers`` share (loaded from ``specs``,
    in order) and the specs that gave it; None when every name is distinct. A command line
    that selects two rasterizers of one name is refused with it: their results would be
    told apart only by a suffix, and a report of ``centre_scanline`` would not say which."""
    seen: dict[str, str] = {}
    for r, spec in zip(rasterizers, specs):
        if r.name in seen:
            first = seen[r.name]
            how = f"{first} twice" if first == spec else f"{first} and {spec}"
            return f"two rasterizers are named {r.name!r} ({how}): select each once, or give one another `name`"
        seen[r.name] = spec
    return None
