"""test_python.py - python/pomlab (ctypes over libpomlab) against the program's
JSON: IK, FK, workspace and maneuvers equal to the printed digits, the
registries, a Monte-Carlo run row for row, errors carrying the library's
message, several threads at once, and a reduced run of docs/python.md's
three-architecture table.

Run by ctest (tests/api.cmake) with POMLAB_LIBRARY (the built libpomlab),
PYTHONPATH (python/) and POMLAB_PROGRAM (the built pomlab) set.
"""

import json
import math
import os
import re
import subprocess
import tempfile
import threading

import h5py
import numpy as np
import pandas as pd
import pytest

import pomlab

SRC = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROGRAM = os.environ.get("POMLAB_PROGRAM", os.path.join(SRC, "build", "cli", "pomlab"))
CFG = {a: os.path.join(SRC, "configs", a + ".cfg") for a in ("3pss", "3sps", "3rrr")}
DEG = math.pi / 180.0


def run_json(*args, ok=(0,)):
    p = subprocess.run([PROGRAM, *args, "--json"], capture_output=True, text=True, timeout=120)
    assert p.returncode in ok, p.stderr
    return json.loads(p.stdout)


def same(got, want):
    """Exactly the doubles the program printed with %.17g (null = None/NaN)."""
    if want is None:
        return got is None or (isinstance(got, float) and math.isnan(got))
    if isinstance(want, list):
        g = np.asarray(got, dtype=float).ravel()
        w = np.asarray(want, dtype=float).ravel()
        return g.shape == w.shape and all(a == b for a, b in zip(g, w))
    return got == want


def printed(got, want):
    """A metric as `pomlab simulate --json` prints it: %.9g for reals, the
    integer for counts, null for NaN."""
    if isinstance(want, list):
        return len(want) == len(got) and all(printed(g, w) for g, w in zip(list(got), want))
    if want is None:
        return isinstance(got, float) and math.isnan(got)
    if isinstance(want, bool) or isinstance(want, str):
        return got == want
    if isinstance(want, int) and not isinstance(got, float):
        return int(got) == want
    return float("%.9g" % got) == float(want)


# ---- registries ---------------------------------------------------------------


def test_registries():
    want = run_json("model", "--list-architectures")["architectures"]
    got = pomlab.architectures()
    assert [a["name"] for a in got] == [a["name"] for a in want]
    assert [a["label"] for a in got] == [a["label"] for a in want]
    assert [a["actuator_kind"] for a in got] == [a["actuator_kind"] for a in want]
    ctrl = run_json("model", "--list-controllers")
    names = [c["name"] for c in (ctrl["controllers"] if isinstance(ctrl, dict) else ctrl)]
    assert [c["name"] for c in pomlab.controllers()] == names
    assert "pid" in names
    assert pomlab.version()["version"]


# ---- kinematics ------------------------------------------------------------------


@pytest.mark.parametrize(
    "arch,angles",
    [("3pss", (2.385, -1.5, 1.0)), ("3sps", (-4.0, 3.25, 0.5)), ("3rrr", (5.0, -2.5, 7.75)), ("3pss", (30, 25, -20))],
)
def test_ik_equals_program(arch, angles):
    want = run_json("ik", CFG[arch], "--euler-zyx", ",".join(repr(a) for a in angles), ok=(0, 1))
    got = pomlab.ik(CFG[arch], angles, degrees=True)
    for key in ("reachable", "unreachable_limb", "within_limits", "violations", "message", "architecture"):
        assert got[key] == want[key], key
    for key in ("q", "jacobian", "singular_values", "kappa", "dexterity"):
        assert same(got[key], want[key]), key
    # the singular flags and the serial measure (docs/kinematics-tables.md 3.2)
    if got["reachable"]:
        assert got["singularities"] == want["singularities"]
        assert got["serial_limbs"] == want["serial_limbs"]
        assert same(got["transmission"], want["transmission"])
    for key in want:
        if key.endswith(("_deg", "_mm")) and key != "euler_zyx_deg":
            assert same(got[key], want[key]), key
    if got["reachable"]:
        J = pomlab.jacobian(CFG[arch], [a * DEG for a in angles])
        assert same(J, want["jacobian"])


