#!/usr/bin/env python3
"""one_trial.py - one placement of an object on block B, from Python, over LCM.

Loads OBJECT.urdf into the gripper of a running comlearn-sim (or a real cell speaking the same
messages), places it with the link-frame point --point-mm over B's edge, releases it and prints
what happened: stays, tips or slides. The steps are those `comlearn estimate` takes for every
trial over LCM (docs/estimate.md, "The LCM backend"):

  1. YUMI_STATUS and OBJECT_STATE heard: the arms' joints now.
  2. `comlearn plan OBJECT.urdf --q-start <joints> --json`: the release pose, the grasp and the
     waypoints (preplace, place, release, retreat), planned as the estimator plans.
  3. SIM_CONTROL ACTION_LOAD puts the object into the planned arm's gripper; OBJECT_STATE's
     sim_control_seq acknowledges it.
  4. One YUMI_COMMAND per waypoint, each waited for until YUMI_STATUS reports it accepted and
     in position; the object's pose is read at PLACE (before the fingers open).
  5. After the release, OBJECT_STATE until the object is at rest on B (stays) or off B (tips, or
     slides when it left B nearly unrotated), within the outcome horizon; then the retreat.

Run (after `bash scripts/setup.sh`; the package is in the build tree and, after an install, in
Python's path):

  build/default/daemon/comlearn-sim &
  PYTHONPATH=build/default/lcmtypes/gen/python python3 examples/python/one_trial.py \\
      assets/rocks/rock_1_uneven.urdf --comlearn build/default/apps/comlearn/comlearn

It uses LCM's Python module when importable (pip install lcm), else comlearn.udpm.
Exit status: 0 a trial ran, 1 it failed (no simulator, refused, timed out), 2 usage.
"""

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import time

from comlearn import object_state_t, sim_control_t, udpm, yumi_command_t, yumi_status_t

EXPIRE_MARGIN_US = 5_000_000  # as comlearn estimate: beyond the motion's planned time


class TrialError(RuntimeError):
    pass


class Cell:
    """The latest YUMI_STATUS and OBJECT_STATE of one robot, and the two senders."""

    def __init__(self, lc, prefix):
        self.lc = lc
        self.ch = {n: prefix + n for n in ("YUMI_COMMAND", "YUMI_STATUS", "OBJECT_STATE", "SIM_CONTROL")}
        self.st = None
        self.os = None
        self.seq = 0
        self.sc_seq = 0
        lc.subscribe(self.ch["YUMI_STATUS"], self._on_status)
        lc.subscribe(self.ch["OBJECT_STATE"], self._on_object)

    def _on_status(self, _channel, data):
        self.st = yumi_status_t.decode(data)

    def _on_object(self, _channel, data):
        self.os = object_state_t.decode(data)

    def wait(self, pred, timeout_s, what):
        end = time.monotonic() + timeout_s
        while not pred():
            left = end - time.monotonic()
            if left <= 0:
                raise TrialError("no %s within %.1f s" % (what, timeout_s))
            self.lc.handle_timeout(int(min(left, 0.05) * 1000) + 1)

    def load(self, urdf, object_id, plan, timeout_s=0.5, sends=10):
        sc = sim_control_t()
        sc.action = sim_control_t.ACTION_LOAD
        sc.object_id = object_id
        sc.urdf_path = urdf
        sc.arm = plan["arm"]
        sc.link_in_tool_position_m = list(plan["link_in_tool_position_m"])
        sc.link_in_tool_wxyz = list(plan["link_in_tool_wxyz"])
        sc.gripper_width_m = plan["grip_width_m"]
        for _ in range(sends):
            self.sc_seq = max(self.sc_seq, self.os.sim_control_seq) + 1
            sc.seq = self.sc_seq
            sc.utime = int(time.time() * 1e6)
            self.lc.publish(self.ch["SIM_CONTROL"], sc.encode())
            try:
                self.wait(lambda: self.os.sim_control_seq == sc.seq, timeout_s, "acknowledgement")
            except TrialError:
                continue
            if self.os.sim_control_result != object_state_t.SIM_CONTROL_APPLIED:
                raise TrialError("SIM_CONTROL load refused: result %d: %s"
                                 % (self.os.sim_control_result, self.st.error_text))
            return
        raise TrialError("SIM_CONTROL not acknowledged on %s after %d sends (is comlearn-sim "
                         "running on this URL?)" % (self.ch["OBJECT_STATE"], sends))

    def move(self, arm, wp, scale, timeout_s=10.0, sends=10):
        """Send waypoint wp to arm (the other arm held), until it is accepted and reached."""
        for _ in range(sends):
            c = yumi_command_t()
            c.q_commanded_rad = [list(q) for q in self.st.q_measured_rad]
            c.gripper_width_commanded_m = list(self.st.gripper_width_measured_m)
            c.q_commanded_rad[arm] = list(wp["q_rad"])
            c.gripper_width_commanded_m[arm] = wp["gripper_width_m"]
            self.seq = max(self.seq, self.st.last_accepted_seq) + 1
            c.seq = self.seq
            c.utime = int(time.time() * 1e6)
            c.expire_utime = self.st.utime + int(round(wp["duration_s"] / scale * 1e6)) + EXPIRE_MARGIN_US
            c.mode = yumi_command_t.MODE_POSITION
            c.velocity_scale = scale
            self.lc.publish(self.ch["YUMI_COMMAND"], c.encode())
            try:
                self.wait(lambda: self.st.last_accepted_seq >= c.seq, 0.5, "acceptance")
                if self.st.last_accepted_seq != c.seq:
                    continue  # something newer was accepted
                self.wait(lambda: self.st.last_accepted_seq != c.seq or self.st.in_position,
                          timeout_s, "in_position")
                if self.st.last_accepted_seq == c.seq:
                    return
            except TrialError:
                continue
        raise TrialError("%s waypoint not accepted / reached after %d sends (status error %d: %s)"
                         % (wp["kind"], sends, self.st.error_code, self.st.error_text))


