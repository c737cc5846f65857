"""Every Python block of the README and of the guide (``docs/guide/*.md``) runs as written.

A ```python block followed (after blank lines only) by a ```text block quotes what it prints:
its standard output is compared with the text line by line, trailing blanks and blank lines
at the end aside, ``[..]``
within a line matching any text and a line ``...`` any number of lines (as
``tests/cli/readme.rs`` compares the command blocks' output).

Each ```python block runs in a fresh folder holding a copy of the repository's
``examples/field/`` (the files the blocks name): what else a block reads, it writes itself. A
block that reads ``brg.toml`` is preceded by the README's commands that write it
(``bearing-ident simulate``, then ``identify --ross brg.toml``). Blocks that import ROSS run
where ROSS is importable (``pip install ross-rotordynamics``, Python >= 3.13) and are skipped,
saying so, elsewhere.
"""

from __future__ import annotations

import contextlib
import importlib.util
import io
import pathlib
import re
import shutil
import subprocess

import pytest

from test_api import CLI

ROOT = pathlib.Path(__file__).resolve().parents[2]


def python_blocks(document: str) -> list[tuple[str, str, str | None]]:
    """The document's ```python blocks, each with the heading it is under and the output it
    quotes (the ```text block right after it), if any."""
    blocks, heading, body, text, after = [], "", None, None, False
    for line in document.splitlines():
        if text is not None:
            if line.strip() == "```":
                h, code, _ = blocks[-1]
                blocks[-1] = (h, code, "\n".join(text) + "\n")
                text = None
            else:
                text.append(line)
        elif body is None:
            if line.startswith("## "):
                heading = line.strip()
            if line.strip() == "```python":
                body = []
            elif line.strip() == "```text" and after:
                text = []
            after = after and line.strip() == ""
        elif line.strip() == "```":
            blocks.append((heading, "\n".join(body) + "\n", None))
            body, after = None, True
        else:
            body.append(line)
    return blocks


def output_matches(quoted: str, printed: str) -> bool:
    """Whether ``printed`` is what ``quoted`` says, by the rules of the module's docstring."""
    lines = []
    for line in quoted.rstrip().splitlines():
        line = line.rstrip()
        if line == "...":
            lines.append(r"(?:[^\n]*\n)*?")
        else:
            lines.append(".*?".join(re.escape(p) for p in line.split("[..]")) + r"\n")
    actual = "".join(l.rstrip() + "\n" for l in printed.rstrip().splitlines())
    return re.fullmatch("".join(lines), actual, re.S) is not None


DOCUMENTS = ["README.md", *sorted(str(p.relative_to(ROOT)) for p in (ROOT / "docs" / "guide").glob("*.md"))]


BLOCKS = [
    (document, heading, code, quoted)
    for document in DOCUMENTS
    for heading, code, quoted in python_blocks((ROOT / document).read_text(encoding="utf-8"))
]


def test_the_readme_has_its_python_blocks():
    headings = [(d, h) for d, h, _, _ in BLOCKS]
    assert ("README.md", "## From Python") in headings, headings
    assert any(d.startswith("docs/guide/01") for d, _ in headings), headings
    assert len(BLOCKS) >= 4, headings


def test_blocks_are_read_with_their_headings():
    text = "## A\n```python\nx = 1\n```\n```sh\nno\n```\n## B\n```python\ny = 2\nz = 3\n```\n\n```text\n5\n```\n"
    assert python_blocks(text) == [("## A", "x = 1\n", None), ("## B", "y = 2\nz = 3\n", "5\n")]


def test_quoted_output_is_compared_with_its_marks():
    printed = "a 1.5 ms\nb\nc\nd  \n"
    assert output_matches("a 1.5 ms\nb\nc\nd\n", printed)
    assert output_matches("a [..] ms\n...\nd\n", printed)
    assert output_matches("...\n", printed)
    assert not output_matches("a 1.6 ms\nb\nc\nd\n", printed)
    assert not output_matches("a [..] ms\nb\nc\n", printed)


@pytest.mark.parametrize(
    "document, heading, code, quoted", BLOCKS, ids=[f"{d}:{h[3:]}-{i}" for i, (d, h, _, _) in enumerate(BLOCKS)]
)
def test_python_block_runs_as_written(document, heading, code, quoted, tmp_path, monkeypatch):
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
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(code, f"{document} ({heading})", "exec"), names)
    if quoted is not None:
        assert output_matches(quoted, printed.getvalue()), f"quoted:\n{quoted}\nprinted:\n{printed.getvalue()}"
    if (document, heading) == ("README.md", "## From Python"):
        # What the block computed: the rig's stiffness from its CSV files, the JSON object, the
        # ROSS element, the field identification's bearings.
        assert len(list((tmp_path / "rig").glob("*.csv"))) == 8
        assert abs(names["result"].K[0, 0] / 146.3e3 - 1) < 0.05, names["result"].K
        assert names["as_json"]["n_records"] == 8
        assert "brg" in names["element"], names["element"][:200]
        assert [b["tag"] for b in names["field"]["bearings"]] == ["brg0", "brg1"]
    if (document, heading) == ("docs/guide/05-campaigns.md", "## A plan of three points, from Python"):
        # The campaign's three points, its table and the ROSS element over the two speeds at 200 N.
        assert names["study"].failed == [] and len(names["study"].points) == 3
        assert names["table"].count("\n") == 4 and "BearingElement_bearing" in names["ross"]
