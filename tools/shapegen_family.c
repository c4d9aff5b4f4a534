/* shapegen_family.c - the families: which numbers each draws, in which ranges (docs/assets.md,
 * "Adversarial shapes"). Every function returns 0, or -1 when the draw makes no valid shape (the
 * attempt is then rejected and the next one drawn). */
#include "shapegen_internal.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MM 1e-3
#define DEG (CL_PI / 180.0)

/* ---- materials ------------------------------------------------------------------------------- */

typedef struct {
  const char *name;
  double density_kg_m3;
} material_t;

enum { WOOD = 1, PLASTIC = 2, CERAMIC = 4, STONE = 8, METAL = 16 };

static const material_t kMaterials[] = {
    {"beech", 720.0},      {"oak", 750.0},        {"maple", 705.0}, /* WOOD */
    {"ABS", 1050.0},       {"nylon", 1150.0},     {"PLA", 1240.0},     {"acetal", 1410.0},
    {"stoneware", 2300.0}, {"porcelain", 2400.0}, {"glass", 2500.0}, /* CERAMIC */
    {"sandstone", 2300.0}, {"limestone", 2600.0}, {"granite", 2650.0}, {"marble", 2700.0},
    {"aluminium", 2700.0}};
static const int kMaterialClass[] = {WOOD,    WOOD,    WOOD,    PLASTIC, PLASTIC,
                                     PLASTIC, PLASTIC, CERAMIC, CERAMIC, CERAMIC,
                                     STONE,   STONE,   STONE,   STONE,   METAL};
enum { MATERIAL_COUNT = sizeof kMaterials / sizeof kMaterials[0] };

/* A uniformly drawn material among the classes in `mask`. */
static void material_draw(uint64_t *state, int mask, shapegen_spec_t *out) {
  unsigned n = 0;
  for (unsigned i = 0; i < MATERIAL_COUNT; ++i) n += (kMaterialClass[i] & mask) != 0;
  unsigned pick = cl_rng_below(state, n);
  for (unsigned i = 0; i < MATERIAL_COUNT; ++i) {
    if (!(kMaterialClass[i] & mask)) continue;
    if (pick-- == 0) {
      snprintf(out->material, sizeof out->material, "%s", kMaterials[i].name);
      out->density_kg_m3 = kMaterials[i].density_kg_m3;
      return;
    }
  }
}

static unsigned clamp_u(double x, unsigned lo, unsigned hi) {
  if (!(x >= (double)lo)) return lo;
  if (x >= (double)hi) return hi;
  return (unsigned)x;
}

static void set_variant(shapegen_spec_t *out, const char *text) {
  snprintf(out->variant, sizeof out->variant, "%s", text);
}

/* ---- boxes ----------------------------------------------------------------------------------- */

static int draw_box(uint64_t *st, shapegen_spec_t *out) {
  out->shape = SHAPEGEN_SHAPE_BOX;
  for (int k = 0; k < 3; ++k) {
    out->box.size_m[k] = cl_rng_range(st, 20 * MM, 120 * MM);
    out->box.cells[k] = 1;
  }
  set_variant(out, "box");
  material_draw(st, WOOD | PLASTIC | STONE | METAL, out);
  return 0;
}

static int draw_domino(uint64_t *st, shapegen_spec_t *out) {
  static const double nominal[3] = {48 * MM, 24 * MM, 7.5 * MM};
  out->shape = SHAPEGEN_SHAPE_BOX;
  for (int k = 0; k < 3; ++k) {
    out->box.size_m[k] = nominal[k] * cl_rng_range(st, 0.85, 1.15);
    out->box.cells[k] = 1;
  }
  set_variant(out, "domino");
  material_draw(st, WOOD | PLASTIC | STONE, out);
  return 0;
}

/* ---- revolve profiles ------------------------------------------------------------------------ */

static int profile_add(shapegen_revolve_t *rev, double r, double z) {
  if (rev->point_count >= SHAPEGEN_MAX_PROFILE) return -1;
  rev->rz_m[rev->point_count][0] = r;
  rev->rz_m[rev->point_count][1] = z;
  ++rev->point_count;
  return 0;
}

