#!/usr/bin/env python3
"""Writes fuzz seeds for `fuzz_obj_parse` from the real-world corpus (tests/data/corpus/).

The target's input is an OBJ text, then a NUL byte and the MTL text every `mtllib` resolves
to, at most 4096 bytes. A corpus OBJ that fits is taken whole with its MTL; a larger one is
cut to its statements up to the budget: every non-vertex statement in order, and the faces
met first, with only the vertices they use (renumbered, so the excerpt stays valid OBJ).

    python3 scripts/corpus_fuzz_seeds.py      # writes fuzz/seeds/fuzz_obj_parse/corpus_*.objmtl
"""
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CORPUS = os.path.join(ROOT, "tests", "data", "corpus", "obj")
OUT = os.path.join(ROOT, "fuzz", "seeds", "fuzz_obj_parse")
BUDGET = 4096


def mtl_of(obj_path, text):
    """The text of the first library an `mtllib` line names (whole line first), or None."""
    for line in text.splitlines():
        parts = line.split(None, 1)
        if parts and parts[0] == "mtllib" and len(parts) > 1:
            for name in [parts[1].strip()] + parts[1].split():
                p = os.path.join(os.path.dirname(obj_path), name)
                if os.path.isfile(p):
                    return open(p, "rb").read()
    return None


def excerpt(text, room):
    """The first faces of `text` (and every other statement before the budget runs out),
    with the vertices they use renumbered from 1."""
    vertices = []  # every `v` line, in order
    out_head, faces = [], []
    for line in text.splitlines():
        parts = line.split()
        if not parts:
            continue
        if parts[0] == "v":
            vertices.append(line.strip())
        elif parts[0] in ("vt", "vn"):
            continue
        elif parts[0] == "f":
            idx = []
            for item in parts[1:]:
                i = int(item.split("/")[0])
                idx.append(i - 1 if i > 0 else len(vertices) + i)
            faces.append(("f", idx))
        else:
            faces.append(("s", line.strip()))
    used, body = {}, []
    size = 0
    for kind, item in faces:
        if kind == "s":
            line = item
        else:
            new = [i for i in item if i not in used]
            cost = sum(len(vertices[i]) + 1 for i in new)
            line = None
            if size + cost + 4 * len(item) + 4 > room:
                break
            for i in new:
                used[i] = len(used) + 1
                size += len(vertices[i]) + 1
            line = ("f", item)
        if isinstance(line, str):
            if size + len(line) + 1 > room:
                break
            size += len(line) + 1
        else:
            size += sum(len(str(used[i])) + 1 for i in item) + 2
        body.append(line)
    order = sorted(used, key=used.get)
    lines = [vertices[i] for i in order]
    for item in body:
        if isinstance(item, str):
            lines.append(item)
        else:
            lines.append("f " + " ".join(str(used[i]) for i in item[1]))
    return ("\n".join(lines) + "\n").encode()


def main():
    os.makedirs(OUT, exist_ok=True)
    written = 0
    for folder, _, files in sorted(os.walk(CORPUS)):
        for name in sorted(files):
            if not name.endswith(".obj"):
                continue
            path = os.path.join(folder, name)
            raw = open(path, "rb").read()
            text = raw.decode("utf-8", "replace")
            mtl = mtl_of(path, text)
            tail = b"" if mtl is None else b"\0" + mtl
            obj = raw if len(raw) + len(tail) <= BUDGET else excerpt(text, BUDGET - len(tail))
            seed = obj + tail
            assert len(seed) <= BUDGET, (path, len(seed))
            key = re.sub(r"[^A-Za-z0-9]+", "_", os.path.relpath(path, CORPUS)[:-4])
            with open(os.path.join(OUT, f"corpus_{key}.objmtl"), "wb") as f:
                f.write(seed)
            written += 1
    print(f"{written} seeds in {os.path.relpath(OUT, ROOT)}", file=sys.stderr)


if __name__ == "__main__":
    main()
