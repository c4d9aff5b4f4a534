#!/usr/bin/env python3
"""Cross-check lib/balance's edge-trial verdicts against MuJoCo (docs/physics.md, "Cross-check
with MuJoCo").

Reads the JSON lines of bench/placements_dump (objects with their URDF truth, lines = object x
stable face x yaw, placements = release poses with lib/balance's verdict), replays every placement
in MuJoCo, bisects each line's threshold in MuJoCo with the same bracket and midpoints as
placements_dump, and prints per class: placements, agreement of the verdicts (STAYS / TIPS /
SLIDES / INVALID), and per line both thresholds and their difference. Bench only: never a build
or test dependency of comlearn.

MuJoCo model (documented in docs/physics.md):
  - B: a box geom of the dump's size, top at z = 0; the object: one mesh geom from the URDF's STL
    on a free joint, mass / CoM / full inertia from the URDF (inertiafromgeom off). MuJoCo collides
    a mesh by its CONVEX HULL (no convex decomposition here): each placement is tagged
    `comparable` when the hull and the mesh touch B's +X edge line alike (see hull_check).
  - dt 1e-4, gravity from the dump, Newton solver (tolerance 1e-10, 200 iterations), pyramidal
    cone, condim 3, friction = the dump's (lib/balance's) mu, no torsional or rolling friction,
    solref (2e-4, 1) (time constant = 2 dt, the smallest MuJoCo accepts, critically damped),
    solimp (0.99, 0.999, 1e-4, 0.5, 2), margin 0, ccd tolerance 1e-10; multi-contact convex
    collision as MuJoCo's default.
  - Release: the dump's pose (link frame = body frame; 1 um pre-penetrated, as lib/balance), at
    rest; --lift raises it (1e-6: exactly touching). The rules of lib/balance/src/trial.c are
    evaluated every 1 ms (every 10 MuJoCo steps), i.e. at lib/balance's step, with its step
    counts (rest 10, grow 20, minimum rest time 0.03 s, horizon 0.75 s) and thresholds, with one
    change: |w| counts as growing only above 1e-8 rad/s (--grow-floor; lib/balance: 1e-11, ODE's
    rounding noise), since a body resting in MuJoCo creeps at a steady 1e-12 to 1e-10 rad/s whose
    rounding flicker would reset the rest count forever.
  - The release pose is recomputed here (pose_over_edge, a port of model_pose_over_edge) for the
    bisection and checked against every dumped pose (a warning above 0.1 um).
Usage: see --help.
"""
import argparse
import json
import math
import sys
import time

import numpy as np

try:
    import mujoco
    import trimesh
except ImportError as exc:  # pragma: no cover - bench-only dependencies
    sys.exit(f"mujoco_crosscheck: {exc}: run in the venv of bench/README.md "
             "(pip install mujoco trimesh)")

SUBSTEPS_DEFAULT = 10  # MuJoCo steps per lib/balance step (1 ms / 0.1 ms)


def quat_to_rot(q):
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
        [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
        [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)],
    ])


