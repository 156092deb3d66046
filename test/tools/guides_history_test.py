#!/usr/bin/python3
"""The guides describe the tool as it is: README.md, doc/guide/*.md and doc/reference/*.md carry
no dated history. A line with a date (2026-11-26) outside a link target, or a narrative of what
the tool did before ("measured before", "before these changes", "since 2026-..."), fails: history
belongs in CHANGELOG.md, and a measured figure names its machine, not its day. The reports
(doc/reports/) and the design notes keep their dated measurements.

Usage: guides_history_test.py [SOURCE_DIR]   (exit 1 with one line per offending line)
"""
import glob
import os
import re
import sys

ROOT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..")
DATE = re.compile(r"\b20\d\d-\d\d-\d\d\b")
LINK_TARGET = re.compile(r"\]\([^)]*\)")
NARRATIVE = re.compile(r"\b(measured before|before these changes|before this change|"
                       r"used before|since 20\d\d|\(later\)|, later\))", re.IGNORECASE)


def offending_lines(path):
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            prose = LINK_TARGET.sub("]()", line)  # a link's anchor may hold a heading's date
            if DATE.search(prose) or NARRATIVE.search(prose):
                yield number, line.rstrip()


def main():
    pages = [os.path.join(ROOT, "README.md")]
    for folder in ("guide", "reference"):
        pages += sorted(glob.glob(os.path.join(ROOT, "doc", folder, "*.md")))
    bad = [(os.path.relpath(p, ROOT), n, line) for p in pages for n, line in offending_lines(p)]
    for path, number, line in bad:
        print("%s:%d: dated history in a guide (move it to CHANGELOG.md): %s"
              % (path, number, line[:160]))
    print("guides_history: %d pages, %d dated history lines" % (len(pages), len(bad)))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
