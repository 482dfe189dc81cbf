"""Rows of docs/campaigns.md's tables from campaigns' state folders.

    python docs/campaign_table.py STATE_ROOT [NAME ...]

STATE_ROOT holds one folder per rasterizer (``STATE_ROOT/<name>/state``, as
``rastercheck fuzz --state`` writes it); without names, every folder there, sorted. Each
row: scenes, findings, signatures, causes, whether the known-bad table's checks
(``tests/test_known_bad.TABLE``) saw its bug, the first finding's time, and each cause with
its findings and the checks that saw it (``CampaignState.causes``).
"""

from __future__ import annotations

import sys
from pathlib import Path

from harness.campaign.state import CampaignState


def _expected() -> dict[str, set[str]]:
    """The known-bad table: each known-bad's name and the checks that must flag it."""
    from tests.acceptance.test_known_bad import TABLE

    return {bad.name: set(checks) for bad, checks in TABLE.items()}


def row(name: str, state: CampaignState, expected: dict[str, set[str]]) -> str:
    """One markdown table row for the campaign ``state`` of rasterizer ``name``."""
    causes = state.causes()
    seen = {str(entry.get("check")) for entry in state.signatures.values()}
    wanted = expected.get(name)
    if wanted is None:
        bug = "-"
    else:
        found, missed = sorted(wanted & seen), sorted(wanted - seen)
        bug = ("yes: " + ", ".join(found) if found else "no") + (f" (not {', '.join(missed)})" if missed and found else "")
    firsts = [float(s["first"]["at"]) for s in state.signatures.values() if isinstance(s.get("first"), dict)]
    first = f"{min(firsts):.1f} s" if firsts else "-"
    listed = "; ".join(f"{c['cause']} {c['findings']:,} ({', '.join(c['checks'])})" for c in causes) or "none"
    return (f"| `{name}` | {state.scenes:,} | {state.findings:,} | {len(state.signatures)} | {len(causes)} "
            f"| {bug} | {first} | {listed} |")


def main(argv: list[str]) -> int:
    root = Path(argv[0])
    names = argv[1:] or sorted(p.name for p in root.iterdir() if (p / "state").is_dir())
    expected = _expected()
    for name in names:
        print(row(name, CampaignState.load(root / name / "state"), expected))
    return 0


if __name__ == "__main__":
    raise SystemExit(main(sys.argv[1:]))
