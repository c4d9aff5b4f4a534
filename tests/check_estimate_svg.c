#define _POSIX_C_SOURCE 200809L
/* check_estimate_svg: `comlearn estimate --svg FILE` as a user runs it, the SVG parsed through the
 * projection its views publish (apps/comlearn/estimate_svg.h): markers and boxes against the
 * --json estimate, the truth only with --truth, the trial panels, a component not found as a
 * band, bad paths; and estimate_svg_write itself on hand-made results (bad input, no component
 * found, fewer trials than panels). */
#include <check.h>
#include <dirent.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "cli_test_util.h"
#include "comlearn/model.h"
#include "estimate_svg.h"
#include "file_test_util.h"

#ifndef COMLEARN_BIN
#error "COMLEARN_BIN must name the comlearn executable"
#endif
#ifndef COMLEARN_SHAPEGEN_BIN
#error "COMLEARN_SHAPEGEN_BIN must name the comlearn-shapegen executable"
#endif

static char tmpdir[256];

static void setup(void) {
  snprintf(tmpdir, sizeof tmpdir, "/tmp/check_estimate_svg.XXXXXX");
  ck_assert_ptr_nonnull(mkdtemp(tmpdir));
}

static void teardown(void) {
  char cmd[512];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", tmpdir);
  ck_assert_int_eq(system(cmd), 0);
}

/* ---- reading the SVG ------------------------------------------------------------------------ */

/* The value of attribute name in the tag at tag (up to its '>') into buf; 0 when it has none. */
static int attr(const char *tag, const char *name, char *buf, size_t size) {
  const char *end = strchr(tag, '>');
  char pat[64];
  snprintf(pat, sizeof pat, " %s=\"", name);
  const char *p = strstr(tag, pat);
  if (!p || !end || p > end) return 0;
  p += strlen(pat);
  const char *q = strchr(p, '"');
  ck_assert_ptr_nonnull(q);
  ck_assert_uint_lt((size_t)(q - p), size);
  memcpy(buf, p, (size_t)(q - p));
  buf[q - p] = '\0';
  return 1;
}

static double attr_num(const char *tag, const char *name) {
  char buf[64], *end;
  ck_assert_msg(attr(tag, name, buf, sizeof buf), "no %s in %.120s", name, tag);
  const double v = strtod(buf, &end);
  ck_assert_msg(end != buf && *end == '\0', "%s=\"%s\" is not a number", name, buf);
  return v;
}

/* The k-th (0-based) <elem ...> tag whose class is cls and, unless NULL, whose data-view is view
 * (or id, for views); NULL when there are fewer. */
static const char *tag_nth(const char *svg, const char *elem, const char *cls, const char *key,
                           const char *val, int k) {
  char open[32], buf[64];
  snprintf(open, sizeof open, "<%s ", elem);
  for (const char *p = strstr(svg, open); p; p = strstr(p + 1, open)) {
    if (!attr(p, "class", buf, sizeof buf) || strcmp(buf, cls) != 0) continue;
    if (key && (!attr(p, key, buf, sizeof buf) || strcmp(buf, val) != 0)) continue;
    if (k-- == 0) return p;
  }
  return NULL;
}

static int tag_count(const char *svg, const char *elem, const char *cls, const char *key,
                     const char *val) {
  int n = 0;
  while (tag_nth(svg, elem, cls, key, val, n)) ++n;
  return n;
}

/* A view's projection (estimate_svg.h): px = ox + s (u - u0), py = oy - s (v - v0), and its
 * frame (the clip rectangle). */
typedef struct {
  int ua, va;
  double s, u0, v0, ox, oy;
  double x, y, w, h;
} proj_t;