def test_fk_equals_program():
    for arch, q_mm in (("3pss", (1.5, -2.0, 0.5)), ("3sps", (-0.75, 1.25, 2.0))):
        want = run_json("fk", CFG[arch], "--q", ",".join(repr(v) for v in q_mm))
        got = pomlab.fk(CFG[arch], [v / 1e3 for v in q_mm])
        assert got["solved"] and want["solved"]
        for key in ("rotation", "euler_zyx_deg", "quaternion_wxyz", "q", "dexterity", "kappa", "residual"):
            assert same(got[key], want[key]), (arch, key)
        assert got["iterations"] == want["iterations"]
    # a rotary architecture: q in rad, back to the orientation IK started from
    pose = pomlab.ik(CFG["3rrr"], (3.0, -2.0, 4.5), degrees=True)
    back = pomlab.fk(CFG["3rrr"], pose["q"])
    assert np.allclose(back["euler_zyx_deg"], (3.0, -2.0, 4.5), rtol=0, atol=1e-9)


def test_workspace_equals_program():
    want = run_json("workspace", CFG["3pss"], "--quiet")
    got = pomlab.workspace(CFG["3pss"])
    for key in ("half_width_deg", "capped", "budget_reached", "min_dexterity", "gci", "gci_half_width_deg",
                "gci_usable_fraction", "poses_evaluated"):
        assert same(got[key], want[key]), key
    assert same(got["first_failure"]["euler_zyx_deg"], want["first_failure"]["euler_zyx_deg"])


def test_limits_are_data():
    want = run_json("ik", CFG["3pss"], "--euler-zyx", "80,60,0", ok=(1,))
    got = pomlab.ik(CFG["3pss"], (80.0, 60.0, 0.0), degrees=True)
    assert got["reachable"] and not got["within_limits"]
    assert got["violations"] == want["violations"] and "stroke limb 1" in got["violations"]
    assert got["message"] == want["message"]
    assert same(pomlab.jacobian(CFG["3pss"], (80.0, 60.0, 0.0), degrees=True), want["jacobian"])


# ---- one maneuver ---------------------------------------------------------------------


def check_maneuver(got, want):
    assert got["status"] == want["status"] and got["reason"] == want["reason"]
    assert got["name"] == want["name"]
    assert printed(got["half_stroke"], want["half_stroke"])
    keys = [k for k, _, _ in pomlab.metric_keys()]
    assert set(keys) <= set(want), set(keys) - set(want)
    for key in keys:
        if key == "wall_time_s":
            continue
        assert printed(got[key], want[key]), (key, got[key], want[key])


@pytest.mark.parametrize(
    "arch,target,options,overrides",
    [
        ("3pss", (1, 2, 3), [], {}),  # the issue's example
        ("3sps", (1.5, -2, 0.5), ["--joints", "rigid", "--kp", "5000"], {"joints.model": "rigid", "controller.kp": 5000}),
        ("3rrr", (4, -3, 2.5), [], {}),
    ],
)
def test_simulate_equals_program(arch, target, options, overrides, tmp_path):
    h5 = str(tmp_path / "m.h5")
    want = run_json("simulate", CFG[arch], "--target", ",".join(str(v) for v in target), "--out", h5, *options)
    unit = want["actuator_unit"]
    to_si = 1e3 if unit == "m" else 180.0 / math.pi  # the program's display -> SI divisor
    got = pomlab.simulate(CFG[arch], target=[v / to_si for v in target], overrides=overrides)
    check_maneuver(got, want)
    # the traces: the very doubles the program wrote
    with h5py.File(h5, "r") as f:
        for name in ("t", "q", "q_dot", "current", "voltage", "energy", "euler_zyx", "quat", "deflection"):
            assert np.array_equal(got["traces"][name], f["trace"][name][()]), name


