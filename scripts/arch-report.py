#!/usr/bin/env python3
"""Architecture report of the engine crates (issue 16's measured outcome): per crate, the
module import graph from `use crate::..`, `use super::..` and inline `crate::..` paths, its
import circles (strongly connected components of more than one module), the imports inside
them, the circles between top-level module trees (each subtree as one node), and the source
files over 1 200 lines.

  scripts/arch-report.py [CRATE_SRC_DIR ...]   (default: every engine crate)
  --max-circle N --max-lines N                 exit 1 when a crate exceeds them (for CI)
"""

import argparse
import os
import re
import sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..")
ENGINES = ["nodes/motion_core/src", "nodes/axis_node/single_axis/src",
           "nodes/axis_node/collision_avoidance/src",
           "nodes/axis_node/axis_groups/src", "nodes/axis_node/isg_platform/src",
           "nodes/axis_node/engine/src", "nodes/planar_node/engine/src",
           "nodes/pickplace_node/engine/src"]
LIMIT = 1200


def modules(src):
    """{module path (tuple): file} for the crate rooted at src (lib.rs)."""
    mods = {}
    for dirpath, _, files in os.walk(src):
        for f in files:
            if not f.endswith(".rs"):
                continue
            rel = os.path.relpath(os.path.join(dirpath, f), src)
            parts = rel[:-3].split(os.sep)
            if parts[-1] in ("lib", "main"):
                parts = parts[:-1]
            elif parts[-1] == "mod":
                parts = parts[:-1]
            mods[tuple(parts)] = os.path.join(dirpath, f)
    return mods


def strip_comments(text):
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def test_blocks_removed(text):
    """Drops `#[cfg(test)] mod x { ... }` bodies: tests may import anything."""
    out, i = [], 0
    for m in re.finditer(r"#\[cfg\(test\)\]\s*mod\s+\w+\s*\{", text):
        if m.start() < i:
            continue
        out.append(text[i:m.start()])
        depth, j = 1, m.end()
        while j < len(text) and depth:
            depth += {"{": 1, "}": -1}.get(text[j], 0)
            j += 1
        i = j
    out.append(text[i:])
    return "".join(out)


def expand_use(tree):
    """`a::{b, c::{d, e}}` -> ['a::b', 'a::c::d', 'a::c::e']."""
    tree = tree.strip()
    m = re.match(r"^(.*?)::\{(.*)\}$", tree, re.S)
    if not m:
        return [tree]
    prefix, inner = m.group(1), m.group(2)
    items, depth, cur = [], 0, ""
    for ch in inner:
        if ch == "," and depth == 0:
            items.append(cur)
            cur = ""
            continue
        depth += {"{": 1, "}": -1}.get(ch, 0)
        cur += ch
    items.append(cur)
    out = []
    for it in items:
        it = it.strip()
        if not it:
            continue
        for e in expand_use(it):
            out.append(prefix + "::" + e if e != "self" else prefix)
    return out


def resolve(path, here, mods):
    """The module a `crate::`/`super::`/`self::` path names (longest existing prefix)."""
    parts = [p for p in path.split("::") if p]
    if not parts:
        return None
    if parts[0] == "crate":
        base, rest = (), parts[1:]
    elif parts[0] in ("super", "self"):
        base = list(here)
        rest = parts
        while rest and rest[0] in ("super", "self"):
            if rest[0] == "super":
                base = base[:-1]
            rest = rest[1:]
        base = tuple(base)
    else:
        return None
    best = base if base in mods else None
    for k in range(1, len(rest) + 1):
        cand = base + tuple(rest[:k])
        if cand in mods:
            best = cand
    return best