static void view_proj(const char *svg, const char *id, proj_t *p) {
  const char *g = tag_nth(svg, "g", "view", "id", id, 0);
  ck_assert_msg(g != NULL, "no view %s", id);
  char u[8], v[8];
  ck_assert(attr(g, "data-u", u, sizeof u) && attr(g, "data-v", v, sizeof v));
  p->ua = u[0] - 'x';
  p->va = v[0] - 'x';
  ck_assert(p->ua >= 0 && p->ua < 3 && p->va >= 0 && p->va < 3 && p->ua != p->va);
  p->s = attr_num(g, "data-px-per-m");
  p->u0 = attr_num(g, "data-u0-m");
  p->v0 = attr_num(g, "data-v0-m");
  p->ox = attr_num(g, "data-ox-px");
  p->oy = attr_num(g, "data-oy-px");
  ck_assert_double_gt(p->s, 0.0);
  char clip[64];
  snprintf(clip, sizeof clip, "<clipPath id=\"clip-%s\"><rect ", id);
  const char *r = strstr(svg, clip);
  ck_assert_ptr_nonnull(r);
  r += strlen(clip) - 6;
  p->x = attr_num(r, "x");
  p->y = attr_num(r, "y");
  p->w = attr_num(r, "width");
  p->h = attr_num(r, "height");
}

/* Back to metres, link frame. */
static double proj_u(const proj_t *p, double px) { return p->u0 + (px - p->ox) / p->s; }
static double proj_v(const proj_t *p, double py) { return p->v0 - (py - p->oy) / p->s; }

/* The circle of class cls in view id maps back to c (link frame) within a pixel. */
static void check_marker(const char *svg, const char *cls, const char *id, const double c[3]) {
  proj_t p;
  view_proj(svg, id, &p);
  const char *m = tag_nth(svg, "circle", cls, "data-view", id, 0);
  ck_assert_msg(m != NULL, "no %s in %s", cls, id);
  ck_assert_msg(tag_nth(svg, "circle", cls, "data-view", id, 1) == NULL, "two %s in %s", cls, id);
  const double du_px = (proj_u(&p, attr_num(m, "cx")) - c[p.ua]) * p.s;
  const double dv_px = (proj_v(&p, attr_num(m, "cy")) - c[p.va]) * p.s;
  ck_assert_msg(fabs(du_px) <= 1.0 && fabs(dv_px) <= 1.0, "%s in %s off by %.3f, %.3f px", cls, id,
                du_px, dv_px);
}

/* The interval rectangle of view id: each found component's edges at com -+ hw within a pixel;
 * a component not found spans the view (data-unbounded names it). */
static void check_interval(const char *svg, const char *id, const double com[3], const double hw[3],
                           const int found[3]) {
  proj_t p;
  view_proj(svg, id, &p);
  const char *r = tag_nth(svg, "rect", "interval", "data-view", id, 0);
  ck_assert_msg(r != NULL, "no interval in %s", id);
  const double x = attr_num(r, "x"), y = attr_num(r, "y");
  const double w = attr_num(r, "width"), h = attr_num(r, "height");
  char unb[8] = "";
  const int has_unb = attr(r, "data-unbounded", unb, sizeof unb);
  const int fu = found[p.ua], fv = found[p.va];
  ck_assert_int_eq(has_unb, !fu || !fv);
  if (has_unb) ck_assert_str_eq(unb, !fu && !fv ? "uv" : (!fu ? "u" : "v"));
  if (fu) {
    ck_assert_double_le(fabs(proj_u(&p, x) - (com[p.ua] - hw[p.ua])) * p.s, 1.0);
    ck_assert_double_le(fabs(proj_u(&p, x + w) - (com[p.ua] + hw[p.ua])) * p.s, 1.0);
  } else { /* a band across the view */
    ck_assert_double_le(fabs(x - p.x), 1e-3);
    ck_assert_double_le(fabs(w - p.w), 1e-3);
  }
  if (fv) {
    ck_assert_double_le(fabs(proj_v(&p, y) - (com[p.va] + hw[p.va])) * p.s, 1.0);
    ck_assert_double_le(fabs(proj_v(&p, y + h) - (com[p.va] - hw[p.va])) * p.s, 1.0);
  } else {
    ck_assert_double_le(fabs(y - p.y), 1e-3);
    ck_assert_double_le(fabs(h - p.h), 1e-3);
  }
}

