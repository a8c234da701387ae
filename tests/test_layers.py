#!/usr/bin/env python3
"""The library folders stand in the order of docs/layers.txt.

Usage: test_layers.py SOURCE_DIR BUILD_DIR [LAYERS_FILE]

Two checks, both against the declared order (docs/layers.txt):
1. Includes: every #include "x.h" of a .c/.h in a library folder names a
   header of the same folder or of a folder on a lower line; a folder that
   declares its public header is included through that header only.
2. Calls: from the object files of the build (nm: defined against undefined
   global symbols), every use of a function or data of another file goes to
   the same folder or to a lower one, and inside a folder the files call each
   other's functions without a circle (the file graph is acyclic; a
   registry's table that points at its entries' descriptors registers them
   and is not a call).
Any violation is printed (file, what it uses, where that lives) and the exit
status is 1.
"""
import collections
import os
import re
import subprocess
import sys

sys.setrecursionlimit(10000)

C_EXT = (".c", ".h")


def read_layers(path):
    level, public, free = {}, {}, set()
    n = 0
    with open(path, encoding="utf-8") as f:
        for raw in f:
            line = raw.split("#", 1)[0].strip()
            if not line:
                continue
            if line.startswith("any:"):
                free.update(line[4:].split())
                continue
            words = line.split()
            folder = words[0]
            level[folder] = n
            if len(words) > 1:
                public[folder] = words[1]
            n += 1
    return level, public, free


def source_folders(src):
    """Top-level folders holding C sources, and each one's .c/.h files."""
    out = {}
    for top in sorted(os.listdir(src)):
        path = os.path.join(src, top)
        if not os.path.isdir(path) or top.startswith(".") or top.startswith("build"):
            continue
        files = []
        for root, dirs, names in os.walk(path):
            dirs[:] = [d for d in dirs if not d.startswith(".")]
            files += [os.path.join(root, n) for n in names if n.endswith(C_EXT)]
        if files:
            out[top] = sorted(files)
    return out


def check_includes(src, folders, level, public, layers_name, errors):
    owner = collections.defaultdict(set)  # header basename -> folders
    for top, files in folders.items():
        for f in files:
            if f.endswith(".h"):
                owner[os.path.basename(f)].add(top)
    inc = re.compile(r'^\s*#\s*include\s+"([^"]+)"')
    for top, files in folders.items():
        if top not in level:
            continue
        for f in files:
            rel = os.path.relpath(f, src)
            with open(f, encoding="utf-8", errors="replace") as fh:
                for no, line in enumerate(fh, 1):
                    m = inc.match(line)
                    if not m:
                        continue
                    name = os.path.basename(m.group(1))
                    homes = owner.get(name, set())
                    if top in homes or not homes:
                        continue  # its own header, or generated / system
                    if len(homes) > 1:
                        errors.append(f"{rel}:{no}: header {name} is in several folders: "
                                      f"{', '.join(sorted(homes))}")
                        continue
                    home = next(iter(homes))
                    if home not in level:
                        continue  # a consumer folder's header: reported as undeclared
                    if level[home] >= level[top]:
                        how = "a peer" if level[home] == level[top] else "a higher layer"
                        errors.append(f"{rel}:{no}: includes {name} of {home}/, {how} "
                                      f"({layers_name}: {top} may use only the folders above "
                                      f"its line)")
                    elif home in public and name != public[home]:
                        errors.append(f"{rel}:{no}: includes {name}, a private header of "
                                      f"{home}/ (its public header is {public[home]})")


def objects(build, folders, level, errors):
    """{folder: {target: [object files]}} for every declared folder."""
    out = {}
    for top in folders:
        if top not in level:
            continue
        base = os.path.join(build, top, "CMakeFiles")
        targets = {}
        if os.path.isdir(base):
            for d in sorted(os.listdir(base)):
                if not d.endswith(".dir"):
                    continue
                objs = []
                for root, _, names in os.walk(os.path.join(base, d)):
                    objs += [os.path.join(root, n) for n in names if n.endswith(".o")]
                if objs:
                    targets[d[:-4]] = sorted(objs)
        if not targets and any(f.endswith(".c") for f in folders[top]):
            errors.append(f"{top}/: no object files under {base} (build first)")
        out[top] = targets
    return out