/* Segments: a multiple of 4 in [lo, hi] (so the polygon is symmetric about both axes). */
static unsigned draw_segments(uint64_t *st, unsigned lo, unsigned hi) {
  return 4 * (lo / 4 + cl_rng_below(st, (hi - lo) / 4 + 1));
}

static int cylinder_profile(shapegen_revolve_t *rev, double radius, double length) {
  rev->point_count = 0;
  int rc = profile_add(rev, 0.0, 0.0);
  rc |= profile_add(rev, radius, 0.0);
  rc |= profile_add(rev, radius, length);
  rc |= profile_add(rev, 0.0, length);
  return rc;
}

static int draw_plate(uint64_t *st, shapegen_spec_t *out) {
  const unsigned kind = cl_rng_below(st, 4);
  if (kind == 0 || kind == 2) {
    out->shape = SHAPEGEN_SHAPE_BOX;
    for (int k = 0; k < 3; ++k) out->box.cells[k] = 1;
    if (kind == 0) {
      out->box.size_m[0] = cl_rng_range(st, 30 * MM, 120 * MM);
      out->box.size_m[1] = cl_rng_range(st, 20 * MM, out->box.size_m[0]);
      out->box.size_m[2] = cl_rng_range(st, 2 * MM, 4 * MM);
      set_variant(out, "thin plate");
    } else {
      out->box.size_m[0] = cl_rng_range(st, 60 * MM, 120 * MM);
      out->box.size_m[1] = cl_rng_range(st, 3 * MM, 10 * MM);
      out->box.size_m[2] = cl_rng_range(st, 3 * MM, 10 * MM);
      set_variant(out, "bar");
    }
  } else {
    out->shape = SHAPEGEN_SHAPE_REVOLVE;
    const unsigned n = 64 + cl_rng_below(st, 65);
    out->rev.segments = n;
    double radius, length;
    if (kind == 1) {
      radius = cl_rng_range(st, 10 * MM, 60 * MM);
      length = cl_rng_range(st, 2 * MM, 4 * MM);
    } else {
      radius = cl_rng_range(st, 5 * MM, 30 * MM);
      length = cl_rng_range(st, 20 * MM, 120 * MM);
      out->lay_on_side = cl_rng_below(st, 2) == 1;
    }
    if (cylinder_profile(&out->rev, radius, length) != 0) return -1;
    snprintf(out->variant, sizeof out->variant, "%s %u sides%s",
             kind == 1 ? "thin disk" : "cylinder", n, out->lay_on_side ? ", lying" : "");
  }
  material_draw(st, WOOD | PLASTIC | CERAMIC | METAL, out);
  return 0;
}

static int draw_ring(uint64_t *st, shapegen_spec_t *out) {
  out->shape = SHAPEGEN_SHAPE_REVOLVE;
  const double big = cl_rng_range(st, 12 * MM, 48 * MM);
  double ar = cl_rng_range(st, 3 * MM, 15 * MM);
  if (ar > 0.6 * big) ar = 0.6 * big;
  const double az = ar * cl_rng_range(st, 0.7, 1.3);
  const unsigned m = 4 * (3 + cl_rng_below(st, 6)); /* 12 .. 32 profile points */
  out->rev.segments = draw_segments(st, 48, 128);
  if (2.0 * (big + ar) > 120 * MM || 2.0 * (big + ar) < 20 * MM) return -1;
  out->rev.point_count = 0;
  for (unsigned k = 0; k < m; ++k) {
    double c, s;
    shapegen_cos_sin_turn(4 * (long)k - (long)m, 4 * (long)m, &c, &s); /* from the bottom up */
    if (profile_add(&out->rev, big + ar * c, az * s) != 0) return -1;
  }
  snprintf(out->variant, sizeof out->variant, "torus %u x %u", out->rev.segments, m);
  material_draw(st, WOOD | PLASTIC | CERAMIC | STONE | METAL, out);
  return 0;
}

/* z of the bowl's outer (or inner) surface at s = r / radius in [0, 1]. */
static double bowl_z(double z0, double height, double alpha, double s) {
  const double s2 = s * s;
  return z0 + height * (alpha * s2 + (1.0 - alpha) * s2 * s2);
}

