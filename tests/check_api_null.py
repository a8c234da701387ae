#!/usr/bin/env python3
"""check_api_null.py - every public function of api/pom_api.h, and every
pom_cfg_* call of docs/api.md section 3's Configuration table (the config
calls the layer exposes), is called by tests/test_api_null.c, so that a new
function cannot escape the NULL rule of docs/api.md section 2.

Usage: check_api_null.py SOURCE_DIR. Exit 1 naming what is missing."""

import re
import sys


def header_functions(text):
    """Names of the function prototypes of a header (comments dropped)."""
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    text = re.sub(r"^\s*#.*$", " ", text, flags=re.M)
    names = set()
    for stmt in text.split(";"):
        stmt = " ".join(stmt.split())
        if stmt.startswith("typedef") or "{" in stmt or "}" in stmt:
            continue
        m = re.search(r"\b(pom_\w+)\s*\(", stmt)
        if m:
            names.add(m.group(1))
    return names


def config_table_functions(text):
    """pom_cfg_* names in the table under '### Configuration'."""
    sect = text.split("### Configuration", 1)[1].split("###", 1)[0]
    return set(re.findall(r"`(pom_cfg_\w+)\(", sect))


def main():
    src = sys.argv[1]
    with open(src + "/api/pom_api.h") as f:
        names = header_functions(f.read())
    with open(src + "/docs/api.md") as f:
        cfg_names = config_table_functions(f.read())
    with open(src + "/tests/test_api_null.c") as f:
        test = f.read()
    if len(names) < 25 or len(cfg_names) < 5:
        print("check_api_null: found only %d functions in pom_api.h and %d config calls in "
              "docs/api.md: the parser is broken" % (len(names), len(cfg_names)))
        return 1
    missing = sorted(n for n in names | cfg_names if not re.search(r"\b%s\(" % n, test))
    if missing:
        print("check_api_null: tests/test_api_null.c does not call %s (docs/api.md section 2: "
              "every public function is called with NULL in each pointer argument)"
              % ", ".join(missing))
        return 1
    print("check_api_null: %d functions of pom_api.h and %d config calls covered"
          % (len(names), len(cfg_names)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
