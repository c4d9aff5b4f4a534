#!/usr/bin/env python3
"""one_trial_test.py SIM COMLEARN ASSETS: examples/python/one_trial.py against the real comlearn-sim.

Starts SIM on a udpm URL of its own (ttl=0, a port from the pid), then runs the example as a user
would, once per case, and checks its answer two ways:
  - against the physics: the point placed over B's +x edge is the true CoM (read here from the
    URDF's <inertial>, which only a test and the simulator may read) moved 3 mm along +x, so that
    the CoM is over B (stays), or 3 mm along -x, so that it is past the edge (tips);
  - against `comlearn plan --simulate` (lib/balance in-process, on the planned release): the same
    outcome and the same settled pose, converted to B's frame, within 1e-6 m and 1e-6 rad.
Exit status 0 only if every case passed."""

import json
import math
import os
import random
import subprocess
import sys
import time
import xml.etree.ElementTree as ET

HERE = os.path.dirname(os.path.abspath(__file__))
EXAMPLE = os.path.join(HERE, "..", "..", "examples", "python", "one_trial.py")
ROCKS = ("rock_1_uneven", "rock_3_even")
OFFSET_M = 0.003
TOL_M = 1e-6


def true_com(urdf):
    origin = ET.parse(urdf).getroot().find("link/inertial/origin")
    return [float(v) for v in origin.get("xyz").split()]


def quat_angle(a, b):
    d = abs(sum(x * y for x, y in zip(a, b)))
    return 2.0 * math.acos(min(1.0, d))


def run(cmd):
    p = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    if p.returncode != 0:
        raise AssertionError("%s: exit %d\n%s%s" % (" ".join(cmd), p.returncode, p.stdout, p.stderr))
    return json.loads(p.stdout)


def main(argv):
    if len(argv) != 4:
        print(__doc__.split("\n")[0], file=sys.stderr)
        return 2
    sim_exe, comlearn_exe, assets = argv[1:]
    port = random.Random(os.getpid()).randrange(20000, 60000)
    url = "udpm://239.255.76.67:%d?ttl=0" % port
    sim = subprocess.Popen([sim_exe, "--lcm-url", url, "-q"])
    failures = 0
    try:
        time.sleep(0.3)
        for rock in ROCKS:
            urdf = os.path.join(assets, "rocks", rock + ".urdf")
            com = true_com(urdf)
            for dx, expected in ((OFFSET_M, "stays"), (-OFFSET_M, "tips")):
                point = "%.9f,%.9f,%.9f" % (1000 * (com[0] + dx), 1000 * com[1], 1000 * com[2])
                trial = run([sys.executable, EXAMPLE, urdf, "--lcm-url", url, "--comlearn",
                             comlearn_exe, "--point-mm=" + point, "--json"])
                plan = run([comlearn_exe, "plan", urdf, "--point-mm=" + point, "--simulate", "--json"])
                sim_in_b = plan["simulated"]["settled_in_block"]
                block = plan["block_in_world"]["position_m"]
                got = [w - b for w, b in zip(trial["settled_world"]["position_m"], block)]
                err = max(abs(g - s) for g, s in zip(got, sim_in_b["position_m"]))
                rot = quat_angle(trial["settled_world"]["orientation_wxyz"], sim_in_b["orientation_wxyz"])
                ok = (trial["outcome"] == expected and plan["simulated"]["outcome"] == expected
                      and err <= TOL_M and rot <= TOL_M)
                print("%s %s point x = CoM %+.0f mm: over LCM %s, in-process %s, expected %s; "
                      "settled poses differ by %.2e m, %.2e rad"
                      % ("ok  " if ok else "FAIL", rock, 1000 * dx, trial["outcome"],
                         plan["simulated"]["outcome"], expected, err, rot))
                failures += not ok
    finally:
        sim.terminate()
        try:
            rc = sim.wait(timeout=10)
        except subprocess.TimeoutExpired:
            sim.kill()
            rc = "killed"
    if rc != 0:
        print("FAIL comlearn-sim did not exit 0 on SIGTERM: %s" % rc)
        failures += 1
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
