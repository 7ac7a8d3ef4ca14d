#!/usr/bin/python3
"""The sizes hencky's sources keep (docs/development.md, "Sizes"), and the check that they do.

    check_structure.py SOURCE_DIR     exit 0 when nothing is over its size; else lists each

- a file of src/ or app/: at most 700 lines; in src/solve/ at most 400;
- a function (a body between braces at namespace or class level): at most 100 lines;
- a class or struct of src/solve/: at most 20 data members.

The parse is a brace count over the source with comments and literals blanked out: good
enough for this codebase's layout (clang-format, one declaration a line), not a C++ parser.
"""
import re
import sys
from pathlib import Path

FILE_LINES, SOLVE_FILE_LINES, FUNCTION_LINES, SOLVE_MEMBERS = 700, 400, 100, 20

LITERAL = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', re.S)


def blank(text: str) -> str:
    """Comments and literals replaced by spaces (newlines kept, so line numbers hold)."""
    return LITERAL.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)


def blocks(code: str):
    """(kind, name, first line, last line, depth, body) of every brace block; kind is
    'type' (class/struct/union/enum), 'function' or 'other'."""
    stack = []  # (start offset, header)
    out = []
    last = 0  # end of the last statement or block at this point: the header starts after it
    for i, ch in enumerate(code):
        if ch == "{":
            header = code[last:i]
            stack.append((i, header))
            last = i + 1
        elif ch == "}":
            if not stack:
                continue
            start, header = stack.pop()
            h = " ".join(header.split())
            first = code.count("\n", 0, start) + 1
            end = code.count("\n", 0, i) + 1
            kind, name = "other", ""
            if m := re.search(r"\b(class|struct|union|enum(?:\s+class)?)\s+(\w+)[^;()]*$", h):
                kind, name = "type", m.group(2)
            elif m := re.search(r"([\w:~<>]+)\s*\([^;]*\)[^;(){}]*$", h):
                if not re.match(r"(if|for|while|switch|catch|return)$", m.group(1)) and \
                        "=" not in h.split("(")[0] and not h.endswith(")="):
                    kind, name = "function", m.group(1)
            out.append((kind, name, first, end, len(stack), code[start + 1:i]))
            last = i + 1
        elif ch == ";" and stack is not None:
            last = i + 1
    return out


def top_level_commas(s: str) -> int:
    """Commas outside <>, (), {} and []: the names one declaration declares, less one."""
    depth, n = 0, 0
    for ch in s:
        if ch in "<({[":
            depth += 1
        elif ch in ">)}]":
            depth -= 1
        elif ch == "," and depth == 0:
            n += 1
    return n


def members(body: str) -> int:
    """Data members of a class body: statements at its own depth that declare no function."""
    depth, stmt, n = 0, [], 0
    for ch in body:
        if ch == "{":
            depth += 1
        elif ch == "}":
            depth -= 1
            if depth == 0:
                stmt = []
            continue
        if depth:
            continue
        if ch == ";":
            s = " ".join("".join(stmt).split())
            s = re.sub(r"^(public|private|protected)\s*:\s*", "", s)
            stmt = []
            if not s or re.match(r"(using|typedef|friend|static constexpr|static_assert|enum)\b", s) \
                    or re.search(r"\boperator\b", s):
                continue
            if "(" in s and not re.search(r"[={]", s.split("(")[0]):
                continue  # a function declaration
            n += top_level_commas(s) + 1
        else:
            stmt.append(ch)
    return n


def main() -> int:
    root = Path(sys.argv[1]).resolve()
    files = sorted([*root.glob("src/**/*.[ch]pp"), *root.glob("app/*.[ch]pp")])
    findings = []
    for f in files:
        rel = f.relative_to(root)
        text = f.read_text()
        solve = rel.parts[:2] == ("src", "solve")
        n_lines = text.count("\n")
        limit = SOLVE_FILE_LINES if solve else FILE_LINES
        if n_lines > limit:
            findings.append(f"{rel}: {n_lines} lines (at most {limit})")
        for kind, name, first, last, _, body in blocks(blank(text)):
            if kind == "function" and last - first + 1 > FUNCTION_LINES:
                findings.append(f"{rel}:{first}: function {name}, {last - first + 1} lines "
                                f"(at most {FUNCTION_LINES})")
            if kind == "type" and solve and (k := members(body)) > SOLVE_MEMBERS:
                findings.append(f"{rel}:{first}: class {name}, {k} data members "
                                f"(at most {SOLVE_MEMBERS})")
    for x in findings:
        print(x)
    print(f"{len(files)} files, {len(findings)} over their size")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