def reexports(mods, texts):
    """{(module, name): module it comes from} for `pub use` items (e.g. lib.rs re-exports),
    so that `crate::Name` counts as an import of the module that defines Name."""
    out = {}
    for m, text in texts.items():
        for u in re.finditer(r"\bpub(?:\([^)]*\))?\s+use\s+([^;]*);", text, re.S):
            for p in expand_use(re.sub(r"\s+", "", u.group(1))):
                p = p.split("as")[0] if "::" not in p.split("as")[-1] else p
                segs = [x for x in p.split("::") if x]
                if not segs or segs[-1] == "*":
                    continue
                q = p if segs[0] in ("crate", "super", "self") else "self::" + p
                t = resolve(q, m, mods)
                if t is not None and t != m:
                    out[(m, segs[-1])] = t
    return out


def graph(src):
    mods = modules(src)
    texts = {}
    for m, f in mods.items():
        with open(f) as fh:
            texts[m] = test_blocks_removed(strip_comments(fh.read()))
    rex = reexports(mods, texts)
    edges = {m: set() for m in mods}
    for m, text in texts.items():
        paths = []
        for u in re.finditer(r"\buse\s+((?:crate|super|self)::[^;]*);", text, re.S):
            paths += expand_use(re.sub(r"\s+", "", u.group(1)))
        paths += re.findall(r"\b((?:crate|super)(?:::\w+)+)", text)
        for p in paths:
            p = p.split(" as ")[0]
            t = resolve(p, m, mods)
            if t is None:
                continue
            # A name re-exported by the module the path stops at: follow it to its source.
            last = p.split("::")[-1]
            while (t, last) in rex and rex[(t, last)] != m:
                t = rex[(t, last)]
            if t != m and t != ():
                edges[m].add(t)
    return mods, edges


def sccs(edges):
    index, low, on, stack, out, n = {}, {}, set(), [], [], [0]

    def visit(v):
        index[v] = low[v] = n[0]
        n[0] += 1
        stack.append(v)
        on.add(v)
        for w in edges.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            out.append(comp)

    sys.setrecursionlimit(10000)
    for v in edges:
        if v not in index:
            visit(v)
    return out


def name(m):
    return "::".join(m) or "crate"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("crates", nargs="*", default=ENGINES)
    ap.add_argument("--max-circle", type=int, default=None)
    ap.add_argument("--max-lines", type=int, default=None)
    args = ap.parse_args()
    bad = False
    for src in args.crates:
        src = os.path.join(ROOT, src) if not os.path.isabs(src) else src
        mods, edges = graph(src)
        circles = [c for c in sccs(edges) if len(c) > 1]
        in_circle = sum(1 for c in circles for v in c for w in edges[v] if w in c)
        long_files = []
        for m, f in mods.items():
            with open(f) as fh:
                k = sum(1 for _ in fh)
            if k > LIMIT:
                long_files.append((k, os.path.relpath(f, ROOT)))
        # The same graph with each top-level module's subtree as one node: a layer (for
        # example `objects` with its children) must not import a module that imports it back.
        top = {}
        for v, ws in edges.items():
            for w in ws:
                if v[:1] and w[:1] and v[:1] != w[:1]:
                    top.setdefault(v[:1], set()).add(w[:1])
        layer_circles = [c for c in sccs(top) if len(c) > 1]
        biggest = max((len(c) for c in circles), default=0)
        print(f"{os.path.relpath(src, ROOT)}: {len(mods)} modules, {len(circles)} import circle(s), "
              f"largest {biggest} modules, {in_circle} imports inside circles, "
              f"{len(long_files)} file(s) over {LIMIT} lines, "
              f"{len(layer_circles)} circle(s) between top-level module trees")
        for c in layer_circles:
            print("  layer circle: " + ", ".join(sorted(name(v) for v in c)))
        for c in sorted(circles, key=len, reverse=True):
            print("  circle: " + ", ".join(sorted(name(v) for v in c)))
        for k, f in sorted(long_files, reverse=True):
            print(f"  {k:5d} lines  {f}")
        if args.max_circle is not None and biggest > args.max_circle:
            bad = True
        if args.max_circle is not None and layer_circles:
            bad = True
        if args.max_lines is not None and long_files and max(long_files)[0] > args.max_lines:
            bad = True
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
