"""test_job.py - one study, one job, for every caller (issue 31 items 1-3):

- tests/job_study_fidelity.cfg (study.fidelity = "auto") through the program
  (`pomlab study --json`), the flat C layer (test_job_api STUDY OUT JSON)
  and the Python module (pomlab.study): the results files equal field by
  field (wall times aside), the same JSON report, the same fidelity each
  candidate earned, the same tables and summary.md;
- pomlab.montecarlo(output=<its own config>) and a tabular file over the
  results refused with the path named, nothing overwritten;
- SIGINT during pomlab.montecarlo (once its runs began): KeyboardInterrupt
  within a second, the finished maneuvers in OUTPUT.partial, resume=True
  finishes them.

Run by ctest (tests/api.cmake) with POMLAB_LIBRARY, PYTHONPATH,
POMLAB_PROGRAM (pomlab-full) and POMLAB_TEST_JOB_API set.
"""

import csv
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import time

import h5py
import numpy as np
import pytest

import pomlab

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROGRAM = os.environ.get("POMLAB_PROGRAM", os.path.join(SRC, "build", "cli", "pomlab-full"))
C_LAYER = os.environ.get("POMLAB_TEST_JOB_API", os.path.join(SRC, "build", "tests", "test_job_api"))
STUDY = os.path.join(SRC, "tests", "job_study_fidelity.cfg")
CFG_3PSS = os.path.join(SRC, "configs", "3pss.cfg")

# attributes measured on the clock, and the commit stamped when each binary
# was linked (the program and the library may be linked at different commits
# of a working tree)
IGNORED = re.compile(r"wall|created_utc|last_resumed|elapsed|cpu_time|git_commit")


def _equal(x, y):
    if isinstance(x, bytes):
        x = x.decode()
    if isinstance(y, bytes):
        y = y.decode()
    if isinstance(x, np.ndarray) or isinstance(y, np.ndarray):
        x, y = np.asarray(x), np.asarray(y)
        if x.shape != y.shape or x.dtype != y.dtype:
            return False
        if x.dtype.names:
            return all(_equal(x[n], y[n]) for n in x.dtype.names if not IGNORED.search(n))
        if x.dtype.kind == "f":
            return np.array_equal(x, y, equal_nan=True)
        if x.dtype.kind in "OSU":
            return all(_equal(a, b) for a, b in zip(x.ravel(), y.ravel()))
        return np.array_equal(x, y)
    if isinstance(x, float) and isinstance(y, float) and x != x and y != y:
        return True
    return x == y


def h5_differences(a_path, b_path):
    """Every field (dataset, attribute) that differs, wall times aside."""
    bad = []

    def walk(a, b, where):
        for k in set(a.attrs) | set(b.attrs):
            if IGNORED.search(k):
                continue
            if k not in a.attrs or k not in b.attrs:
                bad.append("%s@%s only in one" % (where, k))
            elif not _equal(a.attrs[k], b.attrs[k]):
                bad.append("%s@%s" % (where, k))
        if isinstance(a, h5py.Dataset):
            if not _equal(a[()], b[()]):
                bad.append(where)
            return
        for k in set(a) | set(b):
            if k not in a or k not in b:
                bad.append("%s/%s only in one" % (where, k))
            else:
                walk(a[k], b[k], where + "/" + k)

    with h5py.File(a_path, "r") as a, h5py.File(b_path, "r") as b:
        walk(a, b, "")
    return sorted(bad)


def summary_body(path, results):
    """summary.md without what names the run (results path, date, wall
    times: the run's and each candidate's fidelity cost, the last cell of
    the fidelity table; the commit the binary was linked at)."""
    text = open(path).read().replace(results, "RESULTS")
    text = re.sub(r"\d{4}-\d\d-\d\d \d\d:\d\d UTC", "DATE", text)
    text = re.sub(r"\(commit [^)]*\)", "(commit X)", text)
    text = re.sub(r"(±.*\| )[0-9.]+ \|$", r"\1X |", text, flags=re.M)
    return re.sub(r"[0-9.]+ s wall", "X s wall", text)


def table_rows(path):
    """A CSV table's rows without the columns measured on the clock."""
    rows = list(csv.reader(open(path)))
    keep = [i for i, h in enumerate(rows[0]) if not re.search(r"wall|^time_s$|cpu", h)]
    return [[row[i] for i in keep if i < len(row)] for row in rows]


