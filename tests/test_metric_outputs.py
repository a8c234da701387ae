#!/usr/bin/python3
"""Every metric of the schema in every output (tests/test_metric_outputs.sh).

usage: test_metric_outputs.py SCHEMA.json SIMULATE.json STUDY.json MONTECARLO.json STUDY.h5 SUMMARY.md
                              SIMULATE.h5
"""
import json
import sys

import h5py

failures = 0


def check(cond, what):
    global failures
    if not cond:
        failures += 1
        print("FAIL:", what)


def main(argv):
    schema, sim, study, mc, h5, summary, sim_h5 = argv[1:8]
    metrics = json.load(open(schema))
    check(len(metrics) > 20, "schema dump has the metrics")
    sim = json.load(open(sim))
    check(sim["actuator_unit"] == "m", "simulate names the actuator unit")
    summary_text = open(summary).read()
    reports = [json.load(open(study)), json.load(open(mc))]
    with h5py.File(h5, "r") as f:
        nc = int(f.attrs["n_candidates"])
        for c in range(nc):
            check(f["candidates/%d" % c].attrs["actuator_unit"] in (b"m", "m"),
                  "candidate %d actuator_unit" % c)
        fields = f["candidates/0/maneuvers"].dtype.names
        units = f["candidates/0/maneuvers"].attrs["units"]
        units = units.decode() if isinstance(units, bytes) else units
        for m in metrics:
            name = m["name"]
            check(name in fields, "HDF5 maneuvers field %s" % name)
            if name in fields:
                shape = f["candidates/0/maneuvers"].dtype[name].shape
                check(shape == ((3,) if m["count"] == 3 else ()), "shape of %s" % name)
            check((" %s " % name) in units or units.startswith(name + " "), "units of %s" % name)
            check(m["json_key"] in sim, "simulate JSON key %s" % m["json_key"])
            if m["json_key"] in sim:
                v = sim[m["json_key"]]
                check(isinstance(v, list) == (m["count"] == 3), "simulate JSON shape of %s" % name)
            # simulate --out F.h5: /metrics holds it under its JSON key, with the
            # value the JSON prints (%.9g: 9 significant digits)
            with h5py.File(sim_h5, "r") as g:
                attrs = g["metrics"].attrs
                key = m["json_key"]
                check(key in attrs, "simulate HDF5 /metrics attribute %s" % key)
                if key in attrs and key in sim:
                    got = [float(x) for x in (attrs[key] if m["count"] == 3 else [attrs[key]])]
                    want = sim[key] if m["count"] == 3 else [sim[key]]
                    want = [float("nan") if x is None else float(x) for x in want]
                    same = all(a == b or (a != a and b != b) or
                               abs(a - b) <= 1e-8 * max(abs(a), abs(b))
                               for a, b in zip(got, want))
                    check(same, "simulate HDF5 %s = %s, JSON %s" % (key, got, want))
            check("`%s`" % name in summary_text, "summary.md lists %s" % name)
            for rep in reports:
                check(any(x["name"] == name for x in rep["metrics"]), "study JSON lists %s" % name)
            if m["stat_name"]:
                check("statistics/%s" % m["stat_name"] in f, "HDF5 statistics %s" % m["stat_name"])
                for rep in reports:
                    for cand in rep["candidates"]:
                        check(m["stat_key"] in cand, "study JSON statistics %s" % m["stat_key"])
    for rep in reports:
        for cand in rep["candidates"]:
            check(cand["actuator_unit"] == "m", "study JSON actuator_unit")
        check(rep["montecarlo"]["actuator_unit"] == "m", "study JSON range unit")
    print("test_metric_outputs: %d failures" % failures)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
