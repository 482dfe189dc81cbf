"""What a JSON document's first fault against its JSON Schema is, in one line.

Every file rastercheck reads back -- a case or repro (:mod:`harness.contract.case`), a gate
baseline (:mod:`harness.results.gate`), a campaign state (:mod:`harness.campaign.state`) -- is checked
against its schema before anything in it is used, and refused with the file, the field and
the problem. The field is written as a path into the document, ``paths[0][2]``,
``entries["r|a|conformance"].status``, or "the top level".

>>> import jsonschema
>>> schema = {"type": "object", "required": ["count"], "properties": {"count": {"type": "integer"},
...           "rule": {"enum": ["nonzero", "evenodd"]}}}
>>> validator = jsonschema.Draft202012Validator(schema)
>>> schema_fault(validator, {"count": "3"})
"at count: '3' is not of type 'integer'"
>>> schema_fault(validator, {"rule": "odd"})
"at the top level: lacks 'count'"
>>> schema_fault(validator, {"count": 3, "rule": "odd"})
"at rule: 'odd' is not one of 'nonzero', 'evenodd'"
>>> schema_fault(validator, {"count": 3}) is None
True
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterable
from typing import Any

__all__ = ["schema_fault", "first_error", "where", "what"]


def where(path: Iterable[Any]) -> str:
    """A path into a document: ``paths[0][2]``, ``entries["r|a|c"].status``.

    >>> where(["signatures", "conformance|tie", "count"]), where([]), where(["history", 0, 1])
    ('signatures["conformance|tie"].count', 'the top level', 'history[0][1]')
    """
    text = ""
    for step in path:
        if isinstance(step, int):
            text += f"[{step}]"
        elif str(step).isidentifier():
            text += f".{step}"
        else:
            text += f"[{json.dumps(str(step))}]"
    return text.lstrip(".") or "the top level"


def _shown(value: Any) -> str:
    shown = repr(value)
    return shown if len(shown) <= 60 else shown[:57] + "..."


def what(error: Any) -> str:
    """A jsonschema error's problem, in words: a missing field, a wrong type, a value not
    among those allowed, or the constraint it breaks."""
    if error.validator == "required":
        missing = [f for f in error.validator_value if isinstance(error.instance, dict) and f not in error.instance]
        return f"lacks {', '.join(map(repr, missing))}"
    if error.validator == "type":
        return f"{_shown(error.instance)} is not of type {error.validator_value!r}"
    if error.validator == "enum":
        return f"{_shown(error.instance)} is not one of {', '.join(map(repr, error.validator_value))}"
    return f"{_shown(error.instance)} is not valid ({error.validator} {error.validator_value!r:.80})"


def first_error(validator: Any, data: Any) -> Any | None:
    """The most relevant error of ``data`` against ``validator`` (jsonschema's
    ``best_match``), or None when it is valid."""
    import jsonschema

    return jsonschema.exceptions.best_match(validator.iter_errors(data))


def schema_fault(validator: Any, data: Any, explain: Callable[[Any], str | None] | None = None) -> str | None:
    """``at <field>: <problem>`` for the first fault of ``data``, or None when valid.
    ``explain(error)`` may word a document's own constraints (None: the usual words)."""
    error = first_error(validator, data)
    if error is None:
        return None
    said = explain(error) if explain is not None else None
    return f"at {where(error.absolute_path)}: {said or what(error)}"
