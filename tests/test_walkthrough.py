"""test_walkthrough.py - docs/extending.md section 15 does what it says.

The walk-through between `<!-- walkthrough: begin -->` and
`<!-- walkthrough: end -->` is run as a reader would run it:

- a fenced block preceded by `<!-- file: NAME -->` is written to NAME in a
  fresh folder (the reader's own files);
- every ```console block is a list of commands (`$ CMD`), each followed by
  the output the doc shows. Each command runs in that folder with bash, after
  the `export` commands that came before it, `pomlab` being the built
  program; `configs/` and `catalog/` of the source tree are linked into the
  folder, as they are at hand in a source tree.

The output shown must be the output printed, line for line; a line `...`
stands for any number of lines (a part the doc leaves out: wall times, long
tables). A command that fails, or prints other lines, fails the test,
naming the doc line. So the example file, its config and every figure the
walk-through shows stay true.

Usage: test_walkthrough.py SOURCE_DIR PROGRAM
"""

import os
import re
import subprocess
import sys
import tempfile

DOC = "docs/extending.md"


def blocks(text):
    """The walk-through's file blocks and console blocks, in order, each with
    the doc line where it starts."""
    lines = text.split("\n")
    try:
        begin = next(i for i, l in enumerate(lines) if "<!-- walkthrough: begin -->" in l)
        end = next(i for i, l in enumerate(lines) if "<!-- walkthrough: end -->" in l)
    except StopIteration:
        raise SystemExit("%s: no walkthrough markers" % DOC)
    out, i, pending_file = [], begin, None
    while i < end:
        m = re.match(r"<!-- file: (\S+) -->", lines[i].strip())
        if m:
            pending_file = m.group(1)
        elif lines[i].startswith("```"):
            kind = lines[i][3:].strip()
            j = i + 1
            while not lines[j].startswith("```"):
                j += 1
            body = lines[i + 1:j]
            if pending_file:
                out.append(("file", pending_file, body, i + 2))
                pending_file = None
            elif kind == "console":
                out.append(("console", None, body, i + 2))
            i = j
        i += 1
    return out


def matches(expected, actual):
    """expected (with `...` lines) against actual, line for line."""
    if not expected:
        return not actual
    if expected[0] == "...":
        rest = expected[1:]
        return any(matches(rest, actual[k:]) for k in range(len(actual) + 1))
    return bool(actual) and expected[0] == actual[0] and matches(expected[1:], actual[1:])


def main():
    if len(sys.argv) != 3:
        raise SystemExit(__doc__)
    src, program = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    with open(os.path.join(src, DOC), encoding="utf-8") as f:
        items = blocks(f.read())
    n_files = sum(1 for b in items if b[0] == "file")
    n_cmds = 0
    failures = []
    with tempfile.TemporaryDirectory() as tmp:
        for d in ("configs", "catalog"):
            os.symlink(os.path.join(src, d), os.path.join(tmp, d))
        env = dict(os.environ)
        env["PATH"] = os.path.dirname(program) + ":/usr/bin:/bin"
        env.pop("POMLAB_ARCHITECTURES", None)
        exports = []
        for kind, name, body, line in items:
            if kind == "file":
                with open(os.path.join(tmp, name), "w", encoding="utf-8") as f:
                    f.write("\n".join(body) + "\n")
                continue
            k = 0
            while k < len(body):
                if not body[k].startswith("$ "):
                    failures.append("%s:%d: output without a command" % (DOC, line + k))
                    break
                cmd, cmd_line = body[k][2:], line + k
                k += 1
                expected = []
                while k < len(body) and not body[k].startswith("$ "):
                    expected.append(body[k])
                    k += 1
                n_cmds += 1
                if cmd.startswith("export "):
                    exports.append(cmd)
                script = "\n".join(exports + ["set -o pipefail", cmd])
                p = subprocess.run(["bash", "-c", script], cwd=tmp, env=env,
                                   capture_output=True, text=True, timeout=600)
                actual = p.stdout.rstrip("\n").split("\n") if p.stdout.strip() else []
                if p.returncode != 0:
                    failures.append("%s:%d: `%s` exits %d: %s" %
                                    (DOC, cmd_line, cmd, p.returncode, p.stderr.strip()[-800:]))
                elif not matches(expected, actual):
                    failures.append("%s:%d: `%s` prints\n%s\nnot as the doc shows\n%s" %
                                    (DOC, cmd_line, cmd, "\n".join(actual),
                                     "\n".join(expected)))
    if n_files == 0 or n_cmds == 0:
        failures.append("%s: the walk-through has %d files and %d commands" %
                        (DOC, n_files, n_cmds))
    for f in failures:
        print(f)
    print("walk-through: %d files, %d commands, %d failures" % (n_files, n_cmds, len(failures)))
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