def test_issue_example():
    got = pomlab.simulate(CFG["3pss"], target=(1e-3, 2e-3, 3e-3))["execution_time_s"]
    want = run_json("simulate", CFG["3pss"], "--target", "1,2,3")["execution_time_s"]
    assert float("%.9g" % got) == want


def test_config_text_and_overrides():
    text = open(CFG["3pss"]).read()
    cfg = pomlab.load(text=text, name="inline.cfg", overrides={"controller": {"kd_s": 0.0025}})
    a = pomlab.simulate(cfg, (1e-3, -1e-3, 0.5e-3), traces=False)
    b = pomlab.simulate(CFG["3pss"], (1e-3, -1e-3, 0.5e-3), traces=False, overrides={"controller.kd_s": 0.0025})
    assert a["execution_time_s"] == b["execution_time_s"] and "traces" not in a
    c = pomlab.simulate(CFG["3pss"], (1e-3, -1e-3, 0.5e-3), traces=False)
    assert c["execution_time_s"] != a["execution_time_s"]


# ---- errors ---------------------------------------------------------------------------


def test_errors(tmp_path):
    with pytest.raises(pomlab.PomlabError) as e:
        pomlab.simulate(CFG["3pss"], (1e-3, 0, 0), overrides={"controller.kp": -3.5})
    assert e.value.status == "POM_ERR_CONFIG"
    assert "controller.kp" in e.value.message and "-3.5" in e.value.message
    with pytest.raises(pomlab.PomlabError) as e:
        pomlab.ik(str(tmp_path / "missing.cfg"), (0, 0, 0))
    assert e.value.status == "POM_ERR_IO" and "missing.cfg" in e.value.message
    bad = tmp_path / "bad.cfg"
    bad.write_text('name = "x";\narchitecture = "3PSS";\ngeometry = { mode = 12 ;\n')
    with pytest.raises(pomlab.PomlabError) as e:
        pomlab.load(bad)
    assert "bad.cfg" in e.value.message
    with pytest.raises(pomlab.PomlabError) as e:
        pomlab.simulate(CFG["3pss"], (7e-3, 0, 0))
    assert e.value.status == "POM_ERR_ARG" and "stroke" in e.value.message
    with pytest.raises(pomlab.PomlabError) as e:
        pomlab.ik(CFG["3pss"], (0, 0, 0), overrides={"geometry.no_such_key": 2.385})
    assert "no_such_key" in e.value.message
    with pytest.raises(pomlab.PomlabError):
        pomlab.load(CFG["3pss"], overrides={"controller.kp": [1, 2]})
    before = set(os.listdir(tempfile.gettempdir()))
    with pytest.raises(pomlab.PomlabError) as e:
        pomlab.montecarlo(CFG["3pss"], n=0)
    assert "montecarlo.maneuvers" in e.value.message
    assert not [d for d in set(os.listdir(tempfile.gettempdir())) - before if d.startswith("pomlab-")]


def refused(status, *words, call):
    """call() raises PomlabError with status and a message naming every word."""
    with pytest.raises(pomlab.PomlabError) as e:
        call()
    assert e.value.status == status, e.value
    for w in words:
        assert w in e.value.message, (w, e.value.message)


