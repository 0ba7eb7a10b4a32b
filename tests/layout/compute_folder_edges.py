#!/usr/bin/env python3
"""Lists the folder -> folder include edges of compute/src and fails if they form a cycle.

Usage: python3 tests/layout/compute_folder_edges.py [compute]   (ctest: compute_folder_edges)
A public header trailscope/<area>/<name>.hpp belongs to the folder holding <name>.cpp under
compute/src/<area> (so trailscope/bundling/render.hpp belongs to bundling/render), or to <area> when
there is none; trailscope/ocl_info.hpp belongs to ocl. A detail/ subfolder counts as part of its parent
(the op's private stages). Exit status 1 when there is a cycle."""
import os, re, sys
root = sys.argv[1] if len(sys.argv) > 1 else "compute"
src, inc = os.path.join(root, "src"), os.path.join(root, "include", "trailscope")
inc_re = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
cpp_dirs = {}  # stem -> set of folders (relative to src) that hold stem.cpp
for d, _, fs in os.walk(src):
    for f in fs:
        if f.endswith(".cpp"):
            cpp_dirs.setdefault((os.path.relpath(d, src).split(os.sep)[0], f[:-4]), set()).add(os.path.relpath(d, src))
def public_folder(rel):  # rel like "bundling/render.hpp" or "ocl_info.hpp"
    parts = rel.split("/")
    if len(parts) == 1:
        stem = parts[0][:-4]
        return "ocl" if stem == "ocl_info" else "."
    top, stem = parts[0], parts[-1][:-4]
    dirs = cpp_dirs.get((top, stem))
    return sorted(dirs)[0] if dirs and len(dirs) == 1 else top
def folder_of_include(path, here):
    if path.startswith("trailscope/"):
        return public_folder(path[len("trailscope/"):])
    if "/" not in path:
        return here  # same folder
    # private "a/b/c.hpp" relative to compute/src
    return os.path.dirname(path)
edges = {}
def unit(folder):  # a detail/ subfolder is its parent's private part, not a folder of its own
    return folder[: -len("/detail")] if folder.endswith("/detail") else folder
def scan(fn, here):
    here = unit(here)
    for line in open(fn, encoding="utf-8", errors="replace"):
        m = inc_re.match(line)
        if not m or m.group(1).startswith("../") or m.group(1).endswith(".pb.h"): continue
        to = unit(folder_of_include(m.group(1), here))
        if to != here and to != ".":
            edges.setdefault(here, set()).add(to)
for d, _, fs in os.walk(src):
    for f in fs:
        if f.endswith((".cpp", ".hpp")):
            scan(os.path.join(d, f), os.path.relpath(d, src))
for d, _, fs in os.walk(inc):
    for f in fs:
        if f.endswith(".hpp"):
            rel = os.path.relpath(os.path.join(d, f), inc)
            scan(os.path.join(d, f), public_folder(rel))
for a in sorted(edges):
    print(f"{a if a != '.' else '(top level)':22s} -> {', '.join(sorted(edges[a]))}")
# cycle check (DFS)
state, stack, cycles = {}, [], []
def dfs(u):
    state[u] = 1; stack.append(u)
    for v in sorted(edges.get(u, ())):
        if state.get(v) == 1: cycles.append(stack[stack.index(v):] + [v])
        elif not state.get(v): dfs(v)
    stack.pop(); state[u] = 2
for u in sorted(edges):
    if not state.get(u): dfs(u)
print("cycles:", "none" if not cycles else "; ".join(" -> ".join(c) for c in cycles))
sys.exit(1 if cycles else 0)
