#!/usr/bin/env python3
"""Fails when a comment or a document cites a repository path that does not exist.

Scans the comments of C++, C and GLSL files and the whole text of scripts, CMake files and
Markdown under the folders below for path-like citations (`src/io/file/json_file.cpp`,
`io/image/jpeg_decode.h`, `shaders/render/composite.glsl`, `vknerf/config.h`, `tools/dev/`), and
resolves each against the repository root and the folders that code names paths from (src/,
include/, shaders/, tools/, tests/, tools/cli/). A word is taken for a citation when its first
folder is a top-level folder of the repository, when it names a source file (.h .cpp .comp .py
...), or when it ends in '/' after a subfolder of a root: so `sparse/0/cameras.bin` (a dataset's
layout), `rays/s` (a unit) or `M/model.vknerf` (a placeholder) are not checked. Globs
(`shaders/*/encode_*.comp`) must match at least one path; a short allowlist below names the
citations of generated files and of other projects' files.

Usage: python3 tools/dev/check_cited_paths.py [REPO_ROOT]   (run by ctest as cited_paths)
Prints FILE:LINE: PATH for each citation that resolves nowhere; exits 1 if there is any.
"""
import glob
import os
import re
import sys

SCANNED = ["src", "include", "shaders", "tools", "tests", "fuzz", "cmake", "docs", ".ci", "python", "examples"]
SCANNED_FILES = ["CMakeLists.txt", "README.md", "assets/README.md"]
# Where a cited path may start: the repository root, then the include and shader roots.
RESOLVE_ROOTS = ["", "src", "include", "shaders", "tools", "tests", "tools/cli"]
TOP_LEVEL = ["src", "include", "shaders", "tools", "tests", "fuzz", "cmake", "docs", "assets", ".ci", "python", "examples"]
SOURCE_EXTENSIONS = (".h", ".hpp", ".cpp", ".c", ".comp", ".glsl", ".py", ".sh", ".cmake")
C_LIKE = (".h", ".hpp", ".cpp", ".c", ".comp", ".glsl", ".in")

# Cited on purpose although they are not files of this repository.
ALLOWED = {
    "generated/shader_ids.h", "gpu/kernels/shader_ids.h",  # written by the build: build/generated/gpu/kernels/shader_ids.h
}
# Other projects' files, cited by their own paths (what vknerf follows or compares with).
ALLOWED_PREFIXES = (
    "scripts/",  # instant-ngp's scripts (scripts/colmap2nerf.py, scripts/run.py)
    "numpy/",  # numpy/lib/format.py: the .npy format
    "sensor/",  # COLMAP's sensor/models.h: its camera models
)

WORD = r"[A-Za-z0-9_.*{},+-]"
# A path: two or more components joined by '/', optionally ending in '/'. Not the tail of a longer
# path or an absolute one, a URL, a placeholder (<out>/x) or a variable (${ROOT}/x, $BUILD/x).
PATH = re.compile(r"(?<![\w./>${}*~:@=-])(" + WORD + r"+(?:/" + WORD + r"+)+/?)")
URL = re.compile(r"\b[a-z][a-z0-9+.-]*://\S+")


def c_comments(text):
    """The text of a C-like file with everything but comments blanked (lines kept)."""
    out, i, n = [], 0, len(text)
    state = "code"
    while i < n:
        c = text[i]
        nxt = text[i + 1] if i + 1 < n else ""
        if state == "code":
            if c == "/" and nxt == "/":
                state, i = "line", i + 2
                out.append("  ")
                continue
            if c == "/" and nxt == "*":
                state, i = "block", i + 2
                out.append("  ")
                continue
            raw = re.match(r'R"([^(\s]{0,16})\(', text[i:i + 20])
            if raw and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
                end = text.find(")" + raw.group(1) + '"', i)
                end = n if end < 0 else end + len(raw.group(1)) + 2
                out.append(re.sub(r"[^\n]", " ", text[i:end]))
                i = end
                continue
            if c in "\"'":
                quote, j = c, i + 1
                while j < n and text[j] != quote and text[j] != "\n":
                    j += 2 if text[j] == "\\" else 1
                out.append(re.sub(r"[^\n]", " ", text[i:j + 1]))
                i = j + 1
                continue
            out.append("\n" if c == "\n" else " ")
        elif state == "line":
            if c == "\n":
                state = "code"
            out.append(c)
        else:  # block
            if c == "*" and nxt == "/":
                state, i = "code", i + 2
                out.append("  ")
                continue
            out.append(c)
        i += 1
    return "".join(out)


def expand_braces(path):
    m = re.search(r"\{([^{}]*)\}", path)
    if not m:
        return [path]
    return [x for alt in m.group(1).split(",") for x in expand_braces(path[:m.start()] + alt + path[m.end():])]


def exists(root, rel):
    for candidate in expand_braces(rel):
        full = os.path.join(root, candidate)
        if any(ch in candidate for ch in "*?[") and glob.glob(full):
            return True
        if os.path.exists(full):
            return True
    return False


def subfolders(root):
    names = set()
    for r in RESOLVE_ROOTS:
        base = os.path.join(root, r)
        if os.path.isdir(base):
            # Build folders (build/, build-asan/: .gitignore's /build*/) come and go with the
            # builds: a path under one is an output, not a citation of the repository.
            names.update(d for d in os.listdir(base)
                         if os.path.isdir(os.path.join(base, d)) and not d.startswith(("build", ".")))
    return names


def is_citation(path, folders):
    first = path.split("/", 1)[0]
    if first in TOP_LEVEL:
        return True
    # Below a root, a folder name alone is also a common word (rays/s, render/render.json in a
    # capture's layout): a citation there names a source file or ends in '/'.
    return path.endswith(SOURCE_EXTENSIONS) or (first in folders and path.endswith("/"))


def resolves(root, path, citing_dir):
    if path in ALLOWED or path.startswith(ALLOWED_PREFIXES):
        return True
    bases = RESOLVE_ROOTS + [citing_dir]
    return any(exists(os.path.join(root, base), path) for base in bases)


def scanned_files(root):
    for top in SCANNED:
        for dirpath, dirnames, filenames in os.walk(os.path.join(root, top)):
            dirnames[:] = [d for d in dirnames if d not in ("__pycache__", "build")]
            for name in filenames:
                yield os.path.join(dirpath, name)
    for name in SCANNED_FILES:
        yield os.path.join(root, name)


def main():
    root = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "../.."))
    folders = subfolders(root)
    missing = 0
    for path in scanned_files(root):
        rel = os.path.relpath(path, root)
        if not os.path.isfile(path) or rel.endswith((".png", ".jpg", ".bin", ".vknerf", ".npy")):
            continue
        try:
            text = open(path, encoding="utf-8").read()
        except UnicodeDecodeError:
            continue
        if rel.endswith(C_LIKE):
            text = c_comments(text)
        for lineno, line in enumerate(text.splitlines(), 1):
            line = URL.sub(" ", line)
            for m in PATH.finditer(line):
                cited = m.group(1).rstrip(".,;:")
                if "/" not in cited or not is_citation(cited, folders):
                    continue
                if not resolves(root, cited, os.path.dirname(rel)):
                    print(f"{rel}:{lineno}: {cited}")
                    missing += 1
    if missing:
        print(f"{missing} cited path(s) do not exist (tools/dev/check_cited_paths.py)", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