static int draw_rim(uint64_t *st, shapegen_spec_t *out) {
  out->shape = SHAPEGEN_SHAPE_REVOLVE;
  const int plate = cl_rng_below(st, 3) == 0;
  double radius, height, alpha;
  if (plate) {
    radius = cl_rng_range(st, 40 * MM, 60 * MM);
    height = cl_rng_range(st, 8 * MM, 16 * MM);
    alpha = cl_rng_range(st, 0.05, 0.3);
  } else {
    radius = cl_rng_range(st, 25 * MM, 60 * MM);
    height = radius * cl_rng_range(st, 0.35, 0.8);
    alpha = cl_rng_range(st, 0.6, 1.0);
  }
  const double rim = cl_rng_range(st, 2 * MM, 5 * MM);     /* top annulus width */
  const double floor_t = cl_rng_range(st, 2 * MM, 5 * MM); /* bottom thickness */
  const double z0 = cl_rng_range(st, 1 * MM, 3 * MM);      /* underside clearance at the center */
  const double foot_w = cl_rng_range(st, 2 * MM, 4 * MM);
  const double lo = 5.0 * foot_w > 0.4 * radius ? 5.0 * foot_w : 0.4 * radius;
  const double r_fo = cl_rng_range(st, lo, 0.65 * radius);
  const double r_fi = r_fo - foot_w;
  out->rev.segments = draw_segments(st, 64, 128);
  if (lo >= 0.65 * radius || !(height > z0 + floor_t + 3 * MM)) return -1;
  const double inner_r = radius - rim;
  /* the walls must stay >= 1.5 mm apart vertically */
  for (int k = 0; k <= 200; ++k) {
    const double r = inner_r * k / 200.0;
    const double zo = bowl_z(z0, height - z0, alpha, r / radius);
    const double zi = bowl_z(z0 + floor_t, height - z0 - floor_t, alpha, r / inner_r);
    if (zi - zo < 1.5 * MM) return -1;
  }
  shapegen_revolve_t *rev = &out->rev;
  rev->point_count = 0;
  const unsigned n1 = 4 + (unsigned)(r_fi / (3 * MM)),
                 n2 = 8 + (unsigned)((radius - r_fo) / (2 * MM));
  int rc = profile_add(rev, 0.0, z0);
  for (unsigned k = 1; k <= n1; ++k) {
    const double r = r_fi * k / n1;
    rc |= profile_add(rev, r, bowl_z(z0, height - z0, alpha, r / radius));
  }
  rc |= profile_add(rev, r_fi, 0.0);
  rc |= profile_add(rev, r_fo, 0.0);
  for (unsigned k = 0; k <= n2; ++k) {
    const double r = r_fo + (radius - r_fo) * k / n2;
    rc |= profile_add(rev, k == n2 ? radius : r,
                      k == n2 ? height : bowl_z(z0, height - z0, alpha, r / radius));
  }
  const unsigned n3 = 8 + (unsigned)(inner_r / (2.5 * MM));
  for (unsigned k = n3; k >= 1; --k) {
    const double r = inner_r * k / n3;
    rc |= profile_add(
        rev, r, k == n3 ? height : bowl_z(z0 + floor_t, height - z0 - floor_t, alpha, r / inner_r));
  }
  rc |= profile_add(rev, 0.0, z0 + floor_t);
  if (rc != 0) return -1;
  snprintf(out->variant, sizeof out->variant, "%s, foot ring %.1f mm", plate ? "plate" : "bowl",
           foot_w / MM);
  material_draw(st, WOOD | PLASTIC | CERAMIC, out);
  return 0;
}

