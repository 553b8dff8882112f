"""The repository stands on its own: nothing in it cites notes or files outside it (the team's
working notes and the files the project started from); it cites the docs site's theory page
("theory: SECTION") and the literature. And tests are named by what they check, not by issue
numbers."""

from __future__ import annotations

import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUTSIDE = re.compile(
    # (the note's name is written in two pieces, so that this file does not cite it either)
    r"PHYS"
    r"ICS(?: notes|\.md)|/work/shared|\.\./shared|-top\.txt"
    r"|(?-i:\b(?:BENCHMARKS|DESIGN|STYLE)\.md)|\bseeds?/"
    r"|seed's|seed files?\b|\bthe seed\b(?! of| for)",
    re.IGNORECASE,
)
TEXT = (".py", ".rs", ".md", ".rst", ".toml", ".txt", ".js", ".html", ".css", ".json", ".ipynb",
        ".yml", ".yaml", ".cfg", ".pyi", "Makefile")  # fmt: skip


def _tracked() -> list[Path]:
    out = subprocess.run(["git", "ls-files"], cwd=ROOT, capture_output=True, text=True)
    if out.returncode != 0:  # not a git checkout: every file under the root
        return [p for p in ROOT.rglob("*") if p.is_file() and ".venv" not in p.parts]
    return [ROOT / line for line in out.stdout.splitlines()]


def test_nothing_cites_notes_or_files_outside_the_repository():
    found = []
    for path in _tracked():
        if not path.name.endswith(TEXT) or not path.is_file():
            continue
        if path.name == "test_self_contained.py":
            continue
        rel = path.relative_to(ROOT).as_posix()
        for number, line in enumerate(path.read_text(errors="replace").splitlines(), 1):
            if OUTSIDE.search(line):
                found.append(f"{rel}:{number}: {line.strip()}")
    assert not found, "\n".join(found)


def test_tests_are_named_by_behaviour_not_by_issue_numbers():
    found = []
    for path in sorted((ROOT / "tests").rglob("*.py")):
        for number, line in enumerate(path.read_text().splitlines(), 1):
            if re.search(r"\bissues? ?#?\d+|\bitem ?\d+\b|def test_item\d", line, re.IGNORECASE):
                found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert not found, "\n".join(found)
