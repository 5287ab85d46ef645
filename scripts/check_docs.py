#!/usr/bin/env python3
"""Checks that the documentation's links resolve: README.md and every docs/*.md.

Usage: check_docs.py [REPOSITORY_DIR]

Every relative link or image, [text](target) or ![alt](target), and every reference definition,
[name]: target, must name a file or folder that exists, relative to the page it is on. A
#anchor, alone (this page) or after a .md target, must be the slug of a heading of that page by
GitHub's rule: the heading's text in lower case, punctuation other than '-' and '_' dropped, each
space a '-', and a repeated slug numbered -1, -2, ... Links with a scheme (http:, https:, mailto:)
are not checked, nor anything inside fenced code blocks or inline code. Prints each broken link as
"check_docs: FILE:LINE: broken link TARGET" and fails; else prints one line of what it checked.
"""
import os
import re
import sys
from urllib.parse import unquote

FENCE = re.compile(r"^\s{0,3}(```|~~~)")
HEADING = re.compile(r"^\s{0,3}(#{1,6})\s+(.*?)\s*#*\s*$")
CODE_SPAN = re.compile(r"(`+)(.+?)\1")
# [text](target "title"): the text may hold one level of brackets (an image inside a link).
INLINE_LINK = re.compile(r"!?\[((?:[^\[\]]|\[[^\[\]]*\])*)\]\(\s*<?([^)\s>]*)>?(?:\s+[\"'(][^)]*)?\)")
REFERENCE = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s+.*)?$")
SCHEME = re.compile(r"^[A-Za-z][A-Za-z0-9+.-]*:")


def prose_lines(path):
    """(line number, text) of each line outside fenced code blocks."""
    fence = None
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            line = line.rstrip("\n")
            m = FENCE.match(line)
            if m:
                if fence is None:
                    fence = m.group(1)
                elif m.group(1) == fence:
                    fence = None
                continue
            if fence is None:
                yield number, line


def slug(text):
    """GitHub's anchor for a heading's text (its markup as GitHub renders it away)."""
    text = CODE_SPAN.sub(lambda m: m.group(2), text)
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", text)  # a link's text only
    text = re.sub(r"<[^>]+>", "", text)  # inline HTML
    return re.sub(r"[^\w\- ]", "", text.strip().lower()).replace(" ", "-")


_ANCHORS = {}


def anchors(path):
    """The anchors of a page's headings."""
    if path not in _ANCHORS:
        found, seen = set(), {}
        for _number, line in prose_lines(path):
            m = HEADING.match(line)
            if not m:
                continue
            base = slug(m.group(2))
            count = seen.get(base, 0)
            seen[base] = count + 1
            found.add(base if count == 0 else "%s-%d" % (base, count))
        _ANCHORS[path] = found
    return _ANCHORS[path]


def links(path):
    """(line number, target) of each link on a page, code excluded."""
    for number, line in prose_lines(path):
        m = REFERENCE.match(line)
        if m:
            yield number, m.group(1)
            continue
        texts = [CODE_SPAN.sub("", line)]
        while texts:
            for m in INLINE_LINK.finditer(texts.pop()):
                texts.append(m.group(1))  # an image inside a link's text
                yield number, m.group(2)


def broken(page, target):
    """True when a link's target does not resolve from the page."""
    if not target or SCHEME.match(target):
        return False
    file_part, _hash, anchor = target.partition("#")
    destination = page
    if file_part:
        destination = os.path.normpath(os.path.join(os.path.dirname(page), unquote(file_part)))
        if not os.path.exists(destination):
            return True
    if anchor and destination.endswith(".md") and os.path.isfile(destination):
        return unquote(anchor).lower() not in anchors(destination)
    return False


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else
                           os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    pages = [os.path.join(root, "README.md")]
    docs = os.path.join(root, "docs")
    if os.path.isdir(docs):
        pages += [os.path.join(docs, n) for n in sorted(os.listdir(docs)) if n.endswith(".md")]
    problems, checked = [], 0
    for page in pages:
        if not os.path.isfile(page):
            problems.append("%s: missing" % os.path.relpath(page, root))
            continue
        for number, target in links(page):
            checked += 1
            if broken(page, target):
                problems.append("%s:%d: broken link %s" % (os.path.relpath(page, root), number,
                                                            target))
    for p in problems:
        print("check_docs: " + p)
    if problems:
        return 1
    print("check_docs: %d links on %d pages, every file and anchor found" % (checked, len(pages)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
