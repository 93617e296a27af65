#!/usr/bin/env python3
"""Every repository path the Markdown documents name exists in the tree.

It reads every tracked *.md file (README.md, docs/**, viewer/README.md, accuracy/README.md,
bench/RESULTS.md, ...) outside fenced code blocks and checks:
* each Markdown link or image target that is not a URL: the file or folder, relative to the
  document, and for a link into a Markdown file with a #fragment, a heading of that file;
* each path in an inline `code span` or in the text: a word holding a '/' whose first folder is a
  top-level folder of the repository (`granular/step/block_step.hpp`, `docs/ACCURACY.md`), or a
  word of the form folder/file.ext with a known extension (`step/motion_table.hpp`). The first kind
  must exist from the repository root, or under an include folder (`granular/extend/backend.hpp`
  is <granular/extend/backend.hpp>), or relative to the document; the second kind relative to the
  document, under an include folder, or as the tail of a repository path (`gpu/test_cuda_history.cpp`
  is tests/gpu/test_cuda_history.cpp).
Words that name no repository file are skipped by the narrow rules of `skipped` below: URLs,
shell globs, placeholders (`<prefix>/bin`, `docs/accuracy/<test>.md`, `$OUT`), elisions
(`<granular/engine/...>`), absolute and home paths, and build outputs (`build/...`, `build-gpu/...`).
It prints each missing path with its document and line, and exits 1 when there is one."""
import os
import re
import subprocess
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

# Extensions of the files a document may name by folder/file.ext.
EXTENSIONS = ("md", "cpp", "hpp", "h", "cu", "cuh", "py", "json", "txt", "cmake", "in", "comp",
              "vert", "frag", "glsl", "spv", "png", "csv", "sh", "vox", "raw", "gsnap")

# First folders of paths that are build outputs or scratch folders, never repository files.
OUTPUT_FOLDERS = ("build", ".gpubin", "gpu-out", ".deps")

# Characters that make a word a glob, a placeholder or a shell expression rather than a path.
NOT_A_PATH = re.compile(r"[*?{}<>$|\\=]|\.\.\.")


def tracked_files():
    """The repository's files (tracked, or new and not ignored), as paths relative to ROOT."""
    try:
        out = subprocess.run(["git", "-C", ROOT, "ls-files", "--cached", "--others", "--exclude-standard", "-z"],
                             check=True, capture_output=True).stdout.decode()
        files = [f for f in out.split("\0") if f]
        return [f for f in files if os.path.exists(os.path.join(ROOT, f))]
    except (OSError, subprocess.CalledProcessError):
        files = []
        for folder, dirs, names in os.walk(ROOT):
            dirs[:] = [d for d in dirs if not d.startswith(".") and not d.startswith("build")]
            files += [os.path.relpath(os.path.join(folder, n), ROOT) for n in names]
        return files


def skipped(word):
    """True for a word that names no repository path: a URL, a glob, a placeholder, an elision,
    an absolute or home path, a build output."""
    if "://" in word or word.startswith(("mailto:", "www.")):
        return True
    if NOT_A_PATH.search(word):
        return True
    if word.startswith(("/", "~")):
        return True
    first = (word[2:] if word.startswith("./") else word).split("/")[0]
    return first in OUTPUT_FOLDERS or first.startswith("build-")


def heading_anchors(text):
    """The GitHub anchors of a Markdown text's headings."""
    anchors, seen = set(), {}
    for line in strip_fences(text).splitlines():
        m = re.match(r"#{1,6}\s+(.*?)\s*#*\s*$", line)
        if not m:
            continue
        title = re.sub(r"[`*_]|\[([^\]]*)\]\([^)]*\)", lambda g: g.group(1) or "", m.group(1))
        slug = re.sub(r"[^\w\- ]", "", title.lower()).replace(" ", "-")
        n = seen.get(slug, 0)
        seen[slug] = n + 1
        anchors.add(slug if n == 0 else f"{slug}-{n}")
    return anchors


def strip_fences(text):
    """The text with each fenced code block's lines blanked (line numbers kept)."""
    out, fenced = [], False
    for line in text.splitlines():
        if re.match(r"\s*(```|~~~)", line):
            fenced = not fenced
            out.append("")
        else:
            out.append("" if fenced else line)
    return "\n".join(out)