@pytest.mark.parametrize(
    "key, words",
    [
        ("contoller.kp", ("contoller.kp", "unknown top-level key")),
        ("nosuch.key", ("nosuch.key", "unknown top-level key")),
        ("controller.kpp", ("controller.kpp", "unknown key")),
        ("montecarlo.maneuvers", ("montecarlo.maneuvers", "not read")),
        ("workspace.resolution_deg", ("workspace.resolution_deg", "not read")),
    ],
)
def test_overrides_checked_as_file_keys(key, words):
    """docs/python.md section 2: an override nobody reads is refused, as the
    same key in a file would be (issue 31 item 5)."""
    refused("POM_ERR_CONFIG", *words, call=lambda: pomlab.simulate(CFG["3pss"], (1e-3, 0, 0), traces=False,
                                                                    overrides={key: 5}))
    if not key.startswith("montecarlo"):
        refused("POM_ERR_CONFIG", key, call=lambda: pomlab.montecarlo(CFG["3pss"], n=2, threads=1,
                                                                       overrides={key: 5}))
    if key.startswith(("contoller", "nosuch", "montecarlo")):
        refused("POM_ERR_CONFIG", key, call=lambda: pomlab.ik(CFG["3pss"], (0, 0, 0), overrides={key: 5}))


def test_nul_bytes_refused(tmp_path):
    """A NUL byte would cut a C string short: refused before the library
    (docs/fuzzing.md; issue 31 item 7)."""
    sim = lambda cfg, **kw: pomlab.simulate(cfg, (1e-3, 0, 0), traces=False, **kw)
    refused("POM_ERR_ARG", "NUL", call=lambda: sim(CFG["3pss"], overrides={"controller.kp\x00junk": 5000}))
    refused("POM_ERR_ARG", "NUL", call=lambda: sim(CFG["3pss"], overrides={"joints.model": "rigid\x00x"}))
    refused("POM_ERR_ARG", "NUL", call=lambda: sim(CFG["3pss"] + "\x00.cfg"))
    with open(CFG["3pss"]) as f:
        text = f.read()
    k = text.index("controller = {")
    refused("POM_ERR_ARG", "NUL", call=lambda: sim(pomlab.Config(text=text[:k] + "\x00" + text[k:])))
    refused("POM_ERR_ARG", "NUL", call=lambda: sim(pomlab.Config(text=text, name="a\x00b")))
    refused("POM_ERR_ARG", "NUL", call=lambda: pomlab.load(text=text, overrides={"controller\x00": {"kp": 1}}))


def test_lenient_arguments_refused():
    """Arguments the program refuses are refused alike, naming the key
    (issue 31 item 10); numpy scalars are numbers."""
    base = pomlab.simulate(CFG["3pss"], (1e-3, 0, 0), traces=False, overrides={"controller.kp": 5000})
    for v in (np.int64(5000), np.int32(5000), np.float64(5000.0), np.float32(5000.0)):
        got = pomlab.simulate(CFG["3pss"], (1e-3, 0, 0), traces=False, overrides={"controller.kp": v})
        assert got["execution_time_s"] == base["execution_time_s"] or (
            math.isnan(got["execution_time_s"]) and math.isnan(base["execution_time_s"])
        )
    sim = lambda ov: pomlab.simulate(CFG["3pss"], (1e-3, 0, 0), traces=False, overrides=ov)
    refused("POM_ERR_ARG", "controller.kp", call=lambda: sim({"controller.kp": True}))
    refused("POM_ERR_ARG", "controller.kp", call=lambda: sim({"controller.kp": np.bool_(True)}))
    refused("POM_ERR_ARG", "controller.kp", call=lambda: sim({"controller.kp": None}))
    for key in ("", "controller. kp", "controller..kp", "controller.kp."):
        refused("POM_ERR_CONFIG", "not a config key", call=lambda: sim({key: 1}))
    mc = lambda **kw: pomlab.montecarlo(CFG["3pss"], **kw)
    refused("POM_ERR_CONFIG", "montecarlo.maneuvers", call=lambda: mc(n=1.5, threads=1))
    refused("POM_ERR_ARG", "montecarlo.maneuvers", call=lambda: mc(n=True, threads=1))
    refused("POM_ERR_CONFIG", "montecarlo.seed", call=lambda: mc(n=2, seed=1.5, threads=1))
    for t in (-1, 10**6, 1.5, True, 2**80):
        refused("POM_ERR_ARG", "threads", call=lambda: mc(n=2, threads=t))
        refused("POM_ERR_ARG", "threads", call=lambda: pomlab.study(CFG["3pss"], n=2, threads=t))
    r = mc(n=np.int64(2), seed=np.int64(7), threads=np.int64(1))
    assert len(r.rows) == 2


