#!/usr/bin/env python3
"""Writes out the code of a Markdown guide (docs/plugin-guide.md) as the files it names.

A fenced code block whose first non-blank line is a marker

    // file: kg_elastic.hpp            (C++)
    # file: CMakeLists.txt             (CMake, TOML, shell)

is (part of) a file of the guide's example project, at that path relative to the output
directory. Several blocks naming the same file are joined in the order of the guide (with a
blank line between them), so a file can be shown in pieces with prose between them (the
marker of a later piece may say "(continued)" after the name). The marker lines are kept: they are comments in every language
the guide uses.

A block whose first line is

    // excerpt of: plugins/cam_clay/cam_clay.cpp

quotes a file of the Stratum source tree; with --source ROOT its lines (leading and trailing
blanks ignored, blank lines skipped) must occur in that file consecutively and in this order, so
that a quotation that no longer matches its source fails. Blocks without a marker are
illustrations (abridged declarations, shell sessions) and are not checked.

    guide_snippets.py GUIDE.md OUTDIR [--source ROOT]   write the files, check the excerpts
    guide_snippets.py GUIDE.md --list                   print the marked blocks

Exit status 0, or 1 with one located line per problem (GUIDE.md:LINE: what is wrong).
Standard library only.
"""

from __future__ import annotations

import argparse
import os
import re
import sys
from dataclasses import dataclass
from pathlib import Path, PurePosixPath

FENCE = re.compile(r"^(?P<indent> *)(?P<fence>`{3,}|~{3,})(?P<info>.*)$")
MARKER = re.compile(r"^\s*(?://|#)\s*(?P<kind>file|excerpt of):\s*(?P<path>\S+)")


@dataclass
class Block:
    line: int  # 1-based line of the opening fence in the guide
    info: str  # the fence's info string (language)
    lines: list[str]  # the content, with the fence's indentation removed


class GuideError(Exception):
    pass


def blocks(text: str, guide: str) -> list[Block]:
    """The fenced code blocks of a Markdown text (backtick or tilde fences, indented or not)."""
    out: list[Block] = []
    lines = text.splitlines()
    i = 0
    while i < len(lines):
        m = FENCE.match(lines[i])
        if not m:
            i += 1
            continue
        indent, fence = len(m["indent"]), m["fence"]
        start = i
        body: list[str] = []
        i += 1
        while i < len(lines):
            close = FENCE.match(lines[i])
            if close and close["fence"][0] == fence[0] and len(close["fence"]) >= len(fence) and not close["info"].strip():
                break
            line = lines[i]
            # CommonMark: up to the fence's indentation is removed from each content line.
            strip = min(indent, len(line) - len(line.lstrip(" ")))
            body.append(line[strip:])
            i += 1
        else:
            raise GuideError(f"{guide}:{start + 1}: the code block opened here is never closed")
        out.append(Block(start + 1, m["info"].strip(), body))
        i += 1
    return out


def marker(block: Block) -> tuple[str, str] | None:
    """(kind, path) of a marked block, or None."""
    for line in block.lines:
        if line.strip():
            m = MARKER.match(line)
            return (m["kind"], m["path"]) if m else None
    return None


def safe_path(path: str, guide: str, line: int) -> PurePosixPath:
    p = PurePosixPath(path)
    if p.is_absolute() or ".." in p.parts or not p.parts:
        raise GuideError(f"{guide}:{line}: file: {path} must be a relative path inside the project (no '..')")
    return p


def check_excerpt(block: Block, path: str, source: Path, guide: str) -> str | None:
    """None when the block's lines occur consecutively in source/path, else the problem."""
    target = source / path
    try:
        have = [s.strip() for s in target.read_text(encoding="utf-8").splitlines() if s.strip()]
    except OSError as e:
        return f"{guide}:{block.line}: excerpt of {path}: cannot read {target}: {e.strerror}"
    want = [s.strip() for s in block.lines if s.strip()][1:]  # without the marker
    if not want:
        return f"{guide}:{block.line}: excerpt of {path}: the block quotes nothing"
    n = len(want)
    for k in range(len(have) - n + 1):
        if have[k : k + n] == want:
            return None
    # Name the first quoted line that is not in the file, or the first that breaks the sequence.
    for w in want:
        if w not in have:
            return f"{guide}:{block.line}: excerpt of {path} no longer matches it: '{w}' is not in the file"
    return f"{guide}:{block.line}: excerpt of {path} no longer matches it: its lines are not consecutive there"


def main(argv: list[str]) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("guide")
    ap.add_argument("outdir", nargs="?")
    ap.add_argument("--source", help="root of the Stratum source tree, to check the excerpts against")
    ap.add_argument("--list", action="store_true", help="print the marked blocks and exit")
    a = ap.parse_args(argv)
    guide = a.guide
    try:
        text = Path(guide).read_text(encoding="utf-8")
    except OSError as e:
        print(f"guide_snippets: cannot read {guide}: {e.strerror}", file=sys.stderr)
        return 1
    problems: list[str] = []
    files: dict[PurePosixPath, list[str]] = {}
    excerpts = 0
    try:
        found = blocks(text, guide)
        for b in found:
            mk = marker(b)
            if mk is None:
                continue
            kind, path = mk
            if a.list:
                print(f"{guide}:{b.line}: {kind} {path}")
            if kind == "file":
                lines = files.setdefault(safe_path(path, guide, b.line), [])
                if lines:
                    lines.append("")  # a blank line between the pieces of one file
                lines.extend(b.lines)
            else:
                excerpts += 1
                if a.source:
                    if problem := check_excerpt(b, path, Path(a.source), guide):
                        problems.append(problem)
    except GuideError as e:
        problems.append(str(e))
    if a.list:
        for p in problems:
            print(p, file=sys.stderr)
        return 1 if problems else 0
    if not a.outdir:
        ap.error("give OUTDIR (or --list)")
    if not files:
        problems.append(f"{guide}: no code block starts with a '// file: NAME' or '# file: NAME' line")
    if problems:
        for p in problems:
            print(p, file=sys.stderr)
        return 1
    out = Path(a.outdir)
    for rel, lines in files.items():
        target = out / rel
        target.parent.mkdir(parents=True, exist_ok=True)
        tmp = target.with_name(target.name + ".tmp")
        tmp.write_text("\n".join(lines) + "\n", encoding="utf-8")
        os.replace(tmp, target)
    names = ", ".join(str(p) for p in files)
    checked = f"; {excerpts} excerpts match their sources" if a.source else ""
    print(f"{guide}: {len(files)} files written to {out}: {names}{checked}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
