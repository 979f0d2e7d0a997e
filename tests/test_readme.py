"""The README's tour is executable and says what the library really does."""

from __future__ import annotations

import re
from pathlib import Path

README = Path(__file__).resolve().parents[1] / "README.md"


def test_readme_tour_runs_and_its_claims_hold():
    text = README.read_text()
    block = re.search(r"```python\n(.*?)```", text, re.S).group(1)
    ns: dict = {}
    exec(compile(block, "README.md", "exec"), ns)  # noqa: S102 - our own documentation
    after = ns["after"]
    # every line commented "True" in the tour is checked here
    for line in block.splitlines():
        m = re.match(r'after\.holds\("(.*)"\)\s+# True', line)
        if m:
            assert after.holds(m.group(1)), line
    from delkit import bisimilar, contract

    small = contract(after)
    assert bisimilar(small, after) and contract(small).n_worlds == small.n_worlds == 4


def test_readme_gives_the_two_setup_commands():
    text = README.read_text()
    assert "make demo" in text and "make test" in text


def test_readme_shell_examples_name_files_that_exist():
    """Every repository path in the README's shell examples (``specs/...``, ``arms/...``) is a real file."""
    root = README.parent
    blocks, lang, lines = [], None, []          # fenced blocks as (language, text); fences open and close
    for line in README.read_text().splitlines():
        if line.startswith("```"):
            if lang is None:
                lang, lines = line[3:].strip(), []
            else:
                blocks.append((lang, "\n".join(lines)))
                lang = None
        elif lang is not None:
            lines.append(line)
    shell = "\n".join(text for language, text in blocks if language in ("", "sh", "bash", "shell"))
    paths = re.findall(r"(?<![\w./])((?:specs|arms)/[\w./-]+\.\w+)", shell)
    assert paths, "the README's shell examples name no spec file"
    missing = [p for p in paths if not (root / p).is_file()]
    assert not missing, f"README names files that do not exist: {missing}"