/* ---- reading the JSON ----------------------------------------------------------------------- */

/* "key": [a, b, c] with null for a non-finite number (INFINITY). */
static void json_vec_null(const char *json, const char *key, double v[3]) {
  char pat[64];
  snprintf(pat, sizeof pat, "\"%s\": [", key);
  const char *p = strstr(json, pat);
  ck_assert_msg(p != NULL, "no %s", key);
  p += strlen(pat);
  for (int k = 0; k < 3; ++k) {
    while (*p == ' ' || *p == ',') ++p;
    if (strncmp(p, "null", 4) == 0) {
      v[k] = INFINITY;
      p += 4;
      continue;
    }
    char *end;
    v[k] = strtod(p, &end);
    ck_assert_msg(end != p, "bad %s", key);
    p = end;
  }
}

static void json_found(const char *json, int found[3]) {
  const char *p = strstr(json, "\"found\": [");
  ck_assert_ptr_nonnull(p);
  p += strlen("\"found\": [");
  for (int k = 0; k < 3; ++k) {
    while (*p == ' ' || *p == ',') ++p;
    found[k] = strncmp(p, "true", 4) == 0;
    ck_assert(found[k] || strncmp(p, "false", 5) == 0);
    p += found[k] ? 4 : 5;
  }
}

/* The JSON without its "wall_s" value (the one field two runs may differ in). */
static void drop_wall(char *json) {
  char *p = strstr(json, "\"wall_s\": ");
  ck_assert_ptr_nonnull(p);
  char *q = p + strlen("\"wall_s\": ");
  while (*q && *q != ',') ++q;
  memmove(p, q, strlen(q) + 1);
}

/* The n-th trial's "kind" and "outcome" in the JSON trial_log. */
static void json_trial(const char *json, int n, char kind[16], char outcome[16]) {
  const char *p = strstr(json, "\"trial_log\": [");
  ck_assert_ptr_nonnull(p);
  for (int i = 0; i <= n; ++i) {
    p = strstr(p + 1, "{\"kind\": \"");
    ck_assert_ptr_nonnull(p);
  }
  ck_assert_int_eq(sscanf(p, "{\"kind\": \"%15[a-z]\"", kind), 1);
  const char *o = strstr(p, "\"outcome\": \"");
  ck_assert_ptr_nonnull(o);
  ck_assert_int_eq(sscanf(o, "\"outcome\": \"%15[a-z]\"", outcome), 1);
}

static const char *const kViews[6] = {"front",      "side",      "top",
                                      "front-zoom", "side-zoom", "top-zoom"};

/* Everything the picture of one --json run must agree with. every_line: each main view draws
 * every edge trial's line (a flat face's lines lie in the mesh's box); 0: each line drawn is a
 * different edge trial's (a round object on its side: its lines lie in a tangent plane, and one
 * far out along it leaves the drawn box and is left out). */
