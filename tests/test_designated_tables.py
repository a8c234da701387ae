#!/usr/bin/env python3
"""Every descriptor table is written with designated initializers
(docs/STYLE.md, convention 15): in a table of one of the descriptor types
below, every element that is a struct opens with `.field =` or `[index] =`,
so that which number is a range, a default or a flag is on the line.

Scans the library and program folders for definitions of those types
(`static const T name[] = {...}`, `const T name = {...}`) and, for tables
generated from an X-macro list (`= {POM_..._LIST(ENTRY)}`), the expansion
macro's body. Fails naming file, line and table. `--selftest` first checks
that a positional table is caught and a designated one passes. An optional
last argument names another source tree to scan."""
import os
import re
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
if len(sys.argv) > 1 and not sys.argv[-1].startswith("-"):
    ROOT = sys.argv[-1]  # another source tree
# The library folders as docs/layers.txt declares them (one place), plus cli.
def _folders():
    out = []
    with open(os.path.join(ROOT, "docs", "layers.txt")) as f:
        for line in f:
            line = line.split("#")[0].strip()
            if line and not line.startswith("any:"):
                out.append(line.split()[0])
    return out


FOLDERS = _folders()

# The descriptor types: what a table row describes (keys, ranges, defaults,
# flags, offsets, callbacks).
TYPES = [
    "pom_kin_param_desc", "pom_kin_points_desc", "pom_kin_inertia_body_desc",
    "pom_kin_value_desc", "pom_kin_limit_desc", "pom_kin_arch_type", "pom_act_desc",
    "pom_dyn_gain_desc", "pom_dyn_ctrl_option_desc", "pom_dyn_ctrl_state_desc",
    "pom_dyn_ctrl_type", "pom_dyn_ctrl_engine", "dyn_formulation", "pom_dyn_param_info",
    "pom_dyn_metric_info", "unit_info", "tabular_column", "pom_fidelity_setting",
    "pom_dist_ops", "kind_keys", "command",
]

DEF = re.compile(r"\b(?:%s)\s+(?:const\s+)?(\w+)\s*(\[[^\]]*\])?\s*=\s*\{" % "|".join(TYPES))
# Macros that expand to (part of) a descriptor table: an array of limit kinds.
ARRAY_MACROS = ["POM_KIN_SEGMENT_LIMIT_KINDS"]


def skip_literal(s, i):
    """Index after the string/char literal or comment starting at i (else i)."""
    if s[i] in "\"'":
        q, j = s[i], i + 1
        while s[j] != q:
            j += 2 if s[j] == "\\" else 1
        return j + 1
    if s.startswith("/*", i):
        return s.index("*/", i) + 2
    if s.startswith("//", i):
        return s.index("\n", i)
    return i


def matching_brace(s, i):
    depth = 0
    while True:
        j = skip_literal(s, i)
        if j != i:
            i = j
            continue
        if s[i] == "{":
            depth += 1
        elif s[i] == "}":
            depth -= 1
            if depth == 0:
                return i
        i += 1


def positional(body):
    """Offsets in body (the inside of a table's braces, macro line
    continuations removed) of element braces that do not open with a
    designator. An element brace follows '{' or ',' (a brace after '=' is a
    member's value, e.g. an array of names, and may be positional)."""
    bad, prev, i = [], "{", 0
    while i < len(body):
        j = skip_literal(body, i)
        if j != i:
            prev, i = "x", j
            continue
        c = body[i]
        if c == "{" and prev in "{,":
            k = i + 1
            while k < len(body):
                k2 = skip_literal(body, k) if body[k] == "/" else k
                if k2 != k:
                    k = k2
                    continue
                if not body[k].isspace():
                    break
                k += 1
            if body[k] not in ".[}":
                bad.append(i)
        if not c.isspace():
            prev = c
        i += 1
    return bad


