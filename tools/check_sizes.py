#!/usr/bin/env python3
"""The size rule of the sources (ARCHITECTURE.md, "Sizes"): no source file
above 800 lines and no function above 150 lines, unless the reason is
written at its top: a comment starting "Over 800 lines:" in the file's first
lines, or "Over 150 lines:" in the comment just above the function.

usage: tools/check_sizes.py [--list] [ROOT]
Exits 1 naming each file or function over its limit without a reason;
--list also prints those with one (what the rule lets through, and why).
"""

import re
import sys
from pathlib import Path

FILE_LIMIT = 800
FUNCTION_LIMIT = 150
SOURCE_DIRS = ["include", "src", "apps", "tools", "bench", "web/src"]
SUFFIXES = {".h", ".cc", ".cpp", ".ts"}
CONTROL = re.compile(r"^\s*(if|for|while|switch|catch|do|else|try|return)\b")


def strip_code(line, state):
    """The line without comments and string/char literals (braces inside
    them do not count); state carries a /* */ comment across lines."""
    out = []
    i = 0
    quote = None
    while i < len(line):
        c = line[i]
        if state["block"]:
            if line.startswith("*/", i):
                state["block"] = False
                i += 2
            else:
                i += 1
            continue
        if quote:
            if c == "\\":
                i += 2
                continue
            if c == quote:
                quote = None
            i += 1
            continue
        if line.startswith("//", i):
            break
        if line.startswith("/*", i):
            state["block"] = True
            i += 2
            continue
        if line.startswith('R"(', i):  # raw strings: skip to )"
            end = line.find(')"', i + 3)
            if end < 0:
                break
            i = end + 2
            continue
        if c in "\"'`":
            quote = c
            i += 1
            continue
        out.append(c)
        i += 1
    return "".join(out)


def reason_above(lines, index, marker):
    """A comment block right above line `index` (0-based) holding `marker`."""
    j = index - 1
    while j >= 0 and lines[j].strip().startswith(("//", "*", "/*", "template", "[[")):
        if marker in lines[j]:
            return True
        j -= 1
    return False


def functions(path, lines):
    """(name, first line, length) of each function body: a brace block whose
    head has a parameter list and that sits at namespace or class level."""
    state = {"block": False}
    stack = []  # (kind, start line, head)
    head = ""
    head_line = 0  # where the head began
    found = []
    for n, raw in enumerate(lines):
        code = strip_code(raw, state)
        if code.lstrip().startswith("#"):  # preprocessor lines hold no braces of the code
            head = ""
            continue
        for c in code:
            if c == "{":
                h = head.strip()
                parent_ok = all(kind in ("namespace", "class") for kind, _, _ in stack)
                if re.match(r"^(export\s+)?namespace\b|^extern\s+\"", h) or h.startswith("namespace"):
                    kind = "namespace"
                elif re.search(r"\b(class|struct|union|enum)\b[^()]*$", h):
                    kind = "class"
                elif parent_ok and "(" in h and not CONTROL.match(h) and not h.endswith("=") and "=>" not in h[-4:]:
                    kind = "function"
                else:
                    kind = "block"
                stack.append((kind, head_line if h else n, h))
                head = ""
            elif c == "}":
                if stack:
                    kind, start, h = stack.pop()
                    if kind == "function":
                        name = re.sub(r"\s+", " ", h.split("(")[0]).strip().split(" ")[-1]
                        found.append((name, start, n - start + 1))
                head = ""
            elif c == ";":
                head = ""
            else:
                if not head.strip() and not c.isspace():
                    head_line = n
                head += c
        head += " "
    return found


def main(argv):
    list_all = "--list" in argv
    args = [a for a in argv if not a.startswith("--")]
    root = Path(args[0]) if args else Path(__file__).resolve().parent.parent
    bad, allowed = [], []
    for d in SOURCE_DIRS:
        for path in sorted((root / d).rglob("*")):
            if path.suffix not in SUFFIXES or not path.is_file() or "node_modules" in path.parts:
                continue
            lines = path.read_text(encoding="utf-8", errors="replace").splitlines()
            rel = path.relative_to(root)
            if len(lines) > FILE_LIMIT:
                head = "\n".join(lines[:12])
                (allowed if "Over 800 lines:" in head else bad).append(f"{rel}: {len(lines)} lines")
            if path.suffix == ".ts":
                continue
            for name, start, length in functions(path, lines):
                if length > FUNCTION_LIMIT:
                    entry = f"{rel}:{start + 1}: {name}: {length} lines"
                    (allowed if reason_above(lines, start, "Over 150 lines:") else bad).append(entry)
    if list_all:
        for a in allowed:
            print("over, with a reason:", a)
    for b in bad:
        print("over, without a reason:", b)
    if bad:
        print(f"check_sizes: {len(bad)} over the limits (files {FILE_LIMIT} lines, functions {FUNCTION_LIMIT}) "
              "without a reason at their top", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