static void check_picture(const char *svg, const char *json, int truth, int every_line) {
  double com[3], hw[3], tr[3];
  int found[3];
  json_vec(json, "com_m", com);
  json_vec_null(json, "halfwidth_m", hw);
  json_found(json, found);
  if (truth) json_vec(json, "truth_m", tr);
  for (int i = 0; i < 6; ++i) {
    check_marker(svg, "com-est", kViews[i], com);
    if (truth)
      check_marker(svg, "com-truth", kViews[i], tr);
    else
      ck_assert_ptr_null(tag_nth(svg, "circle", "com-truth", "data-view", kViews[i], 0));
    check_interval(svg, kViews[i], com, hw, found);
  }
  if (!truth) ck_assert_ptr_null(strstr(svg, "com-truth"));
  /* the trial strip: the first min(8, trials) trials, in order, as the JSON logs them */
  const int trials = (int)json_num(json, "trials");
  const int panels = trials < ESTIMATE_SVG_TRIAL_PANELS ? trials : ESTIMATE_SVG_TRIAL_PANELS;
  ck_assert_int_eq(tag_count(svg, "g", "trial", NULL, NULL), panels);
  for (int i = 0; i < panels; ++i) {
    const char *g = tag_nth(svg, "g", "trial", NULL, NULL, i);
    char kind[16], outcome[16], buf[16];
    json_trial(json, i, kind, outcome);
    ck_assert_int_eq((int)attr_num(g, "data-trial"), i + 1);
    ck_assert(attr(g, "data-kind", buf, sizeof buf));
    ck_assert_str_eq(buf, kind);
    ck_assert(attr(g, "data-outcome", buf, sizeof buf));
    ck_assert_str_eq(buf, outcome);
    /* both poses drawn */
    const char *next = tag_nth(svg, "g", "trial", NULL, NULL, i + 1);
    const char *rel = strstr(g, "class=\"released\""), *set = strstr(g, "class=\"settled\"");
    ck_assert(rel && set && (!next || (rel < next && set < next)));
  }
  /* every edge trial's line in each main view; the confirmed faces outlined in each */
  const int edge = (int)json_num(json, "edge_trials");
  int confirmed = 0;
  for (const char *p = strstr(json, "\"stable\": true"); p; p = strstr(p + 1, "\"stable\": true"))
    ++confirmed;
  for (int i = 0; i < 3; ++i) {
    char id[16];
    snprintf(id, sizeof id, "%s", kViews[i]);
    const char *g = tag_nth(svg, "g", "view", "id", id, 0);
    const char *end = tag_nth(svg, "g", "view", "id", kViews[i + 1], 0);
    ck_assert(g && end && g < end);
    int lines = 0, faces = 0;
    char drawn[1024] = {0};
    for (const char *p = strstr(g, "class=\"edge-line\""); p && p < end;
         p = strstr(p + 1, "class=\"edge-line\"")) {
      const int t = (int)attr_num(p, "data-trial");
      char kind[16], outcome[16];
      ck_assert(t >= 1 && t <= trials && t <= (int)sizeof drawn && !drawn[t - 1]);
      drawn[t - 1] = 1;
      json_trial(json, t - 1, kind, outcome);
      ck_assert_str_ne(kind, "stable");
      ++lines;
    }
    for (const char *p = strstr(g, "class=\"face\""); p && p < end;
         p = strstr(p + 1, "class=\"face\""))
      ++faces;
    if (every_line)
      ck_assert_int_eq(lines, edge);
    else
      ck_assert_int_le(lines, edge);
    ck_assert_int_eq(faces, confirmed);
  }
}

/* ---- the program ---------------------------------------------------------------------------- */

/* comlearn estimate URDF EXTRA --json [--truth] [--svg tmpdir/NAME]: stdout into out, the exit
 * status. */
static int estimate(const char *urdf, const char *extra, int truth, const char *svg_name, char *out,
                    size_t size) {
  char cmd[2048], svg[512] = "";
  if (svg_name) snprintf(svg, sizeof svg, " --svg '%s/%s'", tmpdir, svg_name);
  snprintf(cmd, sizeof cmd, "'%s' estimate '%s' %s --json -q%s%s", COMLEARN_BIN, urdf, extra,
           truth ? " --truth" : "", svg);
  return run(cmd, out, size);
}

static char *slurp_in_tmp(const char *name) {
  char path[512];
  snprintf(path, sizeof path, "%s/%s", tmpdir, name);
  return test_slurp(path, NULL);
}

/* The files in tmpdir (without . and ..). */
static int tmp_files(void) {
  DIR *d = opendir(tmpdir);
  ck_assert_ptr_nonnull(d);
  int n = 0;
  for (struct dirent *e; (e = readdir(d)) != NULL;)
    n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
  closedir(d);
  return n;
}

