#!/usr/bin/env python3
"""docs/settings.md's table against the code: its keys are exactly the keys the OIIO plugin knows
(as its "unknown key (known: ...)" message lists them) and its command-line flags exactly the
setting flags `wavecam apply --help` lists. Usage:
settings_reference_check.py SOURCE_DIR WAVECAM_BINARY PLUGIN_DIR"""
import os
import re
import subprocess
import sys
import tempfile

ROOT, WAVECAM, PLUGIN_DIR = sys.argv[1:4]
# `wavecam apply`'s options that are not settings: where the run reads and writes, and how.
COMMAND_ONLY = {"--help", "--output", "--compare", "--png", "--frames", "--threads", "--share"}


def documented():
    """(key, flag) of each row of the table whose header starts with '| key |'."""
    rows, in_table = [], False
    with open(os.path.join(ROOT, "docs", "settings.md"), encoding="utf-8") as f:
        for line in f:
            cells = [c.strip() for c in line.strip().strip("|").split("|")] if line.startswith("|") else []
            if cells and cells[0].lower() == "key":
                in_table = True
                continue
            if not in_table:
                continue
            if not cells:
                break
            if set(cells[0]) <= set("-: "):
                continue  # the separator row
            key = re.fullmatch(r"`([a-z-]+)`", cells[0])
            flag = re.match(r"`(--[a-z-]+)", cells[1])
            if not key or not flag:
                sys.exit(f"docs/settings.md: row '{line.strip()[:80]}': expected `key` then `--flag` in its first cells")
            rows.append((key.group(1), flag.group(1)))
    if not rows:
        sys.exit("docs/settings.md: no table with a 'key' column found")
    return rows


def help_flags():
    out = subprocess.run([WAVECAM, "apply", "--help"], capture_output=True, text=True, check=True).stdout
    return set(re.findall(r"^\s+(?:-\w,)?(--[a-z-]+)", out, re.MULTILINE)) - COMMAND_ONLY


def plugin_keys():
    with tempfile.TemporaryDirectory() as d:
        src = os.path.join(d, "t.exr")
        subprocess.run(["oiiotool", "--pattern", "constant:color=0.5,0.5,0.5", "4x4", "3", "-o", src], check=True)
        env = dict(os.environ, OIIO_LIBRARY_PATH=PLUGIN_DIR)
        r = subprocess.run(["oiiotool", "--iconfig", "wavecam:no-such-key", "1", src + ".wavecam", "-o",
                            os.path.join(d, "x.exr")], capture_output=True, text=True, env=env)
    m = re.search(r"unknown key[^(]*\(known: ([^)]*)\)", r.stdout + r.stderr)
    if not m:
        sys.exit("the plugin did not list its keys for an unknown one:\n" + r.stdout + r.stderr)
    return {k.strip() for k in m.group(1).split(",")}


def main():
    rows = documented()
    keys, flags = {k for k, _ in rows}, {f for _, f in rows}
    problems = []
    if len(keys) != len(rows):
        problems.append("docs/settings.md lists a key twice")
    code_keys, code_flags = plugin_keys(), help_flags()
    for k in sorted(code_keys - keys):
        problems.append(f"key '{k}': known to the plugin, missing from docs/settings.md")
    for k in sorted(keys - code_keys):
        problems.append(f"key '{k}': in docs/settings.md, unknown to the plugin")
    for f in sorted(code_flags - flags):
        problems.append(f"flag '{f}': in `wavecam apply --help`, missing from docs/settings.md "
                        f"(a flag that is no setting belongs in this test's COMMAND_ONLY)")
    for f in sorted(flags - code_flags):
        problems.append(f"flag '{f}': in docs/settings.md, not in `wavecam apply --help`")
    for p in problems:
        print(p)
    print(f"docs/settings.md: {len(rows)} keys; plugin {len(code_keys)} keys; command {len(code_flags)} setting flags: "
          f"{len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
