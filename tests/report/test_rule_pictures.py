"""The README's pictures of the conventions' rules (docs/rule_pictures.py): the script runs,
writes one PNG per rule, and each picture shows what it claims -- the rule and centre
sampling part on it (else the picture would show nothing of the rule)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_the_rule_pictures_script_draws_every_rule_where_it_parts_from_centre_sampling(tmp_path: Path) -> None:
    done = subprocess.run([sys.executable, str(ROOT / "docs" / "rule_pictures.py"), str(tmp_path)], cwd=ROOT,
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.strip().splitlines()
    assert len(lines) >= 12
    for line in lines:
        name, _, said = line.partition(": ")
        png = tmp_path / f"{name}.png"
        assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", name
        drawn, parted = (int(said.split(" pixels drawn, ")[0]), int(said.split(", ")[1].split(" where")[0]))
        assert drawn > 0 and parted > 0, line
    # every picture the README shows is one the script draws
    readme = (ROOT / "README.md").read_text()
    shown = {part.split(")")[0] for part in readme.split("(docs/rules/")[1:]}
    assert shown <= {f"{line.split(':')[0]}.png" for line in lines}, shown