/* rock_1_uneven, noiseless, in-process and over LCM (a comlearn-sim of its own): every marker
 * and box where the JSON says, the truth only with --truth, 8 of its 26 trials in the strip, and
 * the JSON the same with and without --svg. */
START_TEST(rock_picture_matches_json) {
  static char out[1 << 17], plain[1 << 17];
  const char *urdf = COMLEARN_ASSETS_DIR "/rocks/rock_1_uneven.urdf";
  char lcm[256];
  snprintf(lcm, sizeof lcm, "--spawn-sim --lcm-url 'udpm://239.255.76.67:%u?ttl=0'",
           9700u + (unsigned)getpid() % 1000u);
  const char *backends[2] = {"--direct", lcm};
  for (int b = 0; b < 2; ++b) {
    for (int truth = 0; truth < 2; ++truth) {
      ck_assert_int_eq(estimate(urdf, backends[b], truth, "rock.svg", out, sizeof out), 0);
      char *svg = slurp_in_tmp("rock.svg");
      ck_assert_ptr_nonnull(strstr(svg, b ? "backend lcm" : "backend direct"));
      ck_assert_ptr_nonnull(strstr(svg, "policy bisect"));
      ck_assert_int_eq((int)json_num(out, "trials"), 24);
      check_picture(svg, out, truth, 1);
      free(svg);
      /* the estimate's JSON is what it is without the picture */
      ck_assert_int_eq(estimate(urdf, backends[b], truth, NULL, plain, sizeof plain), 0);
      drop_wall(out);
      drop_wall(plain);
      ck_assert_str_eq(out, plain);
      ck_assert_int_eq(tmp_files(), 1); /* rock.svg, no temporary left */
    }
  }
}
END_TEST

/* A bowl on its side (shapegen rim seed 21, even) leaves z not found without pivots (--pivots 0;
 * check_estimate's contact_limited_reason): z is a band across the front and side views, x and y
 * a box in the top view, and the legend gives the reason. */
START_TEST(component_not_found_is_a_band) {
  static char out[1 << 17];
  char cmd[1024], urdf[512];
  snprintf(cmd, sizeof cmd, "'%s' --family rim --seed 21 --out-dir '%s/rim' >/dev/null",
           COMLEARN_SHAPEGEN_BIN, tmpdir);
  ck_assert_int_eq(system(cmd), 0);
  snprintf(urdf, sizeof urdf, "%s/rim/rim_s21_even.urdf", tmpdir);
  ck_assert_int_eq(estimate(urdf, "--direct --pivots 0", 1, "rim.svg", out, sizeof out), 0);
  int found[3];
  json_found(out, found);
  ck_assert(found[0] && found[1] && !found[2]);
  char *svg = slurp_in_tmp("rim.svg");
  check_picture(svg, out, 1, 0);
  char unb[8];
  const char *front = tag_nth(svg, "rect", "interval", "data-view", "front", 0);
  ck_assert(attr(front, "data-unbounded", unb, sizeof unb));
  ck_assert_str_eq(unb, "v");
  ck_assert(!attr(tag_nth(svg, "rect", "interval", "data-view", "top-zoom", 0), "data-unbounded",
                  unb, sizeof unb));
  /* the reason, as the JSON gives it */
  const char *r = strstr(out, "\"reason\": [null, null, \"");
  ck_assert_ptr_nonnull(r);
  r += strlen("\"reason\": [null, null, \"");
  char reason[48];
  memcpy(reason, r, sizeof reason - 1);
  reason[sizeof reason - 1] = '\0';
  ck_assert_ptr_nonnull(strstr(svg, "z: not found (drawn as an unbounded band): "));
  ck_assert_msg(strstr(svg, reason) != NULL, "no '%s' in the legend", reason);
  free(svg);
}
END_TEST

