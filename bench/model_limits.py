"""model_limits.py - the figures of the claims that hold only part of the way
(docs/dynamics.md section 14, README; issue 30 item 7).

  /usr/bin/python3 bench/model_limits.py kp      energy and execution time of
      the parasitic path against its rigid limit, k_p = 1e6 ... 1e10 N/m, on
      (3, -3, 3) mm (deg for the 3-RRR), each architecture's shipped config,
      rtol 1e-9 on both paths (the shipped 1e-6 moves the errors by < 0.01
      points); ~3 s of CPU
  /usr/bin/python3 bench/model_limits.py gains   the K_P stress cases of
      section 14 on both paths (3P-S-S/S, shipped max_steps): status, steps and
      where it stopped; ~6 s of CPU
  /usr/bin/python3 bench/model_limits.py sliding  the 3-RRR in a chattering
      sliding mode (K_P, K_I, tau_D x 1e3, target (3, -2, 2.5) deg): energy
      over the start-up window [0, 3 ms] and over the maneuver, rigid path and
      parasitic path at k_p = 1e6 ... 1e10 (tests/test_dyn_sliding.c holds the
      independent reference); ~3 s of CPU

Run from the source tree with the built module:
  POMLAB_LIBRARY=build/api/libpomlab.so PYTHONPATH=python /usr/bin/python3 bench/model_limits.py kp
(tests/test_docs.py runs both for the checked blocks that quote them.)
"""

import math
import re
import sys

import pomlab

CONFIGS = [("3P-S-S/S", "configs/3pss.cfg", 1e-3), ("3S-P-S/S", "configs/3sps.cfg", 1e-3),
           ("3-RRR", "configs/3rrr.cfg", math.radians(1.0))]
STIFFNESSES = [1e6, 1e7, 1e8, 1e9, 1e10]


def kp_table():
    rtol = 1e-9
    rows = {}
    for name, cfg, unit in CONFIGS:
        target = (3 * unit, -3 * unit, 3 * unit)
        rigid = pomlab.simulate(cfg, target, traces=False,
                                overrides={"joints.model": "rigid", "solver.rtol": rtol})
        assert rigid["status"] == "POM_OK", rigid["reason"]
        rows[name] = (rigid, [])
        for kp in STIFFNESSES:
            par = pomlab.simulate(cfg, target, traces=False,
                                  overrides={"joints.stiffness_N_per_m": kp, "solver.rtol": rtol})
            assert par["status"] == "POM_OK", par["reason"]
            rows[name][1].append(par)
    print("energy of the parasitic path against the rigid one, (E_parasitic / E_rigid - 1) in %%, "
          "target (3, -3, 3) mm or deg, rtol %g" % rtol)
    print("| k_p (N/m) | " + " | ".join(n for n, _, _ in CONFIGS) + " |")
    print("|---|" + "---|" * len(CONFIGS))
    for k, kp in enumerate(STIFFNESSES):
        cells = []
        for name, _, _ in CONFIGS:
            rigid, pars = rows[name]
            cells.append("%+.3f" % (100 * (pars[k]["energy_total_J"] / rigid["energy_total_J"] - 1)))
        print("| %.0e | %s |" % (kp, " | ".join(cells)))
    print("| rigid (J) | " + " | ".join("%.5f" % rows[n][0]["energy_total_J"] for n, _, _ in CONFIGS)
          + " |")
    print()
    print("execution time (ms), parasitic at each k_p and rigid")
    print("| k_p (N/m) | " + " | ".join(n for n, _, _ in CONFIGS) + " |")
    print("|---|" + "---|" * len(CONFIGS))
    for k, kp in enumerate(STIFFNESSES):
        print("| %.0e | %s |" % (kp, " | ".join("%.5f" % (1e3 * rows[n][1][k]["execution_time_s"])
                                                for n, _, _ in CONFIGS)))
    print("| rigid | " + " | ".join("%.5f" % (1e3 * rows[n][0]["execution_time_s"])
                                    for n, _, _ in CONFIGS) + " |")
    for name, _, _ in CONFIGS:
        rigid, pars = rows[name]
        off = pars[-1]["execution_time_s"] - rigid["execution_time_s"]
        print("%s: parasitic at 1e10 - rigid = %.2f us (%.1e relative)"
              % (name, 1e6 * off, off / rigid["execution_time_s"]))


