"""Every Python snippet of the user's manual (docs/src) and of the README runs as it is.

Each ```python block is executed on its own, in a fresh namespace, in a temporary working
directory that links the repository's `models/` and `scenarios/` (the snippets name them
relative to the repository's root), so that files a snippet writes stay out of the tree.
"""

import os
import pathlib
import re

import matplotlib
import pytest

matplotlib.use("Agg")

ROOT = pathlib.Path(__file__).resolve().parents[3]
PAGES = sorted((ROOT / "docs" / "src").rglob("*.md")) + [ROOT / "README.md"]
BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)


def snippets():
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        for i, m in enumerate(BLOCK.finditer(text)):
            line = text.count("\n", 0, m.start()) + 1
            yield pytest.param(m.group(1), id=f"{page.relative_to(ROOT)}:{line}")


SNIPPETS = list(snippets())


def test_the_manual_has_python_snippets():
    pages = {p.id.split(":")[0] for p in SNIPPETS}
    assert "README.md" in pages
    assert len(SNIPPETS) >= 4, [p.id for p in SNIPPETS]


@pytest.mark.parametrize("code", SNIPPETS)
def test_snippet_runs(code, tmp_path, monkeypatch):
    for d in ("models", "scenarios", "examples"):
        os.symlink(ROOT / d, tmp_path / d)
    monkeypatch.chdir(tmp_path)
    exec(compile(code, "<manual snippet>", "exec"), {"__name__": "__manual__"})