/* The cup of a mug; the handle spec refers to its outer wall rows. */
static int draw_mug(uint64_t *st, shapegen_spec_t *out) {
  out->shape = SHAPEGEN_SHAPE_REVOLVE;
  const double radius = cl_rng_range(st, 25 * MM, 38 * MM);
  const double height = cl_rng_range(st, 55 * MM, 105 * MM);
  const double wall = cl_rng_range(st, 3 * MM, 5.5 * MM);
  const double floor_z = cl_rng_range(st, 5 * MM, 10 * MM);
  const double chamfer = cl_rng_range(st, 0.6 * MM, 1.5 * MM);
  const int ring = cl_rng_below(st, 2) == 1;
  const double recess = cl_rng_range(st, 1 * MM, 2.5 * MM);
  const double foot_w = cl_rng_range(st, 3 * MM, 6 * MM);
  const unsigned n = 8 * (8 + cl_rng_below(st, 5)); /* 64 .. 96 */
  out->rev.segments = n;
  const size_t rows = (size_t)((height - chamfer) / (2.5 * MM) + 0.5);
  const double row_h = (height - chamfer) / (double)rows;

  shapegen_revolve_t *rev = &out->rev;
  rev->point_count = 0;
  int rc = 0;
  if (ring) {
    rc |= profile_add(rev, 0.0, recess);
    rc |= profile_add(rev, 0.5 * (radius - foot_w), recess);
    rc |= profile_add(rev, radius - foot_w, recess);
    rc |= profile_add(rev, radius - foot_w, 0.0);
  } else {
    rc |= profile_add(rev, 0.0, 0.0);
    rc |= profile_add(rev, 0.5 * (radius - chamfer), 0.0);
  }
  rc |= profile_add(rev, radius - chamfer, 0.0);
  const size_t wall0 = rev->point_count;
  for (size_t i = 0; i <= rows; ++i) {
    rc |= profile_add(rev, radius, i == rows ? height : chamfer + (double)i * row_h);
  }
  const size_t inner_rows = 2 + (size_t)((height - floor_z) / (6 * MM));
  for (size_t i = 0; i <= inner_rows; ++i) {
    const double z = height - (height - floor_z) * (double)i / (double)inner_rows;
    rc |= profile_add(rev, radius - wall, i == inner_rows ? floor_z : z);
  }
  rc |= profile_add(rev, 0.5 * (radius - wall), floor_z);
  rc |= profile_add(rev, 0.0, floor_z);
  if (rc != 0 || (ring && !(floor_z > recess + 3 * MM))) return -1;

  /* the handle: holes of 2 k columns x q rows, mirror images about the path's center */
  shapegen_handle_t *h = &out->handle;
  const double col_w = radius * (2.0 * CL_PI) / n;
  h->present = 1;
  h->columns = clamp_u(cl_rng_range(st, 3.5 * MM, 6 * MM) / col_w + 0.5, 1, n / 8);
  h->rows = clamp_u(2.0 * cl_rng_range(st, 3.5 * MM, 6 * MM) / row_h + 0.5, 2, 8);
  const double top_gap = cl_rng_range(st, 6 * MM, 14 * MM),
               low_gap = cl_rng_range(st, 8 * MM, 18 * MM);
  const long iu1 = (long)((height - top_gap - chamfer) / row_h);
  const long il0 = (long)((low_gap - chamfer) / row_h) + 1;
  const long iu0 = iu1 - (long)h->rows, il1 = il0 + (long)h->rows;
  const double half_h = 0.5 * (double)h->rows * row_h;
  if (il0 < 1 || iu1 > (long)rows - 1 || iu0 - il1 < 2) return -1;
  h->upper_row = wall0 + (size_t)iu0;
  h->lower_row = wall0 + (size_t)il0;
  h->radius_m = radius;
  h->center_z_m = 0.5 * (rev->rz_m[h->upper_row][1] + rev->rz_m[h->lower_row + h->rows][1]);
  h->half_height_m =
      0.5 * (rev->rz_m[h->upper_row][1] + rev->rz_m[h->upper_row + h->rows][1]) - h->center_z_m;
  /* keep the bend's radius of curvature (reach^2 / half height) >= 2.2 x the tube's half height */
  const double reach_lo = sqrt(2.2 * half_h * h->half_height_m);
  const double lo = reach_lo > 16 * MM ? reach_lo : 16 * MM;
  if (lo > 34 * MM || h->half_height_m < half_h + 5 * MM) return -1;
  h->reach_m = cl_rng_range(st, lo, 34 * MM);
  if (2.0 * radius + h->reach_m + half_h > 120 * MM) h->reach_m = 120 * MM - 2.0 * radius - half_h;
  if (h->reach_m < lo) return -1;
  h->loops = 14 + cl_rng_below(st, 11);
  snprintf(out->variant, sizeof out->variant, "mug, %s", ring ? "foot ring" : "full bottom");
  material_draw(st, PLASTIC | CERAMIC, out);
  return 0;
}

