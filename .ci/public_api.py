#!/usr/bin/env python3
"""The crate's public surface, as a sorted list of lines, from the HTML that stable `cargo doc`
writes (rustdoc's JSON needs a nightly toolchain; this needs none).

Every item of `all.html` (`struct bearing_ident::job::Job`, `fn …`, `macro …`), and on each
item's page: its inherent methods and associated constants, enum variants, public fields, trait
methods, and the traits it implements (not the auto or blanket ones). Signatures are not
compared, names are: a renamed, added or removed item, method, variant or trait impl shows.

    python3 .ci/public_api.py target/doc > public-api.txt     # write the list
    python3 .ci/public_api.py target/doc --check public-api.txt   # compare, exit 1 on change
"""
import html
import pathlib
import re
import sys

KINDS = {
    "struct": "struct", "enum": "enum", "fn": "fn", "trait": "trait", "type": "type",
    "constant": "const", "macro": "macro", "static": "static", "union": "union",
    "derive": "derive", "attr": "attr",
}


def section(page: str, start_id: str, stop_ids: list[str]) -> str:
    at = page.find(f'id="{start_id}"')
    if at < 0:
        return ""
    ends = [page.find(f'id="{s}"', at + 1) for s in stop_ids]
    ends = [e for e in ends if e > 0]
    return page[at:min(ends) if ends else len(page)]


def members(page: str, path: str, is_trait: bool) -> list[str]:
    out = []
    inherent = section(page, "implementations-list", ["trait-implementations", "synthetic-implementations", "blanket-implementations"])
    for kind, name in re.findall(r'id="(method|associatedconstant|associatedtype)\.([A-Za-z0-9_]+)"', inherent):
        out.append(f"  {kind} {path}::{name}")
    # A trait's own items (required and provided), above its implementors.
    if is_trait:
        own = page[: page.find('id="implementors"')] if 'id="implementors"' in page else page
        for kind, name in re.findall(r'id="(tymethod|method|associatedtype|associatedconstant)\.([A-Za-z0-9_]+)"', own):
            out.append(f"  {kind} {path}::{name}")
    for name in re.findall(r'id="variant\.([A-Za-z0-9_]+)"', page):
        out.append(f"  variant {path}::{name}")
    for name in re.findall(r'id="structfield\.([A-Za-z0-9_]+)"', page):
        out.append(f"  field {path}::{name}")
    traits = section(page, "trait-implementations-list", ["synthetic-implementations", "blanket-implementations"])
    for header in re.findall(r'<h3 class="code-header">(.*?)</h3>', traits, re.S):
        text = html.unescape(re.sub(r"<[^>]+>", "", header))
        out.append("  " + re.sub(r"\s+", " ", text).strip())
    return sorted(set(out))


def surface(doc: pathlib.Path, crate: str = "bearing_ident") -> list[str]:
    root = doc / crate
    index = (root / "all.html").read_text(encoding="utf-8")
    lines = []
    for href, label in re.findall(r'<li><a href="([^"]+)">([^<]+)</a></li>', index):
        kind = KINDS.get(pathlib.Path(href).name.split(".")[0], "item")
        path = f"{crate}::{html.unescape(label)}"
        lines.append(f"{kind} {path}")
        page = root / href
        if page.exists():
            lines.extend(members(page.read_text(encoding="utf-8"), path, kind == "trait"))
    return lines


def main() -> int:
    doc = pathlib.Path(sys.argv[1])
    lines = surface(doc)
    text = "\n".join(lines) + "\n"
    if len(sys.argv) > 3 and sys.argv[2] == "--check":
        expected = pathlib.Path(sys.argv[3]).read_text(encoding="utf-8")
        if expected != text:
            import difflib
            diff = difflib.unified_diff(expected.splitlines(), lines, "public-api.txt (committed)", "public surface (built)", lineterm="", n=0)
            print("\n".join(diff))
            print("\nThe public surface changed. If deliberate: python3 .ci/public_api.py target/doc > public-api.txt, and say so in CHANGELOG.md.")
            return 1
        print(f"public surface unchanged ({len(lines)} lines)")
        return 0
    sys.stdout.write(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())