/* Bad --svg paths: a folder that does not exist or a path that is a folder is bad input found
 * before any trial (exit 2, the path named, nothing on stdout, no file); a name the file system
 * refuses fails at the write, after the estimate printed (exit 1, named, no file left). */
START_TEST(bad_svg_paths) {
  static char out[1 << 17];
  char cmd[2048], path[1024];
  const char *urdf = COMLEARN_ASSETS_DIR "/rocks/rock_1_uneven.urdf";
  snprintf(path, sizeof path, "%s/no_such_folder/est.svg", tmpdir);
  snprintf(cmd, sizeof cmd, "'%s' estimate '%s' --direct --svg '%s' 2>&1 >/dev/null", COMLEARN_BIN,
           urdf, path);
  ck_assert_int_eq(run(cmd, out, sizeof out), 2);
  ck_assert_msg(strstr(out, path) && strstr(out, "does not exist"), "%s", out);
  ck_assert_int_eq(tmp_files(), 0);

  snprintf(cmd, sizeof cmd, "'%s' estimate '%s' --direct --json --svg '%s' 2>/dev/null",
           COMLEARN_BIN, urdf, tmpdir);
  ck_assert_int_eq(run(cmd, out, sizeof out), 2);
  ck_assert_str_eq(out, ""); /* refused before the trials */
  snprintf(cmd, sizeof cmd, "'%s' estimate '%s' --direct --svg '%s' 2>&1 >/dev/null", COMLEARN_BIN,
           urdf, tmpdir);
  ck_assert_int_eq(run(cmd, out, sizeof out), 2);
  ck_assert_msg(strstr(out, tmpdir) && strstr(out, "is a folder"), "%s", out);
  snprintf(cmd, sizeof cmd, "'%s' estimate '%s' --direct --svg '' 2>&1", COMLEARN_BIN, urdf);
  ck_assert_int_eq(run(cmd, out, sizeof out), 2);
  ck_assert_ptr_nonnull(strstr(out, "--svg: empty file name"));

  char longname[300];
  memset(longname, 'a', 300);
  memcpy(longname + 290, ".svg", 5); /* 294 bytes: over NAME_MAX (255) */
  snprintf(path, sizeof path, "%s/%s", tmpdir, longname);
  snprintf(cmd, sizeof cmd, "'%s' estimate '%s' --direct --json --svg '%s' 2>&1", COMLEARN_BIN,
           urdf, path);
  ck_assert_int_eq(run(cmd, out, sizeof out), 1);
  ck_assert_ptr_nonnull(strstr(out, "\"com_m\": ["));
  ck_assert_msg(strstr(out, longname) && strstr(out, strerror(ENAMETOOLONG)), "%s", out);
  ck_assert_int_eq(tmp_files(), 0);
}
END_TEST

/* ---- estimate_svg_write on hand-made results ------------------------------------------------ */

/* A 40 x 60 x 20 mm box mesh centred at the origin and a result with n trials, nothing found. */
static void box_result(model_mesh_t *mesh, estimate_result_t *r, size_t n) {
  const double lo[3] = {-0.02, -0.03, -0.01}, hi[3] = {0.02, 0.03, 0.01};
  ck_assert_int_eq(model_mesh_box(lo, hi, mesh), MODEL_OK);
  memset(r, 0, sizeof *r);
  for (int k = 0; k < 3; ++k) {
    r->com_m[k] = 0.001 * (k + 1);
    r->halfwidth_m[k] = INFINITY;
    snprintf(r->reason[k], sizeof r->reason[k], "reason %c <&>", "xyz"[k]);
  }
  r->trial_count = n;
  r->stable_trials = n;
  for (size_t i = 0; i < n; ++i) {
    estimate_trial_t *t = &r->trial[i];
    t->kind = ESTIMATE_TRIAL_STABLE;
    t->search = -1;
    t->outcome = ESTIMATE_STAYS;
    t->released.orientation_wxyz[0] = 1.0;
    t->released.position_m[0] = 0.01 * (double)i;
    t->released.position_m[2] = 0.01;
    t->settled = t->released;
  }
}