/* ---- slabs ----------------------------------------------------------------------------------- */

static int cmp_double(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return x < y ? -1 : x > y;
}

/* Grid lines of one axis: the required ones inside (-half, half) (sorted, duplicates joined; those
 * within 0.05 mm of an end dropped), then every gap wider than `coarse` split evenly. -1 when two
 * lines are closer than 0.05 mm or there are too many. */
static int lines_make(double half, double *req, size_t nreq, double coarse, double *lines,
                      size_t *count) {
  qsort(req, nreq, sizeof *req, cmp_double);
  double pts[SHAPEGEN_MAX_LINES];
  size_t np = 0;
  pts[np++] = -half;
  for (size_t i = 0; i < nreq; ++i) {
    if (req[i] <= -half + 0.05 * MM || req[i] >= half - 0.05 * MM) continue;
    if (req[i] == pts[np - 1]) continue;
    if (req[i] - pts[np - 1] < 0.05 * MM || np + 1 >= SHAPEGEN_MAX_LINES) return -1;
    pts[np++] = req[i];
  }
  pts[np++] = half;
  size_t n = 0;
  for (size_t i = 0; i + 1 < np; ++i) {
    const double gap = pts[i + 1] - pts[i];
    const unsigned parts = gap > coarse ? (unsigned)(gap / coarse) + 1 : 1;
    for (unsigned k = 0; k < parts; ++k) {
      if (n >= SHAPEGEN_MAX_LINES - 1) return -1;
      lines[n++] = k == 0 ? pts[i] : pts[i] + gap * k / parts;
    }
  }
  lines[n++] = half;
  *count = n;
  return 0;
}

/* The required lines of the feet along axis a (square: edges and slope ends; round: a fine comb).
 */
static size_t feet_lines(const shapegen_slab_t *s, int a, double fine, double *req) {
  size_t n = 0;
  for (size_t f = 0; f < s->foot_count; ++f) {
    const shapegen_foot_t *ft = &s->feet[f];
    const double c = ft->center_m[a];
    if (ft->round) {
      const long k = (long)((ft->half_m[0] + s->slope_m) / fine) + 2;
      for (long i = -k; i <= k && n < 4 * SHAPEGEN_MAX_LINES; ++i) req[n++] = c + (double)i * fine;
    } else {
      const double h = ft->half_m[a];
      req[n++] = c - h - s->slope_m;
      req[n++] = c - h;
      req[n++] = c + h;
      req[n++] = c + h + s->slope_m;
    }
  }
  return n;
}