def quat_angle(a, b):
    d = abs(sum(x * y for x, y in zip(a, b)))
    return 2.0 * math.acos(min(1.0, d))


def run_trial(args):
    lc = udpm.connect(args.lcm_url)
    cell = Cell(lc, args.channel_prefix)
    cell.wait(lambda: cell.st is not None and cell.os is not None, args.startup_timeout,
              "YUMI_STATUS / OBJECT_STATE on %s (is comlearn-sim running there?)" % args.lcm_url)
    q_start = [q for arm in cell.st.q_measured_rad for q in arm]
    cmd = [args.comlearn, "plan", args.urdf, "--json", "--edge", args.edge,
           "--point-mm", args.point_mm, "--orientation", args.orientation,
           "--q-start", ",".join(repr(q) for q in q_start)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode != 0:
        raise TrialError("comlearn plan failed (exit %d): %s" % (p.returncode, p.stderr.strip()))
    plan = json.loads(p.stdout)
    arm, scale = plan["arm"], plan["velocity_scale"]
    urdf = os.path.abspath(args.urdf)
    object_id = args.object_id or os.path.basename(urdf).rsplit(".urdf", 1)[0]
    cell.load(urdf, object_id, plan)
    released = None
    for wp in plan["waypoints"][:3]:  # preplace, place, release
        cell.move(arm, wp, scale)
        if wp["kind"] == "place":
            t = cell.st.utime  # the object state published on the status's tick
            cell.wait(lambda: cell.os.utime >= t, 0.5, "OBJECT_STATE at the place pose")
            released = (list(cell.os.position_measured_m), list(cell.os.orientation_measured_wxyz))
    # the fingers started to open duration / scale before the release waypoint was reached
    t_release = cell.st.utime - int(round(plan["waypoints"][2]["duration_s"] / scale * 1e6))
    horizon_us = int(round(plan["outcome_horizon_s"] * 1e6)) + 200_000

    def outcome_ready():
        o = cell.os
        return o.utime > t_release and (not o.tracked or not o.on_base or o.at_rest
                                        or o.utime > t_release + horizon_us)

    cell.wait(outcome_ready, args.outcome_timeout, "trial outcome")
    o = cell.os
    if not o.tracked or o.object_id != object_id:
        raise TrialError("%s no longer tracked after the release" % object_id)
    settled = (list(o.position_measured_m), list(o.orientation_measured_wxyz))
    if o.at_rest and o.on_base:
        outcome = "stays"
    elif not o.on_base:
        # lib/balance's slide rule on the link origin (the CoM is unknown), from the plan
        moved = math.hypot(settled[0][0] - released[0][0], settled[0][1] - released[0][1])
        rot = quat_angle(released[1], settled[1])
        slid = moved > plan["slide_m"] and rot < plan["slide_max_rotation_rad"]
        outcome = "slides" if slid else "tips"
    else:
        outcome = "invalid"  # still moving on B past the horizon
    cell.move(arm, plan["waypoints"][3], scale)  # retreat
    return {"object": urdf, "object_id": object_id, "arm": arm, "outcome": outcome,
            "released_world": {"position_m": released[0], "orientation_wxyz": released[1]},
            "settled_world": {"position_m": settled[0], "orientation_wxyz": settled[1]},
            "planned_release_in_block": plan["release_in_block"],
            "transport": type(lc).__module__}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("urdf", metavar="OBJECT.urdf")
    ap.add_argument("--lcm-url", default=udpm.DEFAULT_URL,
                    help="LCM URL of comlearn-sim or the cell (default: %(default)s)")
    ap.add_argument("--channel-prefix", default="",
                    help="the robot's channel prefix, as comlearn-sim --channel-prefix (default: none)")
    ap.add_argument("--comlearn", default=os.environ.get("COMLEARN") or shutil.which("comlearn") or "comlearn",
                    help="the comlearn program, for `comlearn plan` (default: $COMLEARN, else on PATH)")
    ap.add_argument("--point-mm", default="0,0,0",
                    help="link-frame point over the edge, mm (default: %(default)s); write "
                         "--point-mm=-1,0,0 when the first number is negative")
    ap.add_argument("--edge", default="+x", choices=["+x", "-x", "+y", "-y"],
                    help="B's top edge by outward normal (default: %(default)s)")
    ap.add_argument("--orientation", default="1,0,0,0",
                    help="the object's orientation on B, W,X,Y,Z (default: %(default)s)")
    ap.add_argument("--object-id", default="", help="default: the URDF's file name")
    ap.add_argument("--startup-timeout", type=float, default=3.0, help="seconds (default: 3)")
    ap.add_argument("--outcome-timeout", type=float, default=10.0, help="seconds (default: 10)")
    ap.add_argument("--json", action="store_true", help="print the result as JSON")
    ap.add_argument("-V", "--version", action="version", version="one_trial.py (comlearn)")
    args = ap.parse_args(argv)
    if not os.path.isfile(args.urdf):
        ap.error("%s: no such file" % args.urdf)
    try:
        r = run_trial(args)
    except (TrialError, ValueError, OSError) as e:
        print("one_trial.py: error: %s" % e, file=sys.stderr)
        return 1
    if args.json:
        print(json.dumps(r))
    else:
        p = r["settled_world"]["position_m"]
        print("%s: %s (settled at %.4f, %.4f, %.4f m, world)" % (r["object_id"], r["outcome"], *p))
    return 0


if __name__ == "__main__":
    sys.exit(main())
