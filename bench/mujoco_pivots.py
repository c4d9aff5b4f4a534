#!/usr/bin/env python3
"""Cross-check lib/balance's pivot trials against MuJoCo (docs/physics.md, "Pivots: a knife
edge"; lib/estimate's pivot searches, docs/estimate.md "Pivots").

Reads the JSON lines of `bench_pivot --dump FILE` (objects with their URDF truth, pivots = hull
edges planned for the true CoM with their geometry and lib/balance's bisected bracket,
placements = release poses at the truth +- 1 .. 300 um with lib/balance's outcome and what the
estimator counts it as) and replays every placement in MuJoCo with the model and trial rules of
bench/mujoco_crosscheck.py (imported: dt 1e-4, stiff contact, lib/balance's rules every 1 ms).
Each MuJoCo trial is read as the estimator reads a pivot trial (a port of
estimate_pivot_outcome: the turn about the edge line from the released to the settled pose).
MuJoCo collides the mesh by its convex hull; a pivot touches B only along a hull edge, so hull
and mesh meet B alike. Here the object touches B through two spheres (--sphere r, default 2 um) centred on its edge's
ends, released r higher (PivotEngine): at B's sharp corner MuJoCo's convex collision of the
object's hull takes the object's face normal for the contact (an edge on an edge has none) and
pushes the object off the edge, whatever B's corner is made of (a box, a capsule of a few um);
a sphere on the corner has the normal from the corner to its centre, vertical at release. This
checks the dynamics of the pivot (the turn about the line through two contact points, with
friction and soft contact, under lib/balance's trial rules); that nothing else of the object
touches B is geometry (estimate_pivot_plan's wedge, lib/balance's own contacts). Prints per class: placements, agreement of the counted outcomes, and
per pivot the threshold each engine's placements bracket (the truth is 0: the CoM straight over
the edge) and, with --bisect, MuJoCo's threshold bisected to --resolution. Bench only: never a
build or test dependency of comlearn.
"""
import argparse
import json
import math
import os
import sys
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import mujoco_crosscheck as mc  # noqa: E402  (the same engine and rules)

TURN_RAD = 1e-2  # lib/estimate/src/pivot.c PIVOT_TURN_RAD


def counted(outcome, q_rel, q_set):
    """estimate_pivot_outcome: TIPS (off), STAYS (back onto B) or INVALID, from the turn about
    world +y between the released and settled orientations (w, x, y, z)."""
    aw, ax, ay, az = q_rel
    qc = np.array([aw, -ax, -ay, -az])
    bw, bx, by, bz = q_set
    cw, cx, cy, cz = qc
    dq = np.array([bw * cw - bx * cx - by * cy - bz * cz,
                   bw * cx + bx * cw + by * cz - bz * cy,
                   bw * cy - bx * cz + by * cw + bz * cx,
                   bw * cz + bx * cy - by * cx + bz * cw])
    vn = float(np.linalg.norm(dq[1:]))
    rot = 2.0 * math.atan2(vn, abs(dq[0]))
    turn = rot * dq[2] / vn * (-1.0 if dq[0] < 0 else 1.0) if vn > 0 else 0.0
    if (outcome == "TIPS" and rot <= TURN_RAD) or (rot > TURN_RAD and turn >= 0.5 * rot):
        return "TIPS"
    if turn <= -TURN_RAD and turn <= -0.5 * rot:
        return "STAYS"
    return "INVALID"


def pivot_pose(shape, pv, x, cfg):
    """estimate_pivot_pose: tilted about the edge for x, the midpoint over the +X edge line,
    lowered until the lowest point over B's top is touch_depth deep. None if that is not the
    edge."""
    u, up, e = (np.array(pv[k]) for k in ("u", "up", "e"))
    beta = math.atan((pv["gx_m"] - x) / pv["h_m"])
    c, s = math.cos(beta), math.sin(beta)
    r = np.array([c * u + s * up, e, c * up - s * u])
    q = mc_quat_from_rot(r)
    hx, hy = 0.5 * cfg["base_size_m"][0], 0.5 * cfg["base_size_m"][1]
    m = r @ np.array(pv["mid_m"])
    pos = np.array([hx - m[0], -m[1], 0.0])
    vr = shape.v @ r.T + pos
    low = mc.lowest_over_rect(vr, shape.edges, hx, hy)
    if low is None:
        return None
    pos[2] = -cfg["touch_depth_m"] - low
    for end in ("p1_m", "p2_m"):
        if abs((r @ np.array(pv[end]))[2] + pos[2] + cfg["touch_depth_m"]) > 1e-8:
            return None
    return pos, q