START_TEST(write_nothing_found_few_trials) {
  model_mesh_t mesh = {0};
  estimate_result_t *r = malloc(sizeof *r);
  ck_assert_ptr_nonnull(r);
  box_result(&mesh, r, 3);
  estimate_svg_input_t in = {.object = "box <1>",
                             .policy = "bisect",
                             .backend = "test",
                             .mesh_link = &mesh,
                             .result = r,
                             .base_size_m = {0.3, 0.3, 0.1}};
  char path[512];
  snprintf(path, sizeof path, "%s/box.svg", tmpdir);
  ck_assert_int_eq(estimate_svg_write(path, &in), 0);
  char *svg = test_slurp(path, NULL);
  ck_assert_ptr_nonnull(strstr(svg, "box &lt;1&gt;")); /* escaped */
  ck_assert_ptr_nonnull(strstr(svg, "reason y &lt;&amp;&gt;"));
  ck_assert_int_eq(tag_count(svg, "g", "trial", NULL, NULL), 3); /* min(8, 3) */
  const double hw[3] = {INFINITY, INFINITY, INFINITY};
  const int found[3] = {0, 0, 0};
  for (int i = 0; i < 6; ++i) {
    check_marker(svg, "com-est", kViews[i], r->com_m);
    check_interval(svg, kViews[i], r->com_m, hw, found); /* "uv": the whole view */
  }
  ck_assert_ptr_null(strstr(svg, "com-truth"));
  free(svg);
  struct stat st;
  ck_assert_int_eq(stat(path, &st), 0);
  const mode_t mask = umask(0);
  umask(mask);
  ck_assert_uint_eq(st.st_mode & 0777u, 0666u & ~(unsigned)mask); /* not mkstemp's 0600 */

  /* bad input: -1, EINVAL, no file */
  snprintf(path, sizeof path, "%s/bad.svg", tmpdir);
  const double nan3[3] = {NAN, 0.0, 0.0};
  estimate_svg_input_t bad = in;
  bad.truth_com_m = nan3;
  errno = 0;
  ck_assert_int_eq(estimate_svg_write(path, &bad), -1);
  ck_assert_int_eq(errno, EINVAL);
  bad = in;
  bad.base_size_m[2] = 0.0;
  ck_assert_int_eq(estimate_svg_write(path, &bad), -1);
  bad = in;
  bad.result = NULL;
  ck_assert_int_eq(estimate_svg_write(path, &bad), -1);
  ck_assert_int_eq(estimate_svg_write("", &in), -1);
  ck_assert_int_eq(estimate_svg_write(path, NULL), -1);
  ck_assert_int_eq(access(path, F_OK), -1);
  snprintf(path, sizeof path, "%s/missing/x.svg", tmpdir);
  errno = 0;
  ck_assert_int_eq(estimate_svg_write(path, &in), -1);
  ck_assert_int_eq(errno, ENOENT);
  ck_assert_int_eq(tmp_files(), 1); /* box.svg */
  model_mesh_free(&mesh);
  free(r);
}
END_TEST

static Suite *suite(void) {
  Suite *s = suite_create("estimate_svg");
  TCase *tc = tcase_create("cli");
  tcase_add_checked_fixture(tc, setup, teardown);
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, rock_picture_matches_json);
  tcase_add_test(tc, component_not_found_is_a_band);
  tcase_add_test(tc, bad_svg_paths);
  suite_add_tcase(s, tc);
  TCase *w = tcase_create("write");
  tcase_add_checked_fixture(w, setup, teardown);
  tcase_add_test(w, write_nothing_found_few_trials);
  suite_add_tcase(s, w);
  return s;
}

int main(void) {
  SRunner *sr = srunner_create(suite());
  srunner_run_all(sr, CK_NORMAL);
  const int failed = srunner_ntests_failed(sr);
  srunner_free(sr);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