def check_text(path, text):
    errors = []
    flat = text.replace("\\\n", "  ")  # same offsets, macro bodies joined
    for m in DEF.finditer(flat):
        ob = m.end() - 1
        cb = matching_brace(flat, ob)
        body = flat[ob + 1:cb]
        # an array's elements are structs; a single struct's body is one
        prefix = "" if m.group(2) else "{"
        for off in positional(prefix + body)[0:1]:
            line = flat.count("\n", 0, ob + 1 + off - len(prefix)) + 1
            errors.append("%s:%d: table '%s': positional initializer (write .field = value)"
                          % (path, line, m.group(1)))
        # a table generated from an X-macro list: check the expansion macros
        lm = re.fullmatch(r"\s*\w+_LIST\(([\w\s,]*)\)\s*", body)
        if lm:
            for name in [n.strip() for n in lm.group(1).split(",") if n.strip()]:
                dm = re.search(r"#define\s+%s\(([^)]*)\)\s*\{" % re.escape(name), flat)
                if not dm:
                    errors.append("%s: table '%s': expansion macro %s not found in the file"
                                  % (path, m.group(1), name))
                    continue
                mob = dm.end() - 1
                mbody = flat[mob:matching_brace(flat, mob) + 1]
                if positional(mbody):
                    line = flat.count("\n", 0, mob) + 1
                    errors.append("%s:%d: macro %s (table '%s'): positional initializer"
                                  % (path, line, name, m.group(1)))
    for name in ARRAY_MACROS:
        dm = re.search(r"#define\s+%s\s*\{" % name, flat)
        if dm:
            mob = dm.end() - 1
            for off in positional(flat[mob + 1:matching_brace(flat, mob)])[0:1]:
                line = flat.count("\n", 0, mob + 1 + off) + 1
                errors.append("%s:%d: macro %s: positional initializer" % (path, line, name))
    return errors


def selftest():
    bad = ('static const pom_dyn_gain_desc g[] = {\n    {"kp", "K_P", 0.0, 1e12},\n};\n'
           '#define ENTRY(a, b) {a, b},\n'
           'static const pom_dyn_param_info schema[2] = {POM_DYN_PARAMS_LIST(ENTRY)};\n'
           'const pom_kin_arch_type t = {.limits = {{0}, {"x", 1}}};\n'
           'static const pom_dist_ops u = {"uniform", q_uniform};\n'
           '#define POM_KIN_SEGMENT_LIMIT_KINDS {{0}, {"x", 1}}\n')
    good = ('static const pom_dyn_gain_desc g[] = {\n    {.key = "kp", /* c */ .lo = 0.0},\n};\n'
            'static const kind_keys k[] = {{.key = {"min", "max"}, .optional = {0, 1}}};\n'
            '#define ENTRY(a, b) {.x = a, .y = b},\n'
            'static const pom_dyn_param_info schema[2] = {POM_DYN_PARAMS_LIST(ENTRY)};\n'
            'const pom_kin_arch_type t = {.limits = {[1] = {.name = "x"}}};\n'
            'static const pom_dist_ops u = {.name = "uniform", .quantile = q_uniform};\n'
            '#define POM_KIN_SEGMENT_LIMIT_KINDS {[1] = {.name = "x", .lower = 1}}\n')
    eb, eg = check_text("<bad>", bad), check_text("<good>", good)
    if len(eb) != 5 or eg:
        print("selftest failed:\n  bad: %s\n  good: %s" % (eb, eg))
        return 1
    return 0


def main():
    if "--selftest" in sys.argv and selftest():
        return 1
    errors, tables = [], 0
    for folder in FOLDERS:
        top = os.path.join(ROOT, folder)
        for dirpath, _, files in os.walk(top):
            for f in sorted(files):
                if not f.endswith((".c", ".h")):
                    continue
                path = os.path.join(dirpath, f)
                text = open(path, encoding="utf-8").read()
                tables += len(DEF.findall(text.replace("\\\n", "  ")))
                errors += check_text(os.path.relpath(path, ROOT), text)
    for e in errors:
        print(e)
    if tables < 20:
        print("only %d descriptor tables found: the scan is broken" % tables)
        return 1
    print("%d descriptor tables, %d positional" % (tables, len(errors)))
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