static int draw_feet(uint64_t *st, unsigned feet, shapegen_spec_t *out) {
  out->shape = SHAPEGEN_SHAPE_SLAB;
  shapegen_slab_t *s = &out->slab;
  const double hx = cl_rng_range(st, 20 * MM, 60 * MM);
  const double hy = cl_rng_range(st, 12.5 * MM, hx < 45 * MM ? hx : 45 * MM);
  s->half_m[0] = hx;
  s->half_m[1] = hy;
  s->clearance_m = cl_rng_range(st, 2 * MM, 5 * MM);
  s->slope_m = cl_rng_range(st, 0.6 * MM, 1.5 * MM);
  const double wall = cl_rng_range(st, 2 * MM, 4 * MM);
  const double dome_x = cl_rng_range(st, 2 * MM, 8 * MM), dome_y = cl_rng_range(st, 1 * MM, 5 * MM);
  const double coarse = cl_rng_range(st, 3 * MM, 5 * MM), fine = 1.0 * MM;
  /* a square foot's slope ends inside the footprint (its closed form needs the whole slope) */
  const double inset = cl_rng_range(st, s->slope_m + 0.5 * MM, 6 * MM);
  const unsigned kind = cl_rng_below(st, feet == 2 ? 3 : 2); /* 0 round, 1 square, 2 rails */
  double half = cl_rng_range(st, 2.5 * MM, 6 * MM);
  s->foot_count = feet;
  for (unsigned f = 0; f < feet; ++f) {
    shapegen_foot_t *ft = &s->feet[f];
    ft->round = kind == 0;
    ft->half_m[0] = half;
    ft->half_m[1] = kind == 2 ? hy * cl_rng_range(st, 0.55, 0.85) : half;
    if (kind == 2 && f == 1) ft->half_m[1] = s->feet[0].half_m[1];
  }
  const double xf = hx - inset - half, yf = hy - inset - half;
  const double cx[4][4] = {{0}, {0}, {-xf, xf}, {-xf, -xf, xf}};
  const double cy[4][4] = {{0}, {0}, {0, 0}, {-yf, yf, 0}};
  for (unsigned f = 0; f < feet; ++f) {
    s->feet[f].center_m[0] = feet == 4 ? (f & 1 ? xf : -xf) : cx[feet][f];
    s->feet[f].center_m[1] = feet == 4 ? (f & 2 ? yf : -yf) : cy[feet][f];
  }
  /* flat feet >= 10 mm apart (slopes included); in a tripod, the y combs apart */
  const double reach = half + s->slope_m + fine;
  if (2.0 * xf - 2.0 * (half + s->slope_m) < 10 * MM) return -1;
  if (feet == 3 && yf - 2.0 * reach < 2 * MM) return -1;
  if (feet == 4 && 2.0 * yf - 2.0 * (half + s->slope_m) < 10 * MM) return -1;
  for (int a = 0; a < 2; ++a) {
    double req[4 * SHAPEGEN_MAX_LINES];
    const size_t nreq = feet_lines(s, a, fine, req);
    if (lines_make(s->half_m[a], req, nreq, coarse, s->lines_m[a], &s->line_count[a]) != 0)
      return -1;
    const double dome = a == 0 ? dome_x : dome_y;
    for (size_t i = 0; i < s->line_count[a]; ++i) {
      const double u = s->lines_m[a][i] / s->half_m[a];
      s->bottom_m[a][i] = 0.0;
      s->top_m[a][i] = dome * (1.0 - u * u);
    }
  }
  s->top0_m = s->clearance_m + wall;
  static const char *const kinds[3] = {"round", "square", "rails"};
  snprintf(out->variant, sizeof out->variant, "%s%s", kinds[kind],
           kind == 2 ? "" : (feet == 2 ? " pads" : " feet"));
  material_draw(st, WOOD | PLASTIC | CERAMIC, out);
  return 0;
}

/* A convex piecewise-linear function on [-half, half] with `kinks` kinks (values at the kinks and
 * the ends, minimum 0), slope changes of 0.1-1 degree. Kink positions into kink_x. */
static void convex_pl(uint64_t *st, double half, unsigned kinks, double *kink_x, double *slopes) {
  if (kinks == 1) {
    kink_x[0] = cl_rng_range(st, -0.4, 0.4) * half;
  } else {
    kink_x[0] = cl_rng_range(st, -0.6, -0.1) * half;
    kink_x[1] = cl_rng_range(st, 0.1, 0.6) * half;
  }
  double total = 0.0, delta[2];
  for (unsigned k = 0; k < kinks; ++k) {
    delta[k] = cl_rng_range(st, 0.1, 1.0) * DEG;
    total += delta[k];
  }
  slopes[0] = -cl_rng_range(st, 0.3, 0.7) * total;
  for (unsigned k = 0; k < kinks; ++k) slopes[k + 1] = slopes[k] + delta[k];
}

static double pl_eval(double half, unsigned kinks, const double *kink_x, const double *slopes,
                      double x) {
  double v = 0.0, at = -half;
  for (unsigned k = 0; k <= kinks; ++k) {
    const double end = k < kinks ? kink_x[k] : half;
    const double stop = x < end ? x : end;
    if (stop > at) v += slopes[k] * (stop - at);
    at = end;
    if (x <= end) break;
  }
  return v;
}

