#!/usr/bin/env python3
"""Checks the house's size rules on src/: no function body over 150 lines, no file over 650.

A function body is counted from the line of its opening brace to the line of its closing brace,
both included; lambdas and local classes count towards the function they sit in. The file rule
counts physical lines. The script reads C++ without a compiler: comments, string and character
literals (raw strings too) and preprocessor lines are blanked first, then braces are matched and
each brace opened at namespace or class scope is classed as a namespace, a class, a function
body (its declaration holds a parameter list), a constructor's member initializer, or data.

Prints one line per problem (path:line: what) and exits 1 on any, 0 when src/ passes.

Usage: scripts/check_sizes.py [REPOSITORY_ROOT]
"""

import pathlib
import re
import sys

MAX_FUNCTION_LINES = 150
MAX_FILE_LINES = 650
# Files exempt from the file rule, each with why: data, not code.
FILE_EXEMPT = {}

SOURCE_SUFFIXES = {".cpp", ".hpp", ".h", ".cc"}
RAW_STRING = re.compile(r'R"([^()\\ ]{0,16})\(')


def blank(text):
    """The text with comments, literals and preprocessor lines replaced by spaces (newlines kept)."""
    out = []
    i, n = 0, len(text)
    line_start = True
    while i < n:
        c = text[i]
        if line_start and c == "#":
            # A preprocessor line, continued by trailing backslashes.
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    out.append("  \n")
                    i += 2
                    continue
                out.append(" ")
                i += 1
            continue
        if c == "\n":
            out.append(c)
            i += 1
            line_start = True
            continue
        if c in " \t":
            out.append(c)
            i += 1
            continue
        line_start = False
        if text.startswith("//", i):
            while i < n and text[i] != "\n":
                out.append(" ")
                i += 1
            continue
        if text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
            continue
        raw = RAW_STRING.match(text, i)
        if raw and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            close = ")" + raw.group(1) + '"'
            end = text.find(close, raw.end())
            end = n if end < 0 else end + len(close)
            out.append(re.sub(r"[^\n]", " ", text[i:end]))
            i = end
            continue
        if c in "\"'":
            # A digit separator (1'000) is not a character literal.
            if c == "'" and i > 0 and text[i - 1].isalnum() and i + 1 < n and text[i + 1].isalnum():
                out.append(" ")
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            out.append(" " * (min(j + 1, n) - i))
            i = j + 1
            continue
        out.append(c)
        i += 1
    return "".join(out)


def strip_parens(statement):
    """The statement with everything inside (...) removed, the parentheses kept."""
    out, depth = [], 0
    for c in statement:
        if c == ")":
            depth -= 1
        if depth == 0:
            out.append(c)
        if c == "(":
            depth += 1
    return "".join(out)


def classify(statement):
    """What a brace opened at namespace or class scope after `statement` opens."""
    s = " ".join(statement.split())
    if re.search(r"\bnamespace\b", s) or re.fullmatch(r'extern\s*', s):
        return "scope"
    flat = strip_parens(s)
    if re.search(r"\b(class|struct|union|enum)\b", flat) and "(" not in flat.split("=")[0]:
        return "scope"
    before = s.rstrip()
    if not before or before[-1] in "=,([{":
        return "data"
    top = flat.split("=")[0] if not re.search(r"\boperator\b", flat) else flat
    if "()" not in top:
        return "data"
    # After `) :` a constructor's initializers follow; `x{..}` is one, `) {` or `} {` the body.
    init = re.search(r"\)\s*[a-z\s]*:(?!:)", flat)
    if init and before[-1] not in ")}":
        return "data"
    return "function"


def function_name(statement):
    flat = strip_parens(" ".join(statement.split()))
    m = re.search(r"((?:[\w~]+\s*(?:<[^()]*>)?\s*::\s*)*(?:operator\s*\S+?|[\w~]+))\s*\(\)", flat)
    return m.group(1).replace(" ", "") if m else flat.strip()[:60]


def long_functions(text):
    """(line, name, lines) of every function body longer than the limit."""
    code = blank(text)
    found = []
    stack = []  # one (kind, open_line, statement) per open brace
    statement = []
    line = 1
    for c in code:
        if c == "\n":
            line += 1
        inside_function = any(kind == "function" for kind, _, _ in stack)
        if c == "{":
            if inside_function:
                stack.append(("block", line, ""))
            else:
                text_before = "".join(statement)
                kind = classify(text_before)
                stack.append((kind, line, text_before))
                if kind in ("scope", "function"):
                    statement = []
                else:
                    statement.append(c)
            continue
        if c == "}" and stack:
            kind, open_line, before = stack.pop()
            if kind == "function":
                length = line - open_line + 1
                if length > MAX_FUNCTION_LINES:
                    found.append((open_line, function_name(before), length))
                statement = []
            elif kind == "scope":
                statement = []
            elif not inside_function:
                statement.append(c)
            continue
        if not inside_function:
            if c == ";" and not any(kind == "data" for kind, _, _ in stack):
                statement = []
            else:
                statement.append(c)
    return found


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parent.parent)
    problems = []
    for path in sorted((root / "src").rglob("*")):
        if path.suffix not in SOURCE_SUFFIXES or not path.is_file():
            continue
        rel = path.relative_to(root).as_posix()
        text = path.read_text(encoding="utf-8", errors="replace")
        lines = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
        if lines > MAX_FILE_LINES and rel not in FILE_EXEMPT:
            problems.append(f"{rel}:1: file of {lines} lines (at most {MAX_FILE_LINES})")
        for line, name, length in long_functions(text):
            problems.append(
                f"{rel}:{line}: function {name} of {length} lines (at most {MAX_FUNCTION_LINES})"
            )
    for p in problems:
        print(p)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