# ---- threads --------------------------------------------------------------------------


def test_threads_give_the_sequential_results():
    targets = [(1e-3 * (k % 3 - 1), 0.7e-3 * (k % 4 - 1.5), 0.45e-3 * k) for k in range(6)]
    opts = {"joints.model": "rigid"}
    alone = [pomlab.simulate(CFG["3pss"], t, traces=False, overrides=opts) for t in targets]
    together = [None] * len(targets)

    def work(k):
        together[k] = pomlab.simulate(CFG["3pss"], targets[k], traces=False, overrides=opts)
        pomlab.ik(CFG["3rrr"], (k, -k, 0.5 * k), degrees=True)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(len(targets))]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for a, b in zip(alone, together):
        for key, _, _ in pomlab.metric_keys():
            if key != "wall_time_s":
                assert np.array_equal(np.asarray(a[key]), np.asarray(b[key]), equal_nan=True), key


# ---- Monte-Carlo runs and studies ----------------------------------------------------


def test_montecarlo_equals_program(tmp_path):
    out = str(tmp_path / "cli.h5")
    args = ["montecarlo", CFG["3pss"], "--n", "10", "--seed", "7", "--out", out,
            "--tabular", str(tmp_path / "cli.csv"), "--quiet"]
    p = subprocess.run([PROGRAM, *args], capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr
    want = pd.read_csv(tmp_path / "cli.csv")
    r = pomlab.montecarlo(CFG["3pss"], n=10, seed=7, output=tmp_path / "py.h5")
    assert r.results == str(tmp_path / "py.h5") and os.path.exists(r.results)
    assert list(r.rows.columns) == list(want.columns) and len(r.rows) == 10
    cols = [c for c in want.columns if not c.startswith("wall_time")]
    pd.testing.assert_frame_equal(r.rows[cols], want[cols], check_exact=True)
    with h5py.File(r.results, "r") as f:
        assert f["candidates/0/maneuvers"].shape[0] == 10
    assert int(r.candidates["done"][0]) == 10


def test_three_architectures_reduced(tmp_path):
    """docs/python.md's example on 24 maneuvers instead of 500."""
    r = pomlab.study(os.path.join(SRC, "configs", "architectures.cfg"), n=24, output=tmp_path / "arch.h5")
    table = r.rows.groupby("candidate", sort=False).agg(
        execution_time_ms=("execution_time_s", lambda s: 1e3 * s.mean()),
        energy_J=("energy_total_J", "mean"))
    order = list(table.sort_values("execution_time_ms").index)
    assert order == ["3P-S-S/S", "3-RRR", "3S-P-S/S"]
    # the per-candidate statistics of the results agree with the rows
    stats = r.candidates.set_index("candidate")
    for name in order:
        settled = r.rows[(r.rows.candidate == name) & (r.rows.status == 0)]  # POM_OK
        assert np.isclose(stats.loc[name, "execution_time_s_mean"], settled.execution_time_s.mean(), rtol=1e-9)
    assert os.path.isdir(tmp_path / "arch")  # the tuned gains beside the results


def test_unresolved_and_not_computed_are_nan():
    """docs/results.md sections 1c and 1d: a stepinfo band below what the
    integration resolves, and what a failed maneuver did not compute, are NaN
    (null in the program's JSON), never a number."""
    z = pomlab.simulate(CFG["3pss"], (0, 0, 0), traces=False, overrides={"joints.model": "rigid"})
    assert z["status"] == "POM_OK"
    assert all(math.isnan(v) for v in z["settling_time_final_s"])
    assert list(z["stepinfo_unresolved"]) == [1, 1, 1]
    short = {"joints.model": "rigid", "geometry.platform_radius_mm": 12.0, "geometry.limb_length": 2.0,
             "geometry.limb_lean_deg": 80.0, "geometry.limb_azimuth_deg": 60.0}
    f = pomlab.simulate(CFG["3pss"], (6e-3, -6e-3, 6e-3), traces=False, overrides=short)
    assert f["status"] == "POM_ERR_SINGULAR" and "near-singular" in f["reason"]
    for key in ("energy_total_J", "energy_balance_error", "energy_supplied_J", "final_pointing_error_rad"):
        assert math.isnan(f[key]), key
    for key in ("final_q", "max_abs_q", "energy_J", "saturation_time_s"):
        assert all(math.isnan(v) for v in f[key]), key
    assert all(v == 24.0 for v in f["peak_voltage_V"]) and f["peak_angular_rate_rad_per_s"] > 100
    assert f["steps"] > 0


def test_study_capability_columns(tmp_path):
    """study.capability: the candidates table and the report carry the figures
    (docs/capability.md, "As study responses and constraints"), equal to
    `pomlab capability CFG --grid 3 --json` for the same candidate."""
    r = pomlab.study(os.path.join(SRC, "tests", "doe_study_capability.cfg"), output=tmp_path / "c.h5")
    for i, arch in enumerate(("3pss", "3sps")):
        cap = run_json("capability", CFG[arch], "--grid", "3", "--quiet")
        want = cap["worst_acc"]["acc_inscribed_rad_per_s2"]
        assert math.isclose(r.candidates["capability_acc_inscribed_worst"][i], want, rel_tol=1e-12)
        assert math.isclose(r.report["candidates"][i]["capability"]["acc_inscribed_worst"], want, rel_tol=1e-12)
        want = cap["worst_rate"]["rate_inscribed_rad_per_s"]
        assert math.isclose(r.candidates["capability_rate_inscribed_worst"][i], want, rel_tol=1e-12)
        # the bandwidth: NaN in the table exactly where the report says null
        bw = r.report["candidates"][i]["capability"]["bw_worst_hz"]
        t = r.candidates["capability_bw_worst_hz"][i]
        assert (bw is None and math.isnan(t)) or t == bw


def test_study_capability_require_excludes(tmp_path):
    """study.capability_require: the 3S-P-S/S (~3.8e3 rad/s^2 at its worst
    pose) fails a floor of 1e4 the 3P-S-S/S (~2.4e4) meets: it is out of the
    ranking, and the report names the requirement, its value and bound."""
    text = open(os.path.join(SRC, "tests", "doe_study_capability.cfg")).read()
    text = re.sub(r"capability = \[.*\];", 'capability_require = ["acc_inscribed_worst >= 1e4"];', text)
    text = text.replace('"../configs/', '"%s/configs/' % SRC)
    (tmp_path / "req.cfg").write_text(text)
    r = pomlab.study(str(tmp_path / "req.cfg"), output=tmp_path / "r.h5")
    assert list(r.candidates["capability_met"]) == [1, 0]
    assert r.report["ranking"]["execution_time"] == ["3PSS"]
    (ex,) = r.report["excluded"]
    assert ex["name"] == "3SPS" and ex["failed"][0]["bound"] == 1e4
    # the table's digits against the report's %.17g: equal to rounding
    v = ex["failed"][0]["value"]
    assert v < 1e4 and math.isclose(v, r.candidates["capability_acc_inscribed_worst"][1], rel_tol=1e-12)


def _rigid_3pss(tmp_path):
    text = open(CFG["3pss"]).read()
    text = re.sub(r"(angular_damping_Nms_per_rad = [^;]*;)", r'\1\n  model = "rigid";', text)
    path = tmp_path / "rigid.cfg"
    path.write_text(text)
    return str(path)


def test_gradient(tmp_path):
    """pomlab.gradient returns exactly what `pomlab gradient --json` prints
    (issue 29): per maneuver the metrics and their design gradients, the
    means and theirs; a parasitic config and a model override are refused."""
    cfg = _rigid_3pss(tmp_path)
    keys = ["actuator.resistance_ohm", "controller.kd_s"]
    got = pomlab.gradient(cfg, keys, maneuvers=2)
    want = run_json("gradient", cfg, "--params", ",".join(keys), "--maneuvers", "2")
    assert got["keys"] == keys and len(got["maneuvers"]) == 2
    for g, w in zip(got["maneuvers"], want["maneuvers"]):
        assert same(g["metrics"]["energy_total"], w["metrics"]["energy_total"])
        assert same(g["gradient"]["energy_total"], w["gradient"]["energy_total"])
        assert len(g["gradient"]["energy_total"]) == 2
        # the peak coil current and its argmax (docs/optimize.md 12.2)
        assert g["metrics"]["peak_current"] > 0
        assert same(g["metrics"]["peak_current"], w["metrics"]["peak_current"])
        assert same(g["gradient"]["peak_current"], w["gradient"]["peak_current"])
        assert g["peak_current_at"] == w["peak_current_at"]
        assert 1 <= g["peak_current_at"]["coil"] <= 3
    assert same(got["mean_gradient"]["energy_total"], want["mean_gradient"]["energy_total"])
    # the smooth robust statistic of the times (docs/optimize.md 12.3): its
    # gradient is sum_i w_i dt_i/dp, weights positive and summing to 1, so
    # it lies between the maneuvers' derivatives
    q = got["quantile"]
    assert q == want["quantile"] and q["p"] == 0.95 and q["bandwidth_s"] == 1e-3
    assert "energy_total" not in q["value"]
    for j in range(2):
        per = [m["gradient"]["execution_time"][j] for m in got["maneuvers"]]
        assert min(per) - 1e-12 * abs(max(per)) <= q["gradient"]["execution_time"][j] \
            <= max(per) + 1e-12 * abs(max(per))
    q2 = pomlab.gradient(cfg, keys, maneuvers=2, quantile=0.5, bandwidth_ms=2)["quantile"]
    assert q2["p"] == 0.5 and q2["bandwidth_s"] == 2e-3
    assert q2["value"]["execution_time"] < q["value"]["execution_time"]
    with pytest.raises(pomlab.PomlabError) as e:
        pomlab.gradient(cfg, keys, maneuvers=1, quantile=1.5)
    assert "gradient.quantile" in str(e.value) and "1.5" in str(e.value)
    with pytest.raises(pomlab.PomlabError) as e:
        pomlab.gradient(CFG["3pss"], keys, maneuvers=1)
    assert "rigid" in str(e.value)
    with pytest.raises(pomlab.PomlabError):
        pomlab.gradient(cfg, keys, maneuvers=1, overrides={"controller.kp": 1e4})


def test_gradient_sens_error_test(tmp_path):
    """The sensitivities' error test (docs/optimize.md 12.5): sens_error_test
    is gradient.sens_error_test, the same as `pomlab gradient
    --sens-error-test` and as the file's key; off changes the integration
    (other doubles), and a value other than "on" / "off" is refused naming
    the key and the value."""
    cfg = _rigid_3pss(tmp_path)
    keys = ["actuator.resistance_ohm"]
    on = pomlab.gradient(cfg, keys, maneuvers=1)
    off = pomlab.gradient(cfg, keys, maneuvers=1, sens_error_test="off")
    want = run_json("gradient", cfg, "--params", keys[0], "--maneuvers", "1",
                    "--sens-error-test", "off")
    g_on = on["maneuvers"][0]["gradient"]["energy_total"]
    g_off = off["maneuvers"][0]["gradient"]["energy_total"]
    assert same(g_off, want["maneuvers"][0]["gradient"]["energy_total"])
    assert g_off != g_on
    # at a tight rtol the two agree within the issue's energy bound, as
    # elasticities (measured 3.2e-7 at 1e-10; at the shipped 1e-6 1.7e-3)
    tight = tmp_path / "tight.cfg"
    tight.write_text(re.sub(r"rtol = [^;]*;", "rtol = 1e-10;", open(cfg).read()))
    ta = pomlab.gradient(str(tight), keys, maneuvers=1)
    a = ta["maneuvers"][0]
    b = pomlab.gradient(str(tight), keys, maneuvers=1, sens_error_test="off")["maneuvers"][0]
    elasticity = abs(ta["values"][0]) / a["metrics"]["energy_total"]
    assert abs(a["gradient"]["energy_total"][0] - b["gradient"]["energy_total"][0]) * elasticity < 1e-5
    infile = tmp_path / "infile.cfg"
    infile.write_text(open(cfg).read() + '\ngradient = { sens_error_test = "off"; };\n')
    c = pomlab.gradient(str(infile), keys, maneuvers=1)
    assert same(c["maneuvers"][0]["gradient"]["energy_total"], g_off)
    with pytest.raises(pomlab.PomlabError) as e:
        pomlab.gradient(cfg, keys, maneuvers=1, sens_error_test="no")
    assert "gradient.sens_error_test" in str(e.value) and '"no"' in str(e.value)


def test_gradient_sens_margin(tmp_path):
    """The sensitivities' accuracy (docs/optimize.md 12.4): sens_margin is
    gradient.sens_noise_margin, the same as `pomlab gradient --sens-margin`
    and as the file's key; it acts only below rtol = margin x 7.4e-11 (at
    the shipped rtol 1e-6 the same doubles) and a value outside [1, 1e6] is
    refused naming the key and the value."""
    cfg = _rigid_3pss(tmp_path)
    keys = ["actuator.resistance_ohm"]
    base = pomlab.gradient(cfg, keys, maneuvers=1)
    loose = pomlab.gradient(cfg, keys, maneuvers=1, sens_margin=30)
    assert same(loose["maneuvers"][0]["gradient"]["energy_total"],
                base["maneuvers"][0]["gradient"]["energy_total"])
    tight = tmp_path / "tight.cfg"
    tight.write_text(re.sub(r"rtol = [^;]*;", "rtol = 1e-9;", open(cfg).read()))
    a = pomlab.gradient(str(tight), keys, maneuvers=1)
    b = pomlab.gradient(str(tight), keys, maneuvers=1, sens_margin=30)
    want = run_json("gradient", str(tight), "--params", keys[0], "--maneuvers", "1",
                    "--sens-margin", "30")
    assert same(b["maneuvers"][0]["gradient"]["energy_total"],
                want["maneuvers"][0]["gradient"]["energy_total"])
    assert b["maneuvers"][0]["gradient"]["energy_total"] != a["maneuvers"][0]["gradient"]["energy_total"]
    infile = tmp_path / "infile.cfg"
    infile.write_text(open(tight).read() + "\ngradient = { sens_noise_margin = 30.0; };\n")
    c = pomlab.gradient(str(infile), keys, maneuvers=1)
    assert same(c["maneuvers"][0]["gradient"]["energy_total"],
                want["maneuvers"][0]["gradient"]["energy_total"])
    with pytest.raises(pomlab.PomlabError) as e:
        pomlab.gradient(cfg, keys, maneuvers=1, sens_margin=0.5)
    assert "gradient.sens_noise_margin" in str(e.value) and "0.5" in str(e.value)
    p = subprocess.run([PROGRAM, "gradient", cfg, "--params", keys[0], "--sens-margin", "2e6"],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and "sens_noise_margin" in p.stderr and "2000000" in p.stderr