def mc_quat_from_rot(r):
    """A unit quaternion (w, x, y, z) of rotation matrix r (Shepperd)."""
    t = np.trace(r)
    if t > 0:
        s = 2.0 * math.sqrt(t + 1.0)
        q = [0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
    else:
        i = int(np.argmax(np.diag(r)))
        j, k = (i + 1) % 3, (i + 2) % 3
        s = 2.0 * math.sqrt(1.0 + r[i, i] - r[j, j] - r[k, k])
        q = [0.0, 0.0, 0.0, 0.0]
        q[0] = (r[k, j] - r[j, k]) / s
        q[1 + i] = 0.25 * s
        q[1 + j] = (r[j, i] + r[i, j]) / s
        q[1 + k] = (r[k, i] + r[i, k]) / s
    q = np.array(q)
    return q / np.linalg.norm(q)


class PivotEngine(mc.Engine):
    """mujoco_crosscheck's engine and trial rules for one pivot: the object touches B through two
    spheres of radius r centred on its edge's ends, its mesh kept for nothing but its inertia
    (no collision). Released r higher, so that the spheres' lowest points are where lib/balance
    put the ends (1 um deep in B's top): a sphere meets B's corner with a normal from the corner
    to its centre, vertical at release, where a mesh edge on B's edge has no normal (MuJoCo's
    convex collision took the object's face normal and pushed it off the edge)."""

    def __init__(self, obj, cfg, args, pv):
        r = args.sphere
        xml = mc.mjcf(obj, cfg, args)
        mesh = '<geom name="mesh" type="mesh" mesh="object"/>'
        assert mesh in xml, "mujoco_crosscheck.mjcf changed: the object's mesh geom not found"
        spheres = "".join(
            f'\n      <geom name="{k}" type="sphere" size="{r!r}" '
            f'pos="{" ".join(repr(float(c)) for c in pv[k])}"/>' for k in ("p1_m", "p2_m"))
        xml = xml.replace(mesh, mesh[:-2] + ' contype="0" conaffinity="0"/>' + spheres)
        orig = mc.mjcf
        mc.mjcf = lambda *a: xml
        try:
            super().__init__(obj, cfg, args)
        finally:
            mc.mjcf = orig
        self.r = r

    def trial(self, pos, q):
        return super().trial(np.asarray(pos, dtype=float) + np.array([0.0, 0.0, self.r]), q)


class MeshShape:
    """The object's mesh as lib/balance collides it (link frame): vertices and unique edges, for
    the release pose of a bisection (pivot_pose)."""

    def __init__(self, stl_path):
        mesh = mc.trimesh.load(stl_path, force="mesh")
        self.v = np.asarray(mesh.vertices, dtype=float)
        self.edges = np.asarray(mesh.edges_unique, dtype=np.int64)


def replay(eng, pos, q):
    outcome, rot, _, n = eng.trial(pos, q)
    return outcome, counted(outcome, q, np.array(eng.d.xquat[eng.body])), n


def bracket(rows, truth):
    """The threshold the placements bracket, relative to the truth [um]: between the largest
    offset counted TIPS and the smallest counted STAYS, or None when they contradict."""
    tips = [r[0] for r in rows if r[1] == "TIPS"]
    stays = [r[0] for r in rows if r[1] == "STAYS"]
    lo = max(tips) if tips else -math.inf
    hi = min(stays) if stays else math.inf
    return (1e6 * (lo - truth), 1e6 * (hi - truth)) if lo < hi else None


def bisect(eng, shape, pv, cfg, lo, hi, res):
    """MuJoCo's threshold in x between lo (TIPS) and hi (STAYS): the bracket (lo, hi) where it is
    res wide or a trial is unclear (the CoM within about a micron of the plane); None when a
    pose is not a pivot."""
    for _ in range(60):
        if hi - lo <= res:
            break
        mid = lo + 0.382 * (hi - lo)  # off the middle: the dense offsets straddle the truth
        pose = pivot_pose(shape, pv, mid, cfg)
        if pose is None:
            return None
        c = replay(eng, *pose)[1]
        if c == "TIPS":
            lo = mid
        elif c == "STAYS":
            hi = mid
        else:
            break
    return lo, hi


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dump", help="JSON lines of bench_pivot --dump")
    ap.add_argument("--dt", type=float, default=1e-4)
    ap.add_argument("--substeps", type=int, default=mc.SUBSTEPS_DEFAULT)
    ap.add_argument("--solref", type=float, nargs=2, default=[2e-4, 1.0])
    ap.add_argument("--solimp", type=float, nargs=5, default=[0.99, 0.999, 1e-4, 0.5, 2])
    ap.add_argument("--grow-floor", type=float, default=1e-8)
    ap.add_argument("--lift", type=float, default=0.0)
    ap.add_argument("--strip", type=float, default=0.0)
    ap.add_argument("--sphere", type=float, default=2e-6,
                    help="radius of the two spheres at the edge's ends [m] (default 2e-6)")
    ap.add_argument("--bisect", action="store_true",
                    help="also bisect MuJoCo's threshold of every bracketed pivot")
    ap.add_argument("--resolution", type=float, default=1e-7, help="bisection stop [m]")
    ap.add_argument("--out", help="every placement's result as JSON lines")
    args = ap.parse_args()
    cfg, objs, _, rows = mc.load_dump(args.dump)  # pivot and placement lines in rows
    pivots = {(r["object"], r["pivot"]): r for r in rows if r["type"] == "pivot"}
    places = [r for r in rows if r["type"] == "placement"]
    if cfg is None:
        sys.exit("mujoco_pivots: no config line in the dump")
    out = open(args.out, "w") if args.out else None
    by_pivot = {}
    for p in places:
        by_pivot.setdefault((p["object"], p["pivot"]), []).append(p)
    stats, lines, t0 = {}, [], time.time()
    for oid, obj in sorted(objs.items()):
        cls = obj["name"].split("_")[0]
        shape = None
        for (o, pid), pv in sorted(pivots.items()):
            if o != oid or not pv["bracketed"]:
                continue
            eng = PivotEngine(obj, cfg, args, pv)
            if shape is None:
                shape = MeshShape(obj["mesh"])
            rows_b, rows_m = [], []
            for p in by_pivot.get((o, pid), []):
                outcome, c, n = replay(eng, np.array(p["release_p"]), np.array(p["release_q"]))
                st = stats.setdefault(cls, {"n": 0, "agree": 0, "kinds": {}})
                st["n"] += 1
                st["agree"] += c == p["counted"]
                if c != p["counted"]:
                    k = f'{p["counted"]}->{c}'
                    st["kinds"][k] = st["kinds"].get(k, 0) + 1
                rows_b.append((p["x_m"], p["counted"]))
                rows_m.append((p["x_m"], c))
                if out:
                    out.write(json.dumps(dict(object=oid, name=obj["name"], pivot=pid,
                                              x_m=p["x_m"], balance=p["outcome"],
                                              balance_counted=p["counted"], mujoco=outcome,
                                              mujoco_counted=c, mujoco_steps=n)) + "\n")
            truth = pv["truth_x_m"]
            line = dict(cls=cls, name=obj["name"], pivot=pid, side_mm=1e3 * pv["side_m"],
                        balance=bracket(rows_b, truth), mujoco=bracket(rows_m, truth))
            if args.bisect and line["mujoco"] is not None:
                lo = truth + 1e-6 * line["mujoco"][0] if math.isfinite(line["mujoco"][0]) else None
                hi = truth + 1e-6 * line["mujoco"][1] if math.isfinite(line["mujoco"][1]) else None
                t = (bisect(eng, shape, pv, cfg, lo, hi, args.resolution)
                     if lo is not None and hi is not None else None)
                line["mujoco_bisected_um"] = (None if t is None else
                                              (1e6 * (t[0] - truth), 1e6 * (t[1] - truth)))
            lines.append(line)
        print(f"mujoco_pivots: {obj['name']} done ({time.time() - t0:.0f} s)", file=sys.stderr)
    print("| class | placements | counted alike | disagreements |\n|---|---:|---:|---|")
    tot = [0, 0]
    for cls in sorted(stats):
        st = stats[cls]
        tot[0] += st["n"]
        tot[1] += st["agree"]
        kinds = ", ".join(f"{k} {v}" for k, v in sorted(st["kinds"].items())) or "-"
        print(f'| {cls} | {st["n"]} | {st["agree"]} ({100.0 * st["agree"] / st["n"]:.1f} %) | '
              f'{kinds} |')
    if tot[0]:
        print(f"| all | {tot[0]} | {tot[1]} ({100.0 * tot[1] / tot[0]:.1f} %) | |")

    def fmt(b):
        return "contradicts" if b is None else f"[{b[0]:+g}, {b[1]:+g}]"
    print("\n| class | object | pivot | CoM inside the ends (mm) | lib/balance brackets (um) | "
          "MuJoCo brackets (um) |" + (" MuJoCo bisected (um) |" if args.bisect else ""))
    print("|---|---|---:|---:|---|---|" + ("---|" if args.bisect else ""))
    for ln in lines:
        row = (f'| {ln["cls"]} | {ln["name"]} | {ln["pivot"]} | {ln["side_mm"]:.2f} | '
               f'{fmt(ln["balance"])} | {fmt(ln["mujoco"])} |')
        if args.bisect:
            b = ln.get("mujoco_bisected_um")
            row += f' {"-" if b is None else f"[{b[0]:+.3f}, {b[1]:+.3f}]"} |'
        print(row)


if __name__ == "__main__":
    main()
