"""test_reference_tables.py - results/reference/ reproduced from the tables
(issue 27 item 3): every reference study of tests/test_docs.py is run with
the shipped architectures taken from their architecture files
(catalog/3pss.arch, 3sps.arch, 3rrr.arch: architecture = "3PSS-table", ...)
instead of the hand-coded types, and its summary.md (and controllers.md)
must equal the shipped one line by line, the lines that carry dates, paths
or wall times aside (test_docs.stable): the printed digits agree.

The configs are a copy of configs/ whose 3pss.cfg, 3sps.cfg and 3rrr.cfg
differ from the shipped ones in their `architecture` line only; the studies
run in a temporary folder holding that copy as configs/, so the summaries
name the same config paths.

Usage: test_reference_tables.py SOURCE_DIR PROGRAM [--long] [--only NAME]...
Without --long the short references only (paper-exact, architectures);
--long adds the long ones and needs POMLAB_DOCS_LONG=1 (else exit 77, a
skip). Exit 0 when every reference agrees, 1 otherwise (the first differing
line of each named)."""

import os
import re
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import test_docs  # noqa: E402  (REFERENCES, stable)

TABLES = {"3pss.cfg": "3PSS", "3sps.cfg": "3SPS", "3rrr.cfg": "3RRR"}


def table_configs(src, dest):
    """configs/ copied to dest/configs with the three shipped architectures
    switched to their tables; each switch is checked to happen once."""
    shutil.copytree(os.path.join(src, "configs"), os.path.join(dest, "configs"))
    for name, arch in TABLES.items():
        path = os.path.join(dest, "configs", name)
        with open(path, encoding="utf-8") as f:
            text = f.read()
        line = re.compile(r'^architecture = "%s";$' % arch, re.M)
        new, n = line.subn('architecture = "%s-table";' % arch, text)
        if n != 1:
            raise RuntimeError("configs/%s: %d lines `architecture = \"%s\";`, want 1"
                               % (name, n, arch))
        with open(path, "w", encoding="utf-8") as f:
            f.write(new)


def main(argv):
    if len(argv) < 3:
        print(__doc__, file=sys.stderr)
        return 2
    src, program = os.path.abspath(argv[1]), os.path.abspath(argv[2])
    long_runs = "--long" in argv
    only = [argv[i + 1] for i, a in enumerate(argv) if a == "--only" and i + 1 < len(argv)]
    if long_runs and os.environ.get("POMLAB_DOCS_LONG") != "1":
        print("skipped: the long references run with POMLAB_DOCS_LONG=1")
        return 77
    env = dict(os.environ)
    env["PATH"] = "/usr/bin:/bin"
    env["POMLAB_CATALOG"] = os.path.join(src, "catalog")
    failures, checked = [], 0
    with tempfile.TemporaryDirectory() as tmp:
        table_configs(src, tmp)
        for name, cfg, is_long in test_docs.REFERENCES:
            if (only and name not in only) or (is_long and not long_runs):
                continue
            refdir = os.path.join(src, "results", "reference", name)
            out = os.path.join(tmp, "ref-" + name + ".h5")
            files = ["summary.md"]
            cmds = [[program, "study", cfg, "--out", out, "--quiet", "--no-plots"]]
            if os.path.exists(os.path.join(refdir, "controllers.md")):
                cmds.append(["/usr/bin/python3", os.path.join(src, "scripts",
                                                              "arch_controller_report.py"), out])
                files.append("controllers.md")
            try:
                for c in cmds:
                    p = subprocess.run(c, cwd=tmp, env=env, capture_output=True, text=True,
                                       timeout=7200)
                    if p.returncode != 0:
                        raise RuntimeError("`%s` exited %d: %s" % (" ".join(c), p.returncode,
                                                                   p.stderr.strip()[-800:]))
            except (OSError, RuntimeError, subprocess.TimeoutExpired) as e:
                failures.append("results/reference/%s: %s" % (name, e))
                continue
            for fname in files:
                with open(os.path.join(refdir, fname), encoding="utf-8") as f:
                    want = test_docs.stable(f.read())
                with open(os.path.join(out[:-3], fname), encoding="utf-8") as f:
                    got = test_docs.stable(f.read().replace(out[:-3] + "/", "results/%s/" % name))
                for w, g in zip(want, got):
                    if w != g:
                        failures.append("results/reference/%s/%s: from the tables\n    %s\n  as\n"
                                        "    %s" % (name, fname, w, g))
                        break
                else:
                    if len(want) != len(got):
                        failures.append("results/reference/%s/%s: %d lines, from the tables %d"
                                        % (name, fname, len(want), len(got)))
                    else:
                        print("results/reference/%s/%s: %d lines, equal from the tables"
                              % (name, fname, len(want)))
            checked += 1
    for f in failures:
        print("FAIL " + f)
    print("%d reference(s) run from the tables, %d failure(s)" % (checked, len(failures)))
    return 1 if failures or checked == 0 else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
