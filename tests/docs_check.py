#!/usr/bin/env python3
"""The README and the manual as a reader meets them: the README at most 250 lines; every relative
link and image in README.md and docs/ resolves (the file, and a #heading where one is named), and
every repository path they name (core/src/convolution/far_tail.cpp) exists; no
file of the repository speaks of the work's history (issue numbers, "stop"s, "session"s) or cites
a file outside the repository. Usage: docs_check.py SOURCE_DIR"""
import os
import re
import subprocess
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else ".")
SELF = os.path.relpath(os.path.abspath(__file__), ROOT)
README_MAX_LINES = 250

# Words of the work's history, not of the project. "stop" alone is an ordinary verb (a run stops
# on SIGINT): only the history's phrasings are refused.
PROCESS = re.compile(r"\bissues?\b|\bissue-\d|\b(?:last|this|previous|next|that|earlier) stop\b|\bstops? \d"
                     r"|\bsessions?\b", re.IGNORECASE)
# Files outside the repository that code and docs once cited.
EXTERNAL = re.compile(r"\bNOTES\.md\b|\bPHYSICS\.md\b|\bshared/|/work/")
# The licence text is the Apache licence's own ("issue tracking systems").
PROCESS_EXEMPT = {"LICENSE"}

LINK = re.compile(r"!?\[[^\]]*\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)")
# A path into the repository named in the text ("core/src/convolution/far_tail.cpp", `tests/bench/run_bench.sh`):
# it must exist, so that a reader following the docs finds the file.
SOURCE_PATH = re.compile(r"(?<![\w./-])((?:core|plugin|tests|test_scenes|packaging|ocio_configs|docs|\.ci)/"
                         r"[\w./-]*\.(?:h|hpp|cpp|py|sh|cmake|md|ocio|toml|pov|inc|comp|glsl|json|txt))\b")


def tracked_files():
    try:
        out = subprocess.run(["git", "-C", ROOT, "ls-files", "-z"], check=True, capture_output=True).stdout
        files = [f for f in out.decode().split("\0") if f]
        if files:
            return files
    except (OSError, subprocess.CalledProcessError):
        pass
    files = []  # not a git checkout: every file but build outputs
    for d, dirs, names in os.walk(ROOT):
        dirs[:] = [x for x in dirs if x != ".git" and x != "out" and not x.startswith("build")]
        files += [os.path.relpath(os.path.join(d, n), ROOT) for n in names]
    return files


def text_of(path):
    try:
        with open(os.path.join(ROOT, path), "rb") as f:
            data = f.read()
    except OSError:
        return None  # listed by git but not on disk (e.g. deleted in the work tree)
    if b"\0" in data[:8192]:
        return None  # binary
    return data.decode("utf-8", errors="replace")


def slug(heading):
    """GitHub's anchor for a heading: lower case, punctuation dropped, spaces to hyphens."""
    h = re.sub(r"[`*_]", "", heading.strip().lower())
    h = "".join(c for c in h if c.isalnum() or c in " -")
    return h.replace(" ", "-")


def anchors(path):
    text = text_of(path) or ""
    return {slug(m.group(1)) for m in re.finditer(r"^#+\s+(.*)$", text, re.MULTILINE)}


def main():
    problems = []
    readme = os.path.join(ROOT, "README.md")
    with open(readme, encoding="utf-8") as f:
        lines = f.read().splitlines()
    if len(lines) > README_MAX_LINES:
        problems.append(f"README.md: {len(lines)} lines, expected at most {README_MAX_LINES} (move detail to docs/)")

    files = tracked_files()
    docs = ["README.md"] + sorted(f for f in files if f.startswith("docs/") and f.endswith(".md"))
    if len(docs) < 2:
        problems.append("docs/: no manual pages found")
    for doc in docs:
        text = text_of(doc) or ""
        for n, line in enumerate(text.splitlines(), 1):
            for m in LINK.finditer(line):
                target = m.group(1)
                if re.match(r"^[a-z]+:", target):
                    continue  # http:, https:, mailto:
                path, _, anchor = target.partition("#")
                resolved = os.path.normpath(os.path.join(os.path.dirname(doc), path)) if path else doc
                if resolved.startswith(".."):
                    problems.append(f"{doc}:{n}: link '{target}' leaves the repository")
                elif not os.path.exists(os.path.join(ROOT, resolved)):
                    problems.append(f"{doc}:{n}: link '{target}': {resolved} does not exist")
                elif anchor and resolved.endswith(".md") and anchor not in anchors(resolved):
                    problems.append(f"{doc}:{n}: link '{target}': no heading '#{anchor}' in {resolved}")
            for m in SOURCE_PATH.finditer(line):
                if not os.path.exists(os.path.join(ROOT, m.group(1))):
                    problems.append(f"{doc}:{n}: names {m.group(1)}, which does not exist")

    for path in files:
        if path == SELF:
            continue
        text = text_of(path)
        if text is None:
            continue
        for n, line in enumerate(text.splitlines(), 1):
            if path not in PROCESS_EXEMPT and (m := PROCESS.search(line)):
                problems.append(f"{path}:{n}: speaks of the work's history ('{m.group(0)}'): {line.strip()[:120]}")
            if m := EXTERNAL.search(line):
                problems.append(f"{path}:{n}: cites a file outside the repository ('{m.group(0)}'): "
                                f"{line.strip()[:120]}")

    for p in problems:
        print(p)
    print(f"checked README.md ({len(lines)} lines), {len(docs) - 1} manual pages, {len(files)} files: "
          f"{len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