static int draw_tilted(uint64_t *st, shapegen_spec_t *out) {
  out->shape = SHAPEGEN_SHAPE_SLAB;
  shapegen_slab_t *s = &out->slab;
  s->half_m[0] = cl_rng_range(st, 12 * MM, 60 * MM);
  s->half_m[1] = cl_rng_range(st, 12 * MM, 60 * MM);
  const double height = cl_rng_range(st, 20 * MM, 80 * MM);
  const double coarse = cl_rng_range(st, 6 * MM, 12 * MM);
  /* surface 0 bottom, 1 top; axis a: kinks and slopes */
  unsigned kinks[2][2];
  double kx[2][2][2], sl[2][2][3];
  size_t nreq[2] = {0, 0};
  double req[2][8];
  for (int surf = 0; surf < 2; ++surf) {
    for (int a = 0; a < 2; ++a) {
      kinks[surf][a] = 1 + cl_rng_below(st, 2);
      convex_pl(st, s->half_m[a], kinks[surf][a], kx[surf][a], sl[surf][a]);
      for (unsigned k = 0; k < kinks[surf][a]; ++k) req[a][nreq[a]++] = kx[surf][a][k];
    }
  }
  for (int a = 0; a < 2; ++a) {
    if (lines_make(s->half_m[a], req[a], nreq[a], coarse, s->lines_m[a], &s->line_count[a]) != 0)
      return -1;
    for (int surf = 0; surf < 2; ++surf) {
      double lo = HUGE_VAL;
      double *vals = surf == 0 ? s->bottom_m[a] : s->top_m[a];
      for (size_t i = 0; i < s->line_count[a]; ++i) {
        vals[i] = pl_eval(s->half_m[a], kinks[surf][a], kx[surf][a], sl[surf][a], s->lines_m[a][i]);
        if (vals[i] < lo) lo = vals[i];
      }
      for (size_t i = 0; i < s->line_count[a]; ++i) {
        vals[i] -= lo;
        if (surf == 1) vals[i] = -vals[i];
      }
    }
  }
  s->top0_m = height;
  snprintf(out->variant, sizeof out->variant, "%u x %u bottom facets, %u x %u top", kinks[0][0] + 1,
           kinks[0][1] + 1, kinks[1][0] + 1, kinks[1][1] + 1);
  material_draw(st, WOOD | PLASTIC | STONE | METAL, out);
  return 0;
}

/* ---- rocks ----------------------------------------------------------------------------------- */

/* Semi-axes a >= b >= c drawn into the rock spec; returns their mean. */
static double rock_axes(uint64_t *st, rockgen_spec_t *r, double a_lo, double a_hi, double c_lo) {
  r->semi_axes_m[0] = cl_rng_range(st, a_lo, a_hi);
  r->semi_axes_m[1] = r->semi_axes_m[0] * cl_rng_range(st, 0.6, 0.95);
  r->semi_axes_m[2] = r->semi_axes_m[1] * cl_rng_range(st, c_lo, 0.9);
  return (r->semi_axes_m[0] + r->semi_axes_m[1] + r->semi_axes_m[2]) / 3.0;
}

static int draw_pebble(uint64_t *st, shapegen_spec_t *out) {
  out->shape = SHAPEGEN_SHAPE_ROCK;
  rockgen_spec_t *r = &out->rock;
  r->seed = cl_rng_next(st);
  const double mean = rock_axes(st, r, 15 * MM, 48 * MM, 0.5);
  r->lobe_count = 5 + cl_rng_below(st, 4);
  r->lobe_amplitude = cl_rng_range(st, 0.06, 0.14);
  r->lobe_cos = cl_rng_range(st, 0.2, 0.45);
  r->bump_count = 6 + cl_rng_below(st, 8);
  r->bump_amplitude = cl_rng_range(st, 0.01, 0.03);
  r->bump_cos = cl_rng_range(st, 0.82, 0.9);
  /* coarse enough that some triangle can carry it (edges of 5-7 mm) */
  r->frequency = clamp_u(1.1 * mean / cl_rng_range(st, 5 * MM, 7 * MM), 3, 12);
  r->fracture_count = 0;
  snprintf(out->variant, sizeof out->variant, "pebble f%u", r->frequency);
  material_draw(st, STONE, out);
  return 0;
}