@pytest.fixture(scope="module")
def three_ways(tmp_path_factory):
    d = tmp_path_factory.mktemp("job")
    prog, c_out, py = d / "prog" / "r.h5", d / "c" / "r.h5", d / "py" / "r.h5"
    for p in (prog, c_out, py):
        p.parent.mkdir()
    p = subprocess.run(
        [PROGRAM, "study", STUDY, "--out", str(prog), "--tabular", str(prog)[:-3] + ".csv", "--json", "--no-plots"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert p.returncode == 0, p.stderr
    prog_report = json.loads(p.stdout)
    c = subprocess.run([C_LAYER, STUDY, str(c_out), str(d / "c.json")], capture_output=True, text=True, timeout=300)
    assert c.returncode == 0, c.stderr
    c_report = json.load(open(d / "c.json"))
    r = pomlab.study(STUDY, output=py, plots=False)
    return {"prog": (prog, prog_report), "c": (c_out, c_report), "py": (py, r.report), "result": r}


def test_results_files_equal_field_by_field(three_ways):
    prog = three_ways["prog"][0]
    for way in ("c", "py"):
        assert h5_differences(str(prog), str(three_ways[way][0])) == [], way


def test_fidelity_earned_by_every_caller(three_ways):
    with h5py.File(three_ways["py"][0], "r") as f:
        for c in ("0", "1"):
            g = f["candidates"][c]
            assert g.attrs["fidelity"] in (b"auto", "auto")
            assert "fidelity_setting" in g.attrs
    for way in ("prog", "c", "py"):
        for cand in three_ways[way][1]["candidates"]:
            assert "fidelity" in cand, way


def test_reports_equal(three_ways):
    want = three_ways["prog"][1]
    assert three_ways["c"][1] == want
    assert three_ways["py"][1] == want


def test_tables_and_summary_equal(three_ways):
    prog, py = three_ways["prog"][0], three_ways["py"][0]
    for suffix in (".csv", "_candidates.csv"):
        assert table_rows(str(prog)[:-3] + suffix) == table_rows(str(py)[:-3] + suffix), suffix
    r = three_ways["result"]
    assert r.summary == os.path.join(str(py)[:-3], "summary.md")
    assert summary_body(r.summary, str(py)) == summary_body(os.path.join(str(prog)[:-3], "summary.md"), str(prog))


def test_montecarlo_output_over_its_config_refused(tmp_path):
    cfg = tmp_path / "v.cfg"
    shutil.copy(CFG_3PSS, cfg)
    before = cfg.read_bytes()
    with pytest.raises(pomlab.PomlabError) as e:
        pomlab.montecarlo(str(cfg), n=2, threads=1, output=str(cfg))
    assert e.value.status == "POM_ERR_CONFIG"
    assert str(cfg) in str(e.value) and "the config" in str(e.value)
    assert cfg.read_bytes() == before
    assert sorted(os.listdir(tmp_path)) == ["v.cfg"]


def test_study_output_over_its_config_refused(tmp_path):
    cfg = tmp_path / "s.cfg"
    shutil.copy(STUDY, cfg)
    text = cfg.read_text().replace("../configs/", SRC + "/configs/")
    cfg.write_text(text)
    with pytest.raises(pomlab.PomlabError, match="s.cfg"):
        pomlab.study(str(cfg), output=str(cfg), plots=False)
    assert cfg.read_text() == text


INTERRUPTED_RUN = r"""
import sys, time, pomlab
print("start", flush=True)
try:
    pomlab.montecarlo(sys.argv[1], n=400, threads=1, output=sys.argv[2], summary=False, plots=False)
    print("finished", flush=True)
except KeyboardInterrupt:
    print("interrupted %.6f" % time.monotonic(), flush=True)
    sys.exit(3)
"""


def test_ctrl_c_stops_within_a_second_and_resumes(tmp_path):
    out = tmp_path / "mc.h5"
    p = subprocess.Popen(
        [sys.executable, "-c", INTERRUPTED_RUN, CFG_3PSS, str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert p.stdout.readline().strip() == "start"
    # the signal goes once the runs have begun (the .partial exists) and
    # have gone on for a while, however loaded the machine
    partial = str(out) + ".partial"
    deadline = time.monotonic() + 60
    while not os.path.exists(partial) and time.monotonic() < deadline:
        time.sleep(0.01)
    time.sleep(0.5)
    sent = time.monotonic()
    p.send_signal(signal.SIGINT)
    stdout, stderr = p.communicate(timeout=60)
    assert p.returncode == 3, stderr
    latency = float(stdout.split()[1]) - sent
    print("KeyboardInterrupt %.1f ms after SIGINT" % (latency * 1e3))
    assert latency < 1.0
    assert os.path.exists(partial) and not os.path.exists(out)
    with h5py.File(partial, "r") as f:
        done = int(np.sum(f["candidates"]["0"]["maneuvers"]["done"][()]))
    assert 0 < done < 400
    # resume=True finishes what is left (the same 400 maneuvers)
    r = pomlab.montecarlo(CFG_3PSS, n=400, threads=2, output=str(out), resume=True, summary=False, plots=False)
    assert os.path.exists(out) and not os.path.exists(partial)
    assert len(r.rows) == 400