class Tree:
    """The repository's files and folders, and how a named path resolves against them."""

    def __init__(self, files):
        self.files = set(files)
        self.folders = set()
        for f in files:
            parts = f.split("/")
            for i in range(1, len(parts)):
                self.folders.add("/".join(parts[:i]))
        self.top = {f.split("/")[0] for f in files if "/" in f}
        self.include_roots = sorted(d for d in self.folders if d.endswith("/include"))

    def exists(self, path):
        path = os.path.normpath(path).replace(os.sep, "/")
        return path in self.files or path in self.folders

    def resolves(self, word, doc_folder, tail_ok):
        """True when `word` names a file or folder from the root, an include folder, the
        document's folder, or (tail_ok) as the tail of a repository path."""
        path = word.rstrip("/")
        candidates = [path, os.path.join(doc_folder, path)] + [f"{r}/{path}" for r in self.include_roots]
        if any(self.exists(c) for c in candidates):
            return True
        if tail_ok:
            tail = "/" + path
            return any(f.endswith(tail) for f in self.files)
        return False


def candidate(word, tree):
    """The path a word of a code span or of the text names, or None; and whether it may match as
    the tail of a repository path."""
    word = word.lstrip("([{'\"").rstrip(")]}'\".,;:!?")
    if word.startswith("<") and word.endswith(">"):
        word = word[1:-1]  # an include: <granular/world.hpp>
    word = re.sub(r":\d+$", "", word)
    if "/" not in word or word == "/" or skipped(word):
        return None
    plain = word[2:] if word.startswith("./") else word
    if plain.split("/")[0] in tree.top:
        return plain, False
    ext = plain.rsplit(".", 1)[-1] if "." in plain.split("/")[-1] else ""
    if ext in EXTENSIONS and re.fullmatch(r"[\w.\-]+(/[\w.\-]+)+", plain):
        return plain, True
    return None


def check_document(doc, tree, anchors_of):
    """The missing paths of one document, as "doc:line: path" lines."""
    text = strip_fences(open(os.path.join(ROOT, doc), encoding="utf-8").read())
    folder = os.path.dirname(doc)
    missing = []
    for number, line in enumerate(text.splitlines(), 1):
        # Links and images: [text](target) and ![alt](target).
        for target in re.findall(r"\]\(([^)\s]+)(?:\s+\"[^\"]*\")?\)", line):
            if "://" in target or target.startswith("mailto:"):
                continue
            path, _, fragment = target.partition("#")
            resolved = os.path.normpath(os.path.join(folder, path)).replace(os.sep, "/") if path else doc
            if path and not tree.exists(resolved):
                missing.append(f"{doc}:{number}: link {target}")
            elif fragment and resolved.endswith(".md") and fragment not in anchors_of(resolved):
                missing.append(f"{doc}:{number}: link {target} (no such heading)")
        # Code spans, then the text around them (links' targets removed).
        spans = re.findall(r"(`+)(.+?)\1", line)
        prose = re.sub(r"(`+).+?\1", " ", re.sub(r"\]\([^)]*\)", "]", line))
        words = [w for _, span in spans for w in span.split()] + prose.split()
        for word in words:
            found = candidate(word, tree)
            if found is None:
                continue
            path, tail_ok = found
            in_prose = word in prose.split()
            if in_prose and not tail_ok and "." not in path.split("/")[-1]:
                continue  # in the text only file names count: "bench/RESULTS.md", not "text/JSON"
            if in_prose and tail_ok:
                continue
            if not tree.resolves(path, folder, tail_ok):
                missing.append(f"{doc}:{number}: {path}")
    return missing


def main():
    files = tracked_files()
    tree = Tree(files)
    documents = sorted(f for f in files if f.endswith(".md"))
    cache = {}

    def anchors_of(doc):
        if doc not in cache:
            cache[doc] = heading_anchors(open(os.path.join(ROOT, doc), encoding="utf-8").read())
        return cache[doc]

    missing = []
    for doc in documents:
        missing += check_document(doc, tree, anchors_of)
    for line in missing:
        print(f"docs_paths: missing: {line}")
    if missing:
        sys.exit(f"docs_paths: {len(missing)} path(s) named by the documents do not exist")
    print(f"docs_paths: every path named by the {len(documents)} documents exists")


if __name__ == "__main__":
    main()
