#!/usr/bin/env python3
"""The house rules of doc/architecture.md, checked on the source tree.

- Layers: a file under include/contact-stefan/<layer>/ or source/<layer>/ includes
  project headers of its own layer or of layers below it only, and the two
  field layers (thermal, mechanics) do not include each other.
- A class template is explicitly instantiated ('template class X<...>') in one
  file only.
- No source or header file over 1000 lines; no function over 150 lines.
- No citation of a file outside the repository (../shared/).

Usage: check_house.py SOURCE_DIR. Prints every violation and exits 1 if any."""
import re
import sys
from pathlib import Path

LAYERS = ["core", "mesh", "interfaces", "linear_algebra", ("thermal", "mechanics"),
          "output", "verification", "coupling", "app"]
RANK = {}
for rank, layer in enumerate(LAYERS):
    for name in (layer if isinstance(layer, tuple) else (layer,)):
        RANK[name] = rank
MAX_FILE_LINES = 1000
MAX_FUNCTION_LINES = 150


def layer_of(path, root):
    parts = path.relative_to(root).parts
    if parts[0] == "include":
        return parts[2]
    return parts[1]


def function_lengths(text):
    """(first line, length) of every function body: a line that is only '{' at
    the indentation of the namespace level (2 or 4 blanks) opens one, the next
    line with '}' at the same indentation closes it."""
    lines = text.split("\n")
    result = []
    open_at = None
    for number, line in enumerate(lines, 1):
        if open_at is None:
            match = re.fullmatch(r"( {2}| {4})\{", line)
            if match and number > 1 and not lines[number - 2].strip().startswith(
                    ("namespace", "struct", "class", "enum")):
                open_at, indent = number, match.group(1)
        elif re.fullmatch(indent + r"\}.*", line):
            result.append((open_at, number - open_at + 1))
            open_at = None
    return result


def main():
    root = Path(sys.argv[1]).resolve()
    files = sorted(list((root / "include" / "contact-stefan").rglob("*.h")) +
                   list((root / "source").rglob("*.cc")))
    problems = []
    instantiated = {}
    for path in files:
        text = path.read_text()
        name = path.relative_to(root)
        layer = layer_of(path, root)
        if layer not in RANK:
            problems.append(f"{name}: folder '{layer}' is not a layer ({', '.join(RANK)})")
            continue
        for header in re.findall(r'#include <contact-stefan/([a-z_]+)/', text):
            if header not in RANK:
                problems.append(f"{name}: includes from '{header}', which is not a layer")
            elif RANK[header] > RANK[layer] or (RANK[header] == RANK[layer] and header != layer):
                problems.append(f"{name}: layer '{layer}' includes '{header}' (a higher layer "
                                "or a sibling)")
        for cls in re.findall(r"^\s*template class (\w+)<", text, re.M):
            instantiated.setdefault(cls, []).append(str(name))
        n_lines = text.count("\n")
        if n_lines > MAX_FILE_LINES:
            problems.append(f"{name}: {n_lines} lines (at most {MAX_FILE_LINES})")
        for first, length in function_lengths(text):
            if length > MAX_FUNCTION_LINES:
                problems.append(f"{name}:{first}: a function of {length} lines "
                                f"(at most {MAX_FUNCTION_LINES})")
        if "../shared/" in text or "BENCHMARKS.md" in text or "DESIGN.md" in text:
            problems.append(f"{name}: cites a file outside the repository")
    for cls, where in sorted(instantiated.items()):
        if len(where) > 1:
            problems.append(f"{cls} is instantiated in {len(where)} files: {', '.join(where)}")
    for other in list(root.glob("prm/**/*.prm")) + list(root.glob("doc/*.md")) + [root / "README.md"]:
        text = other.read_text()
        if "../shared/" in text or "BENCHMARKS.md" in text or "DESIGN.md" in text:
            problems.append(f"{other.relative_to(root)}: cites a file outside the repository")
    for problem in problems:
        print(problem)
    print(f"{len(files)} files in {len(RANK)} layers: {len(problems)} violations")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