def symbols(obj):
    text = subprocess.run(["nm", obj], check=True, capture_output=True, text=True).stdout
    defined, undefined = {}, set()
    for line in text.splitlines():
        parts = line.split()
        if len(parts) == 3 and parts[1] in "TWDBRV":
            defined[parts[2]] = parts[1] in "TW"  # 1: a function
        elif len(parts) == 2 and parts[0] == "U":
            undefined.add(parts[1])
    return defined, undefined


def src_name(obj):
    return os.path.basename(obj)[: -len(".o")]


def circles(graph):
    """The groups of nodes that reach each other (strongly connected
    components of more than one node) of graph {node: set(nodes)}."""
    index, low, on, stack, out = {}, {}, set(), [], []
    counter = [0]

    def visit(n):
        index[n] = low[n] = counter[0]
        counter[0] += 1
        stack.append(n)
        on.add(n)
        for m in sorted(graph.get(n, ())):
            if m not in index:
                visit(m)
                low[n] = min(low[n], low[m])
            elif m in on:
                low[n] = min(low[n], index[m])
        if low[n] == index[n]:
            group = []
            while True:
                m = stack.pop()
                on.discard(m)
                group.append(m)
                if m == n:
                    break
            if len(group) > 1:
                out.append(sorted(group))

    for n in sorted(graph):
        if n not in index:
            visit(n)
    return out


def check_calls(objs, level, errors):
    info = {}  # (folder, target, file) -> (defined, undefined)
    owners = collections.defaultdict(list)
    for top, targets in objs.items():
        for target, files in targets.items():
            for o in files:
                key = (top, target, src_name(o))
                info[key] = symbols(o)
                for s in info[key][0]:
                    owners[s].append(key)
    graphs = collections.defaultdict(lambda: collections.defaultdict(set))
    for key, (_, undefined) in info.items():
        top, target, name = key
        for s in sorted(undefined):
            homes = owners.get(s)
            if not homes:
                continue  # a system or third-party library
            same = [h for h in homes if h[0] == top and h[1] == target]
            if not same:
                same = [h for h in homes if h[0] == top]
            if same:
                to = same[0]
                # the circle check follows calls: a registry's table that
                # lists its entries' descriptors (data) registers them, it
                # does not call them
                if info[to][0][s]:
                    graphs[top][f"{target}:{name}"].add(f"{to[1]}:{to[2]}")
                continue
            for h in homes[:1]:
                if level[h[0]] >= level[top]:
                    how = "a peer" if level[h[0]] == level[top] else "a higher layer"
                    verb = "calls" if info[h][0][s] else "uses"
                    errors.append(f"{top}/{name} {verb} {s} of {h[0]}/{h[2]}, {how}")
    for top, graph in sorted(graphs.items()):
        for node in graph:
            graph[node].discard(node)
        for group in circles(graph):
            errors.append(f"{top}/: {len(group)} files call each other in a circle: "
                          + ", ".join(group))
    return sum(len(g) for g in graphs.values())


def main():
    if len(sys.argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    src, build = sys.argv[1], sys.argv[2]
    layers = sys.argv[3] if len(sys.argv) > 3 else os.path.join(src, "docs", "layers.txt")
    if not os.path.isfile(layers):
        print(f"test_layers: no declared order: {layers} is missing")
        return 1
    level, public, free = read_layers(layers)
    folders = source_folders(src)
    errors = []
    for top in folders:
        if top not in level and top not in free:
            errors.append(f"{top}/ holds C sources but is not in {layers}")
    check_includes(src, folders, level, public, os.path.basename(layers), errors)
    objs = objects(build, folders, level, errors)
    n_files = check_calls(objs, level, errors)
    for e in errors:
        print("test_layers: " + e)
    if errors:
        print(f"test_layers: {len(errors)} violation(s) of {layers}")
        return 1
    order = " < ".join(f for f, _ in sorted(level.items(), key=lambda x: x[1]) if f in folders)
    print(f"test_layers: ok: {order}; {n_files} calling files, no upward call, no circle")
    return 0


if __name__ == "__main__":
    sys.exit(main())