def gains_table():
    """The K_P stress cases, 3P-S-S/S, shipped solver settings."""
    cases = [("(1.2, -0.85, 0.6)", (1.2e-3, -0.85e-3, 0.6e-3)), ("(3, -3, 3)", (3e-3, -3e-3, 3e-3))]
    print("K_P stress, 3P-S-S/S, shipped solver settings (max_steps 200000), horizon 100 ms")
    print("| target (mm) | K_P | parasitic | rigid |")
    print("|---|---|---|---|")
    for label, target in cases:
        for kp in (1.2e7, 1e9):
            cells = []
            for model in ("parasitic", "rigid"):
                r = pomlab.simulate("configs/3pss.cfg", target, traces=False,
                                    overrides={"joints.model": model, "controller.kp": kp})
                if r["status"] == "POM_OK":
                    cells.append("runs, %d steps" % r["steps"])
                else:
                    m = re.search(r"at t = ([0-9.e+-]+) s", r["reason"] or "")
                    where = " at t = %.1f ms" % (1e3 * float(m.group(1))) if m else ""
                    cells.append("%s%s" % ("max_steps" if "max_steps" in (r["reason"] or "")
                                           else r["status"], where))
            print("| %s | %.1e | %s |" % (label, kp, " | ".join(cells)))


def sliding_table():
    target = tuple(math.radians(d) for d in (3.0, -2.0, 2.5))
    gains = {"controller.kp": 1.2e7, "controller.ki_per_s": 1.0, "controller.kd_s": 3.0,
             "solver.max_steps": 2000000}
    runs = [("rigid, rtol 1e-6 (shipped)", {"joints.model": "rigid", "solver.rtol": 1e-6}),
            ("rigid, rtol 1e-7", {"joints.model": "rigid", "solver.rtol": 1e-7}),
            ("rigid, rtol 1e-9, BDF order <= 2", {"joints.model": "rigid", "solver.rtol": 1e-9,
                                                  "solver.max_order": 2})]
    for kp in STIFFNESSES:
        runs.append(("parasitic k_p %.0e, rtol 1e-8, BDF order <= 2" % kp,
                     {"joints.stiffness_N_per_m": kp, "solver.rtol": 1e-8, "solver.max_order": 2}))
    print("3-RRR, K_P, K_I, tau_D x 1e3, target (3, -2, 2.5) deg; energies in J")
    print("| run | [0, 3 ms] | (3, 100 ms] | total | saturated in [0, 3 ms] (ms, per actuator) |")
    print("|---|---|---|---|---|")
    for label, ov in runs:
        out = []
        for horizon in (3.0, 100.0):
            o = dict(gains)
            o.update(ov)
            o["maneuver.horizon_ms"] = horizon
            r = pomlab.simulate("configs/3rrr.cfg", target, traces=False, overrides=o)
            assert r["status"] == "POM_OK", r["reason"]
            out.append(r)
        w, f = out
        print("| %s | %.4e | %.4e | %.4e | %s |" % (
            label, w["energy_total_J"], f["energy_total_J"] - w["energy_total_J"],
            f["energy_total_J"], ", ".join("%.3f" % (1e3 * x) for x in w["saturation_time_s"])))


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else ""
    if what == "kp":
        kp_table()
    elif what == "gains":
        gains_table()
    elif what == "sliding":
        sliding_table()
    else:
        sys.exit("usage: model_limits.py kp|gains|sliding")