def quat_angle(a, b):
    """Angle between two orientations, as comlearn's cl_quat_angle: 2 atan2(|v|, |w|) of a^-1 b."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    w = aw * bw + ax * bx + ay * by + az * bz
    v = np.array([aw * bx - ax * bw - ay * bz + az * by,
                  aw * by + ax * bz - ay * bw - az * bx,
                  aw * bz - ax * by + ay * bx - az * bw])
    return 2.0 * math.atan2(np.linalg.norm(v), abs(w))


# ---- geometry: the release pose (model_pose_over_edge) and the edge-line profiles ------------


class Shape:
    """The object's mesh (link frame, as stored in the STL: what lib/balance collides) and the
    convex hull MuJoCo collides it by (MuJoCo's own, from the model's mesh graph, in the link
    frame)."""

    def __init__(self, stl_path, m):
        mesh = trimesh.load(stl_path, force="mesh")
        self.v = np.asarray(mesh.vertices, dtype=float)
        self.f = np.asarray(mesh.faces, dtype=np.int64)
        self.edges = np.asarray(mesh.edges_unique, dtype=np.int64)
        g = m.mesh_graph[m.mesh_graphadr[0]:]
        nv, nf = int(g[0]), int(g[1])
        faces = np.asarray(g[2 + 3 * nv + 3 * nf:2 + 3 * nv + 6 * nf], dtype=np.int64)
        gid = m.geom("mesh").id
        r = quat_to_rot(np.asarray(m.geom_quat[gid], dtype=float))
        start, count = m.mesh_vertadr[0], m.mesh_vertnum[0]
        verts = np.asarray(m.mesh_vert[start:start + count], dtype=float) @ r.T + m.geom_pos[gid]
        used = np.unique(faces)
        remap = np.full(count, -1, dtype=np.int64)
        remap[used] = np.arange(len(used))
        self.hv = verts[used]
        self.hf = remap[faces.reshape(-1, 3)]


def lowest_over_rect(vw, edges, hx, hy):
    """Lowest z of a mesh (world vertices vw, unique edges) over |x| <= hx, |y| <= hy: vertices
    inside, edge crossings of the four side lines (B's corners, never under an object here, are
    not visited). None when nothing is over it."""
    best = math.inf
    inside = (np.abs(vw[:, 0]) <= hx) & (np.abs(vw[:, 1]) <= hy)
    if inside.any():
        best = vw[inside, 2].min()
    p, q = vw[edges[:, 0]], vw[edges[:, 1]]
    for axis, c, half in ((0, hx, hy), (0, -hx, hy), (1, hy, hx), (1, -hy, hx)):
        dp, dq = p[:, axis] - c, q[:, axis] - c
        cross = ~(((dp > 0) & (dq > 0)) | ((dp < 0) & (dq < 0)) | (dp == dq))
        if not cross.any():
            continue
        t = dp[cross] / (dp[cross] - dq[cross])
        other = 1 - axis
        u = p[cross, other] + t * (q[cross, other] - p[cross, other])
        z = p[cross, 2] + t * (q[cross, 2] - p[cross, 2])
        ok = np.abs(u) <= half
        if ok.any():
            best = min(best, z[ok].min())
    return None if best == math.inf else best


def pose_over_edge(shape, q, point_link, base, depth):
    """comlearn's model_pose_over_edge for B's +X edge, along 0 (lib/model/src/support_place.c)."""
    hx, hy = 0.5 * base[0], 0.5 * base[1]
    q = np.asarray(q, dtype=float)
    q = q / np.linalg.norm(q)
    r = quat_to_rot(q)
    rp = r @ point_link
    pos = np.array([hx - rp[0], -rp[1], 0.0])
    vr = shape.v @ r.T
    pos[2] = -vr[:, 2].min() - depth
    vw = vr + pos
    on_top = (vw[:, 2] <= -depth + 1e-6) & (np.abs(vw[:, 0]) <= hx) & (np.abs(vw[:, 1]) <= hy)
    if not on_top.any():
        zlow = lowest_over_rect(vr + np.array([pos[0], pos[1], 0.0]), shape.edges, hx, hy)
        if zlow is None:
            raise ValueError("no part of the mesh over B")
        pos[2] = -zlow - depth
    return pos, q


def edge_profile(vw, faces, hx, ys):
    """Lowest z of the surface (world vertices vw, triangles) on the vertical plane x = hx at
    each y of ys; inf where the plane does not meet it."""
    tri = vw[faces]  # (T, 3, 3)
    dx = tri[:, :, 0] - hx
    sel = (dx.min(axis=1) <= 0) & (dx.max(axis=1) >= 0)
    tri, dx = tri[sel], dx[sel]
    segs = []
    for a, b in ((0, 1), (1, 2), (2, 0)):
        da, db = dx[:, a], dx[:, b]
        ok = (da * db <= 0) & (da != db)
        t = np.where(ok, da / np.where(ok, da - db, 1.0), 0.0)
        pt = tri[:, a] + t[:, None] * (tri[:, b] - tri[:, a])
        segs.append((ok, pt))
    z = np.full(len(ys), math.inf)
    for i in range(3):
        for j in range(i + 1, 3):
            ok = segs[i][0] & segs[j][0]
            if not ok.any():
                continue
            p, s = segs[i][1][ok], segs[j][1][ok]
            y0, y1, z0, z1 = p[:, 1], s[:, 1], p[:, 2], s[:, 2]
            lo, hi = np.minimum(y0, y1), np.maximum(y0, y1)
            for k in range(len(p)):
                # 10 nm of slack at the ends: MuJoCo's hull vertices are float32 copies
                m = (ys >= lo[k] - 1e-8) & (ys <= hi[k] + 1e-8)
                if not m.any():
                    continue
                dy = y1[k] - y0[k]
                frac = np.clip((ys[m] - y0[k]) / dy, 0.0, 1.0) if abs(dy) >= 1e-12 else None
                zz = (np.full(m.sum(), min(z0[k], z1[k])) if frac is None
                      else z0[k] + frac * (z1[k] - z0[k]))
                z[m] = np.minimum(z[m], zz)
    return z


def hull_check(shape, pos, q, base, band=5e-4, tol=1e-5, step=5e-5):
    """Does B's +X edge line meet the convex hull (what MuJoCo collides) as it meets the mesh
    (what lib/balance collides)? On the plane x = sx/2, wherever the hull's profile is within
    `band` of its lowest point, the mesh's profile must be within `tol` of it; exception: inside
    the hull's chord (the hull touching the edge line at its lowest point, which is at B's top
    within 2 um) when the mesh touches the line at both ends of that chord (a line through both
    feet or a ring's hole: the same support, since the object rests on the hull of its contact).
    Returns (comparable, worst gap m, hull's lowest point over B minus the mesh's, m)."""
    hx, hy = 0.5 * base[0], 0.5 * base[1]
    r = quat_to_rot(np.asarray(q, dtype=float))
    vw, hw = shape.v @ r.T + pos, shape.hv @ r.T + pos
    ys = np.arange(vw[:, 1].min() - step, vw[:, 1].max() + 2 * step, step)
    zm = edge_profile(vw, shape.f, hx, ys)
    zh = edge_profile(hw, shape.hf, hx, ys)
    low_m = lowest_over_rect(vw, shape.edges, hx, hy)
    hull_edges = np.unique(np.sort(np.vstack([shape.hf[:, [0, 1]], shape.hf[:, [1, 2]],
                                              shape.hf[:, [2, 0]]]), axis=1), axis=0)
    low_h = lowest_over_rect(hw, hull_edges, hx, hy)
    release_gap = (low_h - low_m) if low_m is not None and low_h is not None else math.nan
    if not np.isfinite(zh).any():
        return True, 0.0, release_gap
    zmin = zh[np.isfinite(zh)].min()
    near = np.isfinite(zh) & (zh <= zmin + band)
    gap = np.zeros(len(ys))
    gap[near] = zm[near] - zh[near]  # inf where the mesh does not meet the line there
    if zmin <= 2e-6:
        chord = np.flatnonzero(np.isfinite(zh) & (zh <= zmin + 2e-6))
        c0, c1 = chord[0], chord[-1]
        ends_touch = gap[c0] <= tol and gap[c1] <= tol
        if ends_touch and c1 > c0 + 1:
            gap[c0 + 1:c1] = 0.0
    worst = float(gap.max())
    return worst <= tol and abs(release_gap) <= 2e-6, worst, release_gap


# ---- MuJoCo -------------------------------------------------------------------------------


def base_geoms(cfg, strip):
    """B: one box geom, or (strip > 0) the same solid as two boxes, a strip `strip` wide along
    the +X edge and the rest. MuJoCo keeps at most a few contacts per geom pair (4 measured for a
    face on a face); the strip gives the edge line its own pair."""
    sx, sy, sz = cfg["base_size_m"]
    if strip <= 0:
        return (f'    <geom name="B" type="box" size="{sx / 2!r} {sy / 2!r} {sz / 2!r}" '
                f'pos="0 0 {-sz / 2!r}"/>')
    rest = sx - strip
    return (f'    <geom name="B" type="box" size="{rest / 2!r} {sy / 2!r} {sz / 2!r}" '
            f'pos="{-sx / 2 + rest / 2!r} 0 {-sz / 2!r}"/>\n'
            f'    <geom name="B_edge" type="box" size="{strip / 2!r} {sy / 2!r} {sz / 2!r}" '
            f'pos="{sx / 2 - strip / 2!r} 0 {-sz / 2!r}"/>')


def mjcf(obj, cfg, args):
    sx, sy, sz = cfg["base_size_m"]
    i = [[float(x) for x in obj["inertia_kg_m2"][3 * k:3 * k + 3]] for k in range(3)]
    com = " ".join(repr(c) for c in obj["com_m"])
    return f"""<mujoco model="crosscheck">
  <compiler inertiafromgeom="false"/>
  <option timestep="{args.dt}" gravity="0 0 {-cfg['gravity_m_s2']!r}" cone="pyramidal"
          solver="Newton" tolerance="1e-10" iterations="200" ls_iterations="50"
          ccd_tolerance="1e-10" ccd_iterations="200"/>
  <asset><mesh name="object" file="{obj['mesh']}"/></asset>
  <default>
    <geom condim="3" friction="{cfg['friction']!r} 0 0" solref="{args.solref[0]!r} {args.solref[1]!r}"
          solimp="{' '.join(repr(s) for s in args.solimp)}" margin="0"/>
  </default>
  <worldbody>
{base_geoms(cfg, args.strip)}
    <body name="object">
      <freejoint/>
      <inertial pos="{com}" mass="{obj['mass_kg']!r}"
                fullinertia="{i[0][0]!r} {i[1][1]!r} {i[2][2]!r} {i[0][1]!r} {i[0][2]!r} {i[1][2]!r}"/>
      <geom name="mesh" type="mesh" mesh="object"/>
    </body>
  </worldbody>
</mujoco>"""


class Engine:
    def __init__(self, obj, cfg, args):
        self.m = mujoco.MjModel.from_xml_string(mjcf(obj, cfg, args))
        self.d = mujoco.MjData(self.m)
        self.cfg = cfg
        self.radius = obj["radius_m"]
        self.sub = args.substeps
        self.body = self.m.body("object").id
        self.lift = args.lift
        self.invalid = 0
        self.grow_floor = args.grow_floor
        self.steps = 0

    def trial(self, pos, q):
        """One release at rest; lib/balance's rules (trial.c) every `sub` MuJoCo steps.
        Returns (outcome, rotation_rad, displacement_m, lib/balance-sized steps)."""
        m, d, cfg = self.m, self.d, self.cfg
        pos = np.asarray(pos, dtype=float) + np.array([0.0, 0.0, self.lift])
        hx, hy = 0.5 * cfg["base_size_m"][0], 0.5 * cfg["base_size_m"][1]
        mujoco.mj_resetData(m, d)
        d.qpos[:3], d.qpos[3:7] = pos, q
        mujoco.mj_forward(m, d)
        q0, p0, com0 = np.array(q), np.array(pos), d.xipos[self.body].copy()
        max_steps = math.ceil(cfg["horizon_s"] / cfg["dt_s"] - 1e-9)
        min_rest = math.ceil(cfg["rest_min_time_s"] / cfg["dt_s"] - 1e-9)
        om_prev, quiet, grow, outcome, n = math.inf, 0, 0, "INVALID", 0
        while n < max_steps:
            mujoco.mj_step(m, d, nstep=self.sub)
            n += 1
            com = d.xipos[self.body]
            rot = quat_angle(q0, d.xquat[self.body])
            w = d.xmat[self.body].reshape(3, 3) @ d.qvel[3:6]
            v = d.qvel[0:3] + np.cross(w, com - d.xpos[self.body])
            wn, vn = float(np.linalg.norm(w)), float(np.linalg.norm(v))
            if not (np.isfinite(wn) and np.isfinite(vn)):
                outcome = "DIVERGED"
                break
            beyond = abs(com[0]) > hx or abs(com[1]) > hy
            if (rot > cfg["tip_angle_rad"] or com[2] < 0.0 or abs(com[0]) > hx + self.radius
                    or abs(com[1]) > hy + self.radius):
                outcome = "TIPS"
                break
            if (math.hypot(com[0] - com0[0], com[1] - com0[1]) > cfg["slide_m"]
                    and rot < 0.25 * cfg["tip_angle_rad"]):
                outcome = "SLIDES"
                break
            growing = wn > om_prev and wn > self.grow_floor
            grow = grow + 1 if growing else 0
            if beyond and grow >= cfg["tip_grow_steps"]:
                outcome = "TIPS"
                break
            quiet = quiet + 1 if (vn < cfg["rest_lin_m_s"] and wn < cfg["rest_ang_rad_s"]
                                  and not growing) else 0
            om_prev = wn
            if n >= min_rest and quiet >= cfg["rest_steps"]:
                outcome = "STAYS"
                break
        self.steps += n * self.sub
        self.invalid += outcome == "INVALID"
        rot = quat_angle(q0, d.xquat[self.body])
        return outcome, rot, float(np.linalg.norm(d.xpos[self.body] - p0)), n


# ---- the cross-check ----------------------------------------------------------------------


def load_dump(path):
    cfg, objs, lines, places = None, {}, {}, []
    with open(path) as f:
        for row in f:
            r = json.loads(row)
            if r["type"] == "config":
                cfg = r
            elif r["type"] == "object":
                objs[r["object"]] = r
            elif r["type"] == "line":
                lines[r["line"]] = r
            else:
                places.append(r)
    return cfg, objs, lines, places


def class_of(obj):
    return obj["name"].split("_")[0]


def release(shape, line, obj, cfg, dist):
    p = np.array(obj["com_m"]) + dist * np.array(line["u_link"])
    return pose_over_edge(shape, line["orientation_wxyz"], p, cfg["base_size_m"],
                          cfg["touch_depth_m"])


def bisect(eng, shape, line, obj, cfg, stays_or_moving):
    """MuJoCo's threshold: the same bracket, midpoints and rule as placements_dump's dump_bisect
    (stays_or_moving: INVALID counts as staying, the tip threshold)."""
    lo, hi = line["bracket_m"]
    ok = ("STAYS", "INVALID") if stays_or_moving else ("STAYS",)

    def stays(x):
        pos, q = release(shape, line, obj, cfg, x)
        return eng.trial(pos, q)[0] in ok

    if stays(lo) or not stays(hi):
        return math.nan
    for _ in range(60):
        if hi - lo <= cfg["resolution_m"]:
            break
        mid = 0.5 * (lo + hi)
        if stays(mid):
            hi = mid
        else:
            lo = mid
    return 0.5 * (lo + hi)


def run(args):
    cfg, objs, lines, places = load_dump(args.dump)
    if cfg is None:
        sys.exit("mujoco_crosscheck: no config line in the dump")
    by_obj = {}
    for p in places:
        by_obj.setdefault(p["object"], []).append(p)
    out = open(args.out, "w") if args.out else None
    results, line_res = [], []
    t0 = time.time()
    for oid, obj in sorted(objs.items()):
        if args.classes and class_of(obj) not in args.classes:
            continue
        eng = Engine(obj, cfg, args)
        shape = Shape(obj["mesh"], eng.m)
        for p in by_obj.get(oid, []):
            line = lines[p["line"]]
            pos, q = release(shape, line, obj, cfg, p["d_m"])
            dpos = float(np.abs(pos - np.array(p["release_p"])).max())
            if dpos > 1e-7:
                print(f"mujoco_crosscheck: warning: {obj['name']} line {p['line']} d {p['d_m']}: "
                      f"release differs from lib/balance's by {dpos:.3g} m", file=sys.stderr)
            pos, q = np.array(p["release_p"]), np.array(p["release_q"])
            outcome, rot, disp, n = eng.trial(pos, q)
            comp, gap, rgap = hull_check(shape, pos, q, cfg["base_size_m"])
            res = dict(object=oid, name=obj["name"], cls=class_of(obj), line=p["line"],
                       kind=p["kind"], d_m=p["d_m"], balance=p["outcome"],
                       balance_rotation_rad=p["rotation_rad"], mujoco=outcome,
                       mujoco_rotation_rad=rot, mujoco_displacement_m=disp, mujoco_steps=n,
                       comparable=bool(comp), hull_gap_m=gap, hull_release_gap_m=rgap)
            results.append(res)
            if out:
                out.write(json.dumps(dict(type="placement", **res)) + "\n")
        for lid, line in sorted(lines.items()):
            if line["object"] != oid:
                continue
            inv0 = eng.invalid
            th_m = bisect(eng, shape, line, obj, cfg, False)
            inv = eng.invalid - inv0
            tip_m = bisect(eng, shape, line, obj, cfg, True)
            th_b = line["threshold_m"]
            comp = None
            if th_b is not None and math.isfinite(th_b):
                pos, q = release(shape, line, obj, cfg, th_b)
                comp = bool(hull_check(shape, pos, q, cfg["base_size_m"])[0])
            lr = dict(object=oid, name=obj["name"], cls=class_of(obj), line=lid,
                      face=line["face"], flat=line["flat"], yaw_deg=math.degrees(line["yaw_rad"]),
                      com_margin_m=line["com_margin_m"], balance_threshold_m=th_b,
                      mujoco_threshold_m=th_m, mujoco_bisect_invalid=inv,
                      balance_tip_threshold_m=line["tip_threshold_m"],
                      mujoco_tip_threshold_m=tip_m,
                      comparable_at_threshold=comp)
            line_res.append(lr)
            if out:
                out.write(json.dumps(dict(type="line", **lr)) + "\n")
        print(f"mujoco_crosscheck: {obj['name']}: {time.time() - t0:.0f} s, "
              f"{eng.steps} MuJoCo steps", file=sys.stderr)
    if out:
        out.close()
    report(results, line_res, args)


def pct(a, b):
    return f"{100.0 * a / b:.1f}" if b else "-"


def report(results, line_res, args):
    classes = sorted({r["cls"] for r in results} | {r["cls"] for r in line_res})
    print("| class | objects | lines | placements | agree % | comparable | agree % (comparable) "
          "| near threshold (dense) agree % | far (uniform) agree % | disagreements (lib/balance "
          "-> MuJoCo) | STAYS rotated > 0.01 rad, lib/balance / MuJoCo |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for c in classes:
        rs = [r for r in results if r["cls"] == c]
        ag = [r for r in rs if r["balance"] == r["mujoco"]]
        cp = [r for r in rs if r["comparable"]]
        cpa = [r for r in cp if r["balance"] == r["mujoco"]]
        de = [r for r in rs if r["kind"] == "dense"]
        un = [r for r in rs if r["kind"] == "uniform"]
        dis = {}
        for r in rs:
            if r["balance"] != r["mujoco"]:
                k = f"{r['balance']}->{r['mujoco']}"
                dis[k] = dis.get(k, 0) + 1
        nobj = len({r["object"] for r in rs})
        nl = len([r for r in line_res if r["cls"] == c])
        print(f"| {c} | {nobj} | {nl} | {len(rs)} | {pct(len(ag), len(rs))} | {len(cp)} | "
              f"{pct(len(cpa), len(cp))} | "
              f"{pct(sum(r['balance'] == r['mujoco'] for r in de), len(de))} | "
              f"{pct(sum(r['balance'] == r['mujoco'] for r in un), len(un))} | "
              f"{', '.join(f'{k} {v}' for k, v in sorted(dis.items())) or '-'} | "
              f"{_pivoted(rs, 'balance')} / {_pivoted(rs, 'mujoco')} |")
    print()
    print("| class | lines | stay threshold: both bisected | median / max abs diff um "
          "| comparable: lines, median / max um | tip threshold: both bisected "
          "| median / max abs diff um | comparable: lines, median / max um "
          "| lines with INVALID in MuJoCo's stay bisection |")
    print("|---|---|---|---|---|---|---|---|---|")
    for c in classes:
        ls = [r for r in line_res if r["cls"] == c]
        cells = []
        for kb, km in (("balance_threshold_m", "mujoco_threshold_m"),
                       ("balance_tip_threshold_m", "mujoco_tip_threshold_m")):
            both = [r for r in ls if _fin(r[kb]) and _fin(r[km])]
            d = sorted(abs(r[km] - r[kb]) * 1e6 for r in both)
            dc = sorted(abs(r[km] - r[kb]) * 1e6 for r in both if r["comparable_at_threshold"])
            cells += [str(len(both)), f"{_med(d)} / {_max(d)}",
                      f"{len(dc)}, {_med(dc)} / {_max(dc)}"]
        inv = sum(r["mujoco_bisect_invalid"] > 0 for r in ls)
        print(f"| {c} | {len(ls)} | {' | '.join(cells)} | {inv} |")
    if args.lines:
        print()
        print("| object | face | flat | yaw deg | CoM margin mm | lib/balance threshold um "
              "| MuJoCo threshold um | diff um | tip threshold um, lib/balance / MuJoCo "
              "| diff um | hull = mesh at the edge | MuJoCo INVALID in stay bisection |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|")
        for r in line_res:
            tb, tm = r["balance_threshold_m"], r["mujoco_threshold_m"]
            diff = f"{(tm - tb) * 1e6:+.1f}" if _fin(tb) and _fin(tm) else "-"
            pb, pm = r["balance_tip_threshold_m"], r["mujoco_tip_threshold_m"]
            pdiff = f"{(pm - pb) * 1e6:+.1f}" if _fin(pb) and _fin(pm) else "-"
            ca = r["comparable_at_threshold"]
            comp = "-" if ca is None else ("yes" if ca else "no")
            print(f"| {r['name']} | {r['face']} | {'yes' if r['flat'] else 'no'} | "
                  f"{r['yaw_deg']:.0f} | {r['com_margin_m'] * 1e3:.2f} | {_um(tb)} | {_um(tm)} | "
                  f"{diff} | {_um(pb)} / {_um(pm)} | {pdiff} | {comp} | "
                  f"{r['mujoco_bisect_invalid']} |")


def _pivoted(rs, engine):
    return sum(r[engine] == "STAYS" and r[f"{engine}_rotation_rad"] > 0.01 for r in rs)


def _fin(x):
    return x is not None and math.isfinite(x)


def _um(x):
    return f"{x * 1e6:.1f}" if _fin(x) else "none"


def _med(v):
    return f"{float(np.median(v)):.1f}" if v else "-"


def _max(v):
    return f"{max(v):.1f}" if v else "-"


def main():
    ap = argparse.ArgumentParser(
        description="Replay placements_dump's edge placements in MuJoCo (convex hull collision, "
                    "dt 1e-4, stiff contact) and compare verdicts and bisected thresholds with "
                    "lib/balance. Prints markdown tables to stdout.")
    ap.add_argument("dump", help="JSON lines written by placements_dump")
    ap.add_argument("--out", help="also write per-placement and per-line JSON lines here "
                                  "(default: none)")
    ap.add_argument("--dt", type=float, default=1e-4, help="MuJoCo time step, s (default 1e-4)")
    ap.add_argument("--substeps", type=int, default=SUBSTEPS_DEFAULT,
                    help="MuJoCo steps per lib/balance step: the rules run every dt * substeps "
                         "(default 10: every 1 ms at dt 1e-4)")
    ap.add_argument("--solref", type=float, nargs=2, default=[2e-4, 1.0],
                    help="contact solref: time constant s, damping ratio (default 2e-4 1)")
    ap.add_argument("--solimp", type=float, nargs=5, default=[0.99, 0.999, 1e-4, 0.5, 2.0],
                    help="contact solimp (default 0.99 0.999 1e-4 0.5 2)")
    ap.add_argument("--grow-floor", type=float, default=1e-8,
                    help="|w| below this never counts as growing, rad/s (lib/balance: 1e-11, "
                         "ODE's rounding noise; MuJoCo's resting bodies creep at ~1e-10; "
                         "default 1e-8)")
    ap.add_argument("--lift", type=float, default=0.0,
                    help="release this much higher than lib/balance's pose, m (default 0: the "
                         "same pose, 1 um pre-penetrated; 1e-6: exactly touching)")
    ap.add_argument("--strip", type=float, default=0.0,
                    help="build B as two boxes, one a strip this wide along the +X edge, m "
                         "(default 0: one box)")
    ap.add_argument("--classes", nargs="*", help="only these classes (name prefix; default all)")
    ap.add_argument("--lines", action="store_true", help="also print the per-line table")
    args = ap.parse_args()
    run(args)


if __name__ == "__main__":
    main()
