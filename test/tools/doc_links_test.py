#!/usr/bin/python3
"""Every relative link of the documentation resolves: README.md and doc/**/*.md.

A link [text](target) or ![alt](target) (and a reference definition `[name]: target`) whose
target is not a URL must name a file or folder that exists, relative to the Markdown file that
holds it; a `#anchor` (alone, for the same file, or after a .md file) must be the GitHub slug of
a heading of that file: lower case, punctuation other than `-` and `_` dropped, spaces turned
into `-`, a repeated heading numbered -1, -2, ... Links inside code (fenced or indented blocks,
`inline code`) are not links and are skipped.

Usage: doc_links_test.py [SOURCE_DIR]   (exit 1 with one line per broken link)
"""
import os
import re
import sys
import unicodedata

ROOT = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..")
LINK = re.compile(r"!?\[(?:[^\[\]]|\[[^\[\]]*\])*\]\(\s*<?([^()\s<>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
REFERENCE = re.compile(r"^ {0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+\"[^\"]*\")?\s*$")
HEADING = re.compile(r"^ {0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
FENCE = re.compile(r"^ {0,3}(```+|~~~+)")
URL = re.compile(r"^[a-zA-Z][a-zA-Z0-9+.-]*:")


def markdown_files(root):
    files = [os.path.join(root, "README.md")]
    for folder, dirs, names in os.walk(os.path.join(root, "doc")):
        dirs.sort()
        files.extend(os.path.join(folder, n) for n in sorted(names) if n.endswith(".md"))
    return files


def prose_lines(text):
    """(line number, line) of the lines outside code blocks, inline code blanked out."""
    fence = None
    previous_blank = True
    in_indented = False
    for number, line in enumerate(text.split("\n"), 1):
        m = FENCE.match(line)
        if fence:
            if m and m.group(1)[0] == fence[0] and len(m.group(1)) >= len(fence):
                fence = None
            continue
        if m:
            fence = m.group(1)
            continue
        blank = not line.strip()
        # An indented code block starts after a blank line (not inside a list item's text) and
        # runs while lines stay indented by four or more, or blank.
        if line.startswith(("    ", "\t")) and (previous_blank or in_indented):
            in_indented = True
            previous_blank = blank
            continue
        if not blank:
            in_indented = False
        previous_blank = blank
        yield number, re.sub(r"(`+)(?:(?!\1).)+?\1", "", line)


def slug(heading):
    """GitHub's anchor for a heading's text."""
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", heading)  # links: their text
    text = re.sub(r"<[^>]+>", "", text)  # inline HTML
    text = text.replace("`", "").replace("*", "")
    text = re.sub(r"(^|\s)_+|_+(\s|$)", r"\1\2", text)  # _emphasis_, not snake_case
    text = text.lower()
    kept = []
    for ch in text:
        category = unicodedata.category(ch)
        if ch in "-_ " or category[0] in "LNM" or category == "Pc":
            kept.append(ch)
    return "".join(kept).replace(" ", "-")


def headings_raw(path):
    """Headings with their inline code kept (prose_lines blanks inline code)."""
    text = open(path, encoding="utf-8").read()
    lines = text.split("\n")
    return [lines[n - 1] for n, line in prose_lines(text) if HEADING.match(line)]


def heading_anchors(path, cache={}):
    if path not in cache:
        seen = {}
        result = set()
        for line in headings_raw(path):
            base = slug(HEADING.match(line).group(2))
            count = seen.get(base, 0)
            seen[base] = count + 1
            result.add(base if count == 0 else "%s-%d" % (base, count))
        cache[path] = result
    return cache[path]


def check(path, root):
    problems = []
    text = open(path, encoding="utf-8").read()
    name = os.path.relpath(path, root)
    for number, line in prose_lines(text):
        targets = [m.group(1) for m in LINK.finditer(line)]
        m = REFERENCE.match(line)
        if m:
            targets.append(m.group(1))
        for target in targets:
            if URL.match(target):
                continue
            file_part, _, anchor = target.partition("#")
            resolved = os.path.normpath(os.path.join(os.path.dirname(path), file_part)) \
                if file_part else path
            if not os.path.exists(resolved):
                problems.append("%s:%d: %s: no such file %s"
                                % (name, number, target, os.path.relpath(resolved, root)))
                continue
            if anchor:
                if os.path.isdir(resolved) or not resolved.endswith(".md"):
                    problems.append("%s:%d: %s: an anchor into a file that is not Markdown"
                                    % (name, number, target))
                elif anchor not in heading_anchors(resolved):
                    problems.append("%s:%d: %s: no heading '#%s' in %s"
                                    % (name, number, target, anchor,
                                       os.path.relpath(resolved, root)))
    return problems


def main():
    root = os.path.abspath(ROOT)
    problems = []
    files = markdown_files(root)
    links = 0
    for path in files:
        problems.extend(check(path, root))
        links += sum(len(LINK.findall(line)) for _, line in
                     prose_lines(open(path, encoding="utf-8").read()))
    for p in problems:
        print(p)
    print("doc_links: %d files, %d links, %d broken" % (len(files), links, len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
