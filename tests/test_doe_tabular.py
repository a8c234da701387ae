#!/usr/bin/python3
"""Tabular results read back by pandas (docs/results.md, "Tabular results").

usage: test_doe_tabular.py RESULTS.h5 MANEUVERS.csv CANDIDATES.csv

Every value of both CSV tables must equal the results file's (the CSV
numbers are written with round-trip precision, so equality is exact):
factor columns = /factors, metric columns = the maneuver rows, statistics
columns = /statistics, one row per finished candidate x maneuver.
"""
import re
import sys

import h5py
import numpy as np
import pandas as pd


def same(a, b, what):
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape, "%s: shape %s != %s" % (what, a.shape, b.shape)
    ok = (a == b) | (np.isnan(a) & np.isnan(b))
    assert ok.all(), "%s differs: %s vs %s" % (what, a[~ok][:3], b[~ok][:3])


def main(h5, man_csv, cand_csv):
    # round_trip: the parser that gives back the exact doubles written
    man = pd.read_csv(man_csv, float_precision="round_trip")
    cand = pd.read_csv(cand_csv, float_precision="round_trip")
    with h5py.File(h5, "r") as f:
        nc = int(f.attrs["n_candidates"])
        keys = f["factors"].attrs["keys"]
        keys = (keys.decode() if isinstance(keys, bytes) else str(keys)).split(",")
        factors = f["factors"][:]
        assert list(cand["candidate_index"]) == list(range(nc))
        for j, key in enumerate(keys):
            same(cand[key], factors[:, j], "candidate table factor " + key)
        done_rows = 0
        for c in range(nc):
            g = f["candidates/%d" % c]
            name = g.attrs["name"]
            name = name.decode() if isinstance(name, bytes) else str(name)
            assert cand["candidate"][c] == name, (cand["candidate"][c], name)
            rows = g["maneuvers"][:]
            done = rows["done"] == 1
            mine = man[man["candidate_index"] == c]
            assert (mine["candidate"] == name).all()
            same(mine["maneuver"], np.nonzero(done)[0], "maneuver indices")
            for j, key in enumerate(keys):
                same(mine[key], np.full(int(done.sum()), factors[c, j]), "factor " + key)
            same(mine["status"], rows["status"][done], "status")
            # every metric of the schema: name[_<actuator>][_<SI unit>]
            for field in rows.dtype.names:
                if field in ("done", "status", "reason"):
                    continue
                v = rows[field][done]
                per = v.ndim == 2
                pattern = re.compile("^%s%s(_(s|J|V|m|rad|rad_per_s))?$" % (re.escape(field),
                                                                    "_([123])" if per else ""))
                cols = [col for col in man.columns if pattern.match(col)]
                assert len(cols) == (3 if per else 1), (field, cols)
                for col in cols:
                    i = int(pattern.match(col).group(1)) - 1 if per else None
                    same(mine[col], v[:, i] if per else v, col)
            done_rows += int(done.sum())
        assert len(man) == done_rows, (len(man), done_rows)
        # per-candidate statistics
        for stat in f["statistics"]:
            if stat == "counts":
                counts = f["statistics/counts"][:]
                for j, col in enumerate(("done", "ok", "failed", "unsettled", "censored")):
                    same(cand[col], counts[:, j], "counts " + col)
                continue
            table = f["statistics/" + stat][:]
            columns = f["statistics/" + stat].attrs["columns"]
            columns = (columns.decode() if isinstance(columns, bytes) else columns).split(",")
            # the table's 10 columns under one prefix (the statistic's JSON key)
            prefixes = [col[:-2] for col in cand.columns if col.endswith("_n")]
            hits = [p for p in prefixes
                    if all(np.array_equal(cand["%s_%s" % (p, name)].to_numpy(float), table[:, j],
                                          equal_nan=True) for j, name in enumerate(columns))]
            assert len(hits) >= 1, "no columns of the candidate table hold " + stat
    print("tabular: %d maneuver rows, %d candidates match the results file" % (len(man), nc))
    return 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:]))