static int draw_lumpy(uint64_t *st, shapegen_spec_t *out) {
  out->shape = SHAPEGEN_SHAPE_ROCK;
  rockgen_spec_t *r = &out->rock;
  r->seed = cl_rng_next(st);
  const double mean = rock_axes(st, r, 14 * MM, 45 * MM, 0.55);
  r->lobe_count = 6;
  r->lobe_amplitude = cl_rng_range(st, 0.15, 0.22);
  r->lobe_cos = cl_rng_range(st, 0.25, 0.35);
  r->bump_count = 20 + cl_rng_below(st, 7);
  r->bump_amplitude = cl_rng_range(st, 0.04, 0.07);
  r->bump_cos = cl_rng_range(st, 0.86, 0.9);
  r->frequency = clamp_u(1.1 * mean / cl_rng_range(st, 2.5 * MM, 3.5 * MM), 6, 14);
  r->fracture_count = 1 + cl_rng_below(st, 3);
  for (size_t f = 0; f < r->fracture_count; ++f) {
    double *n = r->fractures[f].normal;
    if (f == 0) { /* the bottom, tilted 2-12 degrees */
      double u[3];
      cl_rng_direction(st, 3, u);
      const double h = sqrt(u[0] * u[0] + u[1] * u[1]), t = cl_rng_range(st, 0.035, 0.21);
      n[0] = h > 1e-9 ? t * u[0] / h : t;
      n[1] = h > 1e-9 ? t * u[1] / h : 0.0;
      n[2] = -1.0;
    } else {
      for (int tries = 0; tries < 64; ++tries) { /* a side face: |n_z| <= 0.5 */
        cl_rng_direction(st, 3, n);
        if (fabs(n[2]) <= 0.5) break;
      }
    }
    r->fractures[f].depth_m = cl_rng_range(st, 0.4 * MM, 1.6 * MM);
  }
  snprintf(out->variant, sizeof out->variant, "lumpy f%u, %zu faces", r->frequency,
           r->fracture_count);
  material_draw(st, STONE, out);
  return 0;
}

static int draw_scanned(uint64_t *st, shapegen_spec_t *out) {
  const int rock = cl_rng_below(st, 2) == 1;
  out->noise_m = cl_rng_range(st, 1e-6, 20e-6);
  out->noise_seed = cl_rng_next(st);
  if (rock) {
    out->shape = SHAPEGEN_SHAPE_ROCK;
    if (rockgen_spec_random(cl_rng_next(st), &out->rock) != MODEL_OK) return -1;
    material_draw(st, STONE, out);
  } else {
    out->shape = SHAPEGEN_SHAPE_BOX;
    const double cell = cl_rng_range(st, 3 * MM, 6 * MM);
    for (int k = 0; k < 3; ++k) {
      out->box.size_m[k] = cl_rng_range(st, 20 * MM, 120 * MM);
      out->box.cells[k] = clamp_u(out->box.size_m[k] / cell + 0.5, 2, 64);
    }
    material_draw(st, WOOD | PLASTIC | STONE | CERAMIC, out);
  }
  snprintf(out->variant, sizeof out->variant, "scanned %s, %.1f um", rock ? "rock" : "box",
           out->noise_m * 1e6);
  return 0;
}

int sg_family_draw(shapegen_family_t family, uint64_t *st, shapegen_spec_t *out) {
  switch (family) {
    case SHAPEGEN_BOX: return draw_box(st, out);
    case SHAPEGEN_DOMINO: return draw_domino(st, out);
    case SHAPEGEN_FEET2: return draw_feet(st, 2, out);
    case SHAPEGEN_FEET3: return draw_feet(st, 3, out);
    case SHAPEGEN_FEET4: return draw_feet(st, 4, out);
    case SHAPEGEN_RING: return draw_ring(st, out);
    case SHAPEGEN_RIM: return draw_rim(st, out);
    case SHAPEGEN_MUG: return draw_mug(st, out);
    case SHAPEGEN_PEBBLE: return draw_pebble(st, out);
    case SHAPEGEN_LUMPY: return draw_lumpy(st, out);
    case SHAPEGEN_SCANNED: return draw_scanned(st, out);
    case SHAPEGEN_PLATE: return draw_plate(st, out);
    case SHAPEGEN_TILTED: return draw_tilted(st, out);
    default: return -1;
  }
}
