"""Every Python block of the README runs as written.

Each ```python block runs in a fresh folder holding a copy of the repository's
``examples/field/`` (the files the blocks name): what else a block reads, it writes itself. A
block that reads ``brg.toml`` is preceded by the README's commands that write it
(``bearing-ident simulate``, then ``identify --ross brg.toml``). Blocks that import ROSS run
where ROSS is importable (``pip install ross-rotordynamics``, Python >= 3.13) and are skipped,
saying so, elsewhere.
"""

from __future__ import annotations

import importlib.util
import pathlib
import re
import shutil
import subprocess

import pytest

from test_api import CLI

ROOT = pathlib.Path(__file__).resolve().parents[2]


def python_blocks(readme: str) -> list[tuple[str, str]]:
    """The README's ```python blocks, each with the heading it is under."""
    blocks, heading, body = [], "", None
    for line in readme.splitlines():
        if body is None:
            if line.startswith("## "):
                heading = line.strip()
            if line.strip() == "```python":
                body = []
        elif line.strip() == "```":
            blocks.append((heading, "\n".join(body) + "\n"))
            body = None
        else:
            body.append(line)
    return blocks


BLOCKS = python_blocks((ROOT / "README.md").read_text(encoding="utf-8"))


def test_the_readme_has_its_python_blocks():
    headings = [h for h, _ in BLOCKS]
    assert "## From Python" in headings, headings
    assert len(BLOCKS) >= 3, headings


def test_blocks_are_read_with_their_headings():
    text = "## A\n```python\nx = 1\n```\n```sh\nno\n```\n## B\n```python\ny = 2\nz = 3\n```\n"
    assert python_blocks(text) == [("## A", "x = 1\n"), ("## B", "y = 2\nz = 3\n")]


@pytest.mark.parametrize("heading, code", BLOCKS, ids=[f"{h[3:]}-{i}" for i, (h, _) in enumerate(BLOCKS)])
def test_readme_python_block_runs_as_written(heading, code, tmp_path, monkeypatch):
    if re.search(r"^import ross\b", code, re.M) and importlib.util.find_spec("ross") is None:
        pytest.skip("ROSS is not importable here (it needs Python >= 3.13)")
    shutil.copytree(ROOT / "examples" / "field", tmp_path / "examples" / "field")
    if "brg.toml" in code:
        if CLI is None:
            pytest.skip("no bearing-ident binary to write brg.toml")
        subprocess.run([CLI, "simulate", "--impacts", "4", "--noise", "0.05", "--out", "records"], cwd=tmp_path, check=True, capture_output=True)
        files = sorted(str(p.relative_to(tmp_path)) for p in (tmp_path / "records").glob("*.csv"))
        subprocess.run([CLI, "identify", "--band", "8,49", "--ross", "brg.toml", *files], cwd=tmp_path, check=True, capture_output=True)
    monkeypatch.chdir(tmp_path)
    names = {"__name__": "__readme__"}
    exec(compile(code, f"README.md ({heading})", "exec"), names)
    if heading == "## From Python":
        # What the block computed: the rig's stiffness from its CSV files, the campaign's points,
        # the ROSS element over the two speeds at 200 N, the field identification's bearings.
        assert len(list((tmp_path / "rig").glob("*.csv"))) == 8
        assert abs(names["result"].K[0, 0] / 146.3e3 - 1) < 0.05, names["result"].K
        assert names["as_json"]["n_records"] == 8
        assert names["study"].failed == [] and len(names["study"].points) == 3
        assert names["table"].count("\n") == 4 and "BearingElement_bearing" in names["ross"]
        assert [b["tag"] for b in names["field"]["bearings"]] == ["brg0", "brg1"]
