/* bench_stack: how often `comlearn stack` builds a standing stack of three random uneven rocks,
 * per source of the believed CoMs (--com learned, bbox, true).
 *
 * Triple i (0 .. N-1) is rock_r<b+3i>, rock_r<b+3i+1>, rock_r<b+3i+2> (b = --seed-base), written
 * once by `comlearn-rockgen --random b --count 3N` into a scratch folder (docs/assets.md, "Random
 * rocks"). Per triple and source it runs
 *   comlearn stack A_uneven.urdf B_uneven.urdf C_uneven.urdf --com SRC --json -q
 * and reads "stands", "seconds_standing", "com_source" and every "margin_m" of "objects" from its
 * JSON. Exit 0 means planned and simulated (standing or not); any other exit, a timeout or
 * unreadable JSON is counted as "failed" and reported separately (it is not a standing stack).
 *
 * Prints a markdown table per source: stands k/N, the rate with its Wilson 95 % interval, failed
 * runs, the median seconds standing of the stacks that fell, the median smallest planned margin,
 * the median wall time per call. --json prints the same as one JSON object instead.
 * --svg-dir DIR keeps a side view (`--svg`) of the first triple that stands with learned CoMs.
 * --dry-run prints the commands without running them; --parse FILE reads one JSON reply (a check
 * of the parser). Exit status: 0 done, 1 runtime failure (no rocks, or not one call succeeded),
 * 2 usage. */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <getopt.h>
#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include "comlearn/cli_args.h"
#include "comlearn/cli_json.h"
#include "comlearn/cli_log.h"
#include "comlearn/cli_time.h"

#ifndef COMLEARN_BIN
#define COMLEARN_BIN "comlearn"
#endif
#ifndef COMLEARN_ROCKGEN
#define COMLEARN_ROCKGEN "comlearn-rockgen"
#endif

enum { MAX_TRIPLES = 1000, MAX_OUT = 1 << 20, MAX_LEVELS = 8, SOURCES = 3 };

static const char *const kSources[SOURCES] = {"learned", "bbox", "true"};

/* ---- a minimal JSON reader for the keys we need ------------------------------------------- */

typedef struct {
  int stands;              /* -1 missing */
  double seconds_standing; /* NaN missing */
  char com_source[16];
  size_t levels; /* "margin_m" values found in "objects" */
  double margin_m[MAX_LEVELS];
} reply_t;

typedef struct {
  const char *p, *end;
  int depth;
} reader_t;

static void ws(reader_t *r) {
  while (r->p < r->end && (*r->p == ' ' || *r->p == '\n' || *r->p == '\t' || *r->p == '\r')) ++r->p;
}

static int eat(reader_t *r, char c) {
  ws(r);
  if (r->p < r->end && *r->p == c) {
    ++r->p;
    return 1;
  }
  return 0;
}

/* A string into buf (escapes kept as the character after the backslash; enough for keys). */
static int read_string(reader_t *r, char *buf, size_t n) {
  ws(r);
  if (r->p >= r->end || *r->p != '"') return -1;
  size_t k = 0;
  for (++r->p; r->p < r->end && *r->p != '"'; ++r->p) {
    if (*r->p == '\\' && r->p + 1 < r->end) ++r->p;
    if (k + 1 < n) buf[k++] = *r->p;
  }
  if (r->p >= r->end) return -1;
  ++r->p;
  if (n > 0) buf[k] = '\0';
  return 0;
}

static int read_number(reader_t *r, double *out) {
  ws(r);
  if (r->end - r->p >= 4 && strncmp(r->p, "null", 4) == 0) {
    r->p += 4;
    *out = NAN;
    return 0;
  }
  char buf[64];
  size_t k = 0;
  while (r->p < r->end && k + 1 < sizeof buf && strchr("+-0123456789.eE", *r->p) != NULL) {
    buf[k++] = *r->p++;
  }
  buf[k] = '\0';
  char *e = NULL;
  *out = strtod(buf, &e);
  return k > 0 && *e == '\0' ? 0 : -1;
}

static int skip_value(reader_t *r);

static int skip_container(reader_t *r, char open, char close) {
  if (!eat(r, open)) return -1;
  if (++r->depth > 64) return -1;
  if (eat(r, close)) {
    --r->depth;
    return 0;
  }
  for (;;) {
    if (open == '{') {
      char key[64];
      if (read_string(r, key, sizeof key) != 0 || !eat(r, ':')) return -1;
    }
    if (skip_value(r) != 0) return -1;
    if (eat(r, ',')) continue;
    if (eat(r, close)) break;
    return -1;
  }
  --r->depth;
  return 0;
}

static int skip_value(reader_t *r) {
  ws(r);
  if (r->p >= r->end) return -1;
  const char c = *r->p;
  if (c == '{') return skip_container(r, '{', '}');
  if (c == '[') return skip_container(r, '[', ']');
  if (c == '"') {
    char tmp[2];
    return read_string(r, tmp, sizeof tmp);
  }
  static const char *const lits[] = {"true", "false", "null"};
  for (int i = 0; i < 3; ++i) {
    const size_t n = strlen(lits[i]);
    if ((size_t)(r->end - r->p) >= n && strncmp(r->p, lits[i], n) == 0) {
      r->p += n;
      return 0;
    }
  }
  double x;
  return read_number(r, &x);
}

/* "objects": [ { ..., "margin_m": x, ... }, ... ] */
static int read_objects(reader_t *r, reply_t *out) {
  if (!eat(r, '[')) return -1;
  if (eat(r, ']')) return 0;
  for (;;) {
    if (!eat(r, '{')) return -1;
    if (!eat(r, '}')) {
      for (;;) {
        char key[64];
        if (read_string(r, key, sizeof key) != 0 || !eat(r, ':')) return -1;
        if (strcmp(key, "margin_m") == 0 && out->levels < MAX_LEVELS) {
          if (read_number(r, &out->margin_m[out->levels++]) != 0) return -1;
        } else if (skip_value(r) != 0) {
          return -1;
        }
        if (eat(r, ',')) continue;
        if (eat(r, '}')) break;
        return -1;
      }
    }
    if (eat(r, ',')) continue;
    if (eat(r, ']')) return 0;
    return -1;
  }
}

/* Parse the reply of `comlearn stack --json`; 0 when "stands" was found. */
static int reply_parse(const char *text, size_t len, reply_t *out) {
  memset(out, 0, sizeof *out);
  out->stands = -1;
  out->seconds_standing = NAN;
  reader_t r = {text, text + len, 0};
  if (!eat(&r, '{')) return -1;
  if (eat(&r, '}')) return -1;
  for (;;) {
    char key[64];
    if (read_string(&r, key, sizeof key) != 0 || !eat(&r, ':')) return -1;
    ws(&r);
    if (strcmp(key, "stands") == 0) {
      if (r.end - r.p >= 4 && strncmp(r.p, "true", 4) == 0) {
        out->stands = 1;
        r.p += 4;
      } else if (r.end - r.p >= 5 && strncmp(r.p, "false", 5) == 0) {
        out->stands = 0;
        r.p += 5;
      } else {
        return -1;
      }
    } else if (strcmp(key, "seconds_standing") == 0) {
      if (read_number(&r, &out->seconds_standing) != 0) return -1;
    } else if (strcmp(key, "com_source") == 0) {
      if (read_string(&r, out->com_source, sizeof out->com_source) != 0) return -1;
    } else if (strcmp(key, "objects") == 0) {
      if (read_objects(&r, out) != 0) return -1;
    } else if (skip_value(&r) != 0) {
      return -1;
    }
    if (eat(&r, ',')) continue;
    if (eat(&r, '}')) break;
    return -1;
  }
  return out->stands >= 0 ? 0 : -1;
}

/* ---- running a command ------------------------------------------------------------------- */

typedef struct {
  int status; /* exit status, 128 + signal, or -1 (could not run / timed out) */
  int timed_out;
  double wall_s;
  size_t out_len;
  char *out;          /* stdout, NUL-terminated (malloc, MAX_OUT at most) */
  char err_tail[256]; /* last line of stderr */
} run_t;

enum { ERR_KEEP = 4096 }; /* bytes of stderr kept, for its last line */

/* argv started with stdout and stderr into pipes, whose read ends are *fd_out and *fd_err.
 * Returns the pid, or -1 (nothing left open). */
static pid_t spawn(char *const argv[], int *fd_out, int *fd_err) {
  int po[2], pe[2];
  if (pipe(po) != 0) return -1;
  if (pipe(pe) != 0) {
    close(po[0]);
    close(po[1]);
    return -1;
  }
  const pid_t pid = fork();
  if (pid < 0) {
    close(po[0]);
    close(po[1]);
    close(pe[0]);
    close(pe[1]);
    return -1;
  }
  if (pid == 0) {
    dup2(po[1], 1);
    dup2(pe[1], 2);
    close(po[0]);
    close(pe[0]);
    close(po[1]);
    close(pe[1]);
    execv(argv[0], argv);
    LOG_E("cannot run %s: %s", argv[0], strerror(errno));
    _exit(127);
  }
  close(po[1]);
  close(pe[1]);
  *fd_out = po[0];
  *fd_err = pe[0];
  return pid;
}

/* Stdout into res->out (MAX_OUT at most), stderr's last ERR_KEEP bytes or more into err, until
 * both pipes close or timeout_s after t0 (then SIGKILL pid, res->timed_out). Closes both. */
static void pump(pid_t pid, int fd_out, int fd_err, double t0, double timeout_s, run_t *res,
                 char err[ERR_KEEP], size_t *err_len) {
  int open_fds = 2;
  struct pollfd fds[2] = {{fd_out, POLLIN, 0}, {fd_err, POLLIN, 0}};
  while (open_fds > 0) {
    const double left = timeout_s - (cli_time_now_s() - t0);
    if (left <= 0.0) {
      kill(pid, SIGKILL);
      res->timed_out = 1;
      break;
    }
    const int n = poll(fds, 2, (int)(left * 1000.0) + 1);
    if (n < 0 && errno != EINTR) break;
    for (int i = 0; i < 2 && n > 0; ++i) {
      if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      char buf[4096];
      const ssize_t got = read(fds[i].fd, buf, sizeof buf);
      if (got <= 0) {
        close(fds[i].fd);
        fds[i].fd = -1;
        --open_fds;
        continue;
      }
      if (i == 0) {
        const size_t room = MAX_OUT - res->out_len, take = (size_t)got < room ? (size_t)got : room;
        memcpy(res->out + res->out_len, buf, take);
        res->out_len += take;
      } else {
        for (ssize_t k = 0; k < got; ++k) { /* keep the last 4 KiB */
          if (*err_len == ERR_KEEP) {
            memmove(err, err + ERR_KEEP / 2, ERR_KEEP / 2);
            *err_len = ERR_KEEP / 2;
          }
          err[(*err_len)++] = buf[k];
        }
      }
    }
  }
  for (int i = 0; i < 2; ++i) {
    if (fds[i].fd >= 0) close(fds[i].fd);
  }
}

/* The last non-empty line of err[0 .. err_len) into tail. */
static void last_line(const char *err, size_t err_len, char *tail, size_t size) {
  while (err_len > 0 && (err[err_len - 1] == '\n' || err[err_len - 1] == '\r')) --err_len;
  size_t start = err_len;
  while (start > 0 && err[start - 1] != '\n') --start;
  const size_t n = err_len - start < size - 1 ? err_len - start : size - 1;
  memcpy(tail, err + start, n);
  tail[n] = '\0';
}

/* Run argv with stdout and stderr captured, at most timeout_s (then SIGKILL). */
static int run_cmd(char *const argv[], double timeout_s, run_t *res) {
  memset(res, 0, sizeof *res);
  res->status = -1;
  res->out = malloc(MAX_OUT + 1);
  if (res->out == NULL) return -1;
  res->out[0] = '\0';
  fflush(stdout);
  fflush(stderr);
  const double t0 = cli_time_now_s();
  int fd_out, fd_err;
  const pid_t pid = spawn(argv, &fd_out, &fd_err);
  if (pid < 0) return -1;
  char err[ERR_KEEP];
  size_t err_len = 0;
  pump(pid, fd_out, fd_err, t0, timeout_s, res, err, &err_len);
  int ws_ = 0;
  while (waitpid(pid, &ws_, 0) < 0 && errno == EINTR) {}
  res->wall_s = cli_time_now_s() - t0;
  res->out[res->out_len] = '\0';
  if (!res->timed_out) {
    res->status = WIFEXITED(ws_) ? WEXITSTATUS(ws_) : 128 + (WIFSIGNALED(ws_) ? WTERMSIG(ws_) : 0);
  }
  last_line(err, err_len, res->err_tail, sizeof res->err_tail);
  return 0;
}

/* ---- statistics -------------------------------------------------------------------------- */

static int cmp_double(const void *a, const void *b) {
  const double x = *(const double *)a, y = *(const double *)b;
  return (x > y) - (x < y);
}

static double median(double *v, size_t n) {
  if (n == 0) return NAN;
  qsort(v, n, sizeof *v, cmp_double);
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* Wilson score interval, 95 %. */
static void wilson(size_t k, size_t n, double *lo, double *hi) {
  if (n == 0) {
    *lo = 0.0;
    *hi = 1.0;
    return;
  }
  const double z = 1.959963984540054, nn = (double)n, p = (double)k / nn;
  const double den = 1.0 + z * z / nn;
  const double mid = (p + z * z / (2.0 * nn)) / den;
  const double half = z * sqrt(p * (1.0 - p) / nn + z * z / (4.0 * nn * nn)) / den;
  *lo = mid - half < 0.0 ? 0.0 : mid - half;
  *hi = mid + half > 1.0 ? 1.0 : mid + half;
}

typedef struct {
  size_t runs, simulated, stands, failed;
  size_t exit_hist[4]; /* failed runs: exit 1, exit 2, other exit, timeout / bad JSON */
  double *fallen_s, *min_margin_m, *wall_s;
  size_t n_fallen, n_margin;
  char first_failure[300];
} stats_t;

/* ---- the bench ---------------------------------------------------------------------------- */

static int make_scratch(char *dir, size_t n) {
  const char *base = getenv("TMPDIR");
  snprintf(dir, n, "%s/bench_stack_XXXXXX", base != NULL && base[0] != '\0' ? base : "/tmp");
  return mkdtemp(dir) != NULL ? 0 : -1;
}

static void remove_scratch(const char *dir, unsigned long long base, size_t rocks) {
  char p[4096];
  for (size_t i = 0; i < rocks; ++i) {
    const unsigned long long s = base + i;
    snprintf(p, sizeof p, "%s/rock_r%llu_even.urdf", dir, s);
    remove(p);
    snprintf(p, sizeof p, "%s/rock_r%llu_uneven.urdf", dir, s);
    remove(p);
    snprintf(p, sizeof p, "%s/meshes/rock_r%llu.stl", dir, s);
    remove(p);
  }
  snprintf(p, sizeof p, "%s/meshes", dir);
  rmdir(p);
  rmdir(dir);
}

static void print_cmd(char *const argv[]) {
  for (size_t i = 0; argv[i] != NULL; ++i) printf("%s%s", i ? " " : "", argv[i]);
  printf("\n");
}

static void usage(FILE *f) {
  fprintf(f,
          "usage: bench_stack [options]\n"
          "Success rate of `comlearn stack` on N random triples of uneven rocks per CoM source.\n"
          "  -n, --count N       triples, 1 .. %d (default 50)\n"
          "  --seed-base S       triple i uses seeds S+3i .. S+3i+2 (default 1000)\n"
          "  --com LIST          sources, comma-separated from learned,bbox,true (default all)\n"
          "  --comlearn PATH     the comlearn binary (default %s)\n"
          "  --rockgen PATH      the comlearn-rockgen binary (default %s)\n"
          "  --timeout S         seconds per call before it is killed and counted failed "
          "(default 600)\n"
          "  --svg-dir DIR       save a side view of the first triple standing with learned CoMs\n"
          "                      (default: none)\n"
          "  --json              print a JSON summary instead of the table (default: off)\n"
          "  --keep              keep the scratch folder of rocks (default: removed)\n"
          "  --dry-run           print the commands, run nothing (default: off)\n"
          "  --parse FILE        parse one `comlearn stack --json` reply, print what was read\n"
          "  -v, --verbose       one line per call on stderr (default: progress on a terminal)\n"
          "  -h, --help          this text\n"
          "  -V, --version       print the version\n"
          "Exit status: 0 done, 1 runtime failure, 2 usage.\n",
          MAX_TRIPLES, COMLEARN_BIN, COMLEARN_ROCKGEN);
}

static int parse_file(const char *path) {
  FILE *f = fopen(path, "rb");
  if (f == NULL) {
    LOG_E("%s: %s", path, strerror(errno));
    return 1;
  }
  char *buf = malloc(MAX_OUT + 1);
  if (buf == NULL) {
    fclose(f);
    return 1;
  }
  const size_t n = fread(buf, 1, MAX_OUT, f);
  fclose(f);
  buf[n] = '\0';
  reply_t r;
  const int rc = reply_parse(buf, n, &r);
  free(buf);
  if (rc != 0) {
    LOG_E("%s: not a `comlearn stack --json` reply", path);
    return 1;
  }
  printf("stands %s\nseconds_standing %.17g\ncom_source %s\nlevels %zu\n",
         r.stands ? "true" : "false", r.seconds_standing, r.com_source, r.levels);
  for (size_t i = 0; i < r.levels; ++i) printf("margin_m[%zu] %.17g\n", i, r.margin_m[i]);
  return 0;
}

typedef struct {
  size_t n;                     /* triples */
  unsigned long long seed_base; /* triple i: seeds seed_base + 3i .. + 2 */
  double timeout_s;
  const char *comlearn, *rockgen, *svg_dir;
  int json, keep, dry, verbose, use[SOURCES];
} opts_t;

/* --com LIST into use. Returns 0, or 2 (logged). */
static int parse_sources(const char *arg, int use[SOURCES]) {
  for (int i = 0; i < SOURCES; ++i) use[i] = 0;
  char list[64];
  snprintf(list, sizeof list, "%s", arg);
  char *save = NULL;
  for (char *t = strtok_r(list, ",", &save); t != NULL; t = strtok_r(NULL, ",", &save)) {
    int found = 0;
    for (int i = 0; i < SOURCES; ++i) {
      if (strcmp(t, kSources[i]) == 0) use[i] = found = 1;
    }
    if (!found) {
      LOG_E("--com: unknown source %s", t);
      return 2;
    }
  }
  return 0;
}

/* Options into o (defaults as usage() says). Returns -1 to go on, else the exit status (--help,
 * --parse, usage errors). */
static int parse_args(int argc, char **argv, opts_t *o) {
  static const struct option opts[] = {{"count", required_argument, NULL, 'n'},
                                       {"seed-base", required_argument, NULL, 'b'},
                                       {"com", required_argument, NULL, 'c'},
                                       {"comlearn", required_argument, NULL, 'C'},
                                       {"rockgen", required_argument, NULL, 'R'},
                                       {"timeout", required_argument, NULL, 'T'},
                                       {"svg-dir", required_argument, NULL, 's'},
                                       {"json", no_argument, NULL, 'j'},
                                       {"keep", no_argument, NULL, 'k'},
                                       {"dry-run", no_argument, NULL, 'd'},
                                       {"parse", required_argument, NULL, 'p'},
                                       {"verbose", no_argument, NULL, 'v'},
                                       {"help", no_argument, NULL, 'h'},
                                       {"version", no_argument, NULL, 'V'},
                                       {NULL, 0, NULL, 0}};
  *o = (opts_t){.n = 50,
                .seed_base = 1000,
                .timeout_s = 600.0,
                .comlearn = COMLEARN_BIN,
                .rockgen = COMLEARN_ROCKGEN,
                .use = {1, 1, 1}};
  long n_triples = 50;
  char *end = NULL;
  int c;
  opterr = 0;
  while ((c = getopt_long(argc, argv, "n:vhV", opts, NULL)) != -1) {
    switch (c) {
      case 'n':
        n_triples = strtol(optarg, &end, 10);
        if (*end != '\0' || n_triples < 1 || n_triples > MAX_TRIPLES) {
          usage(stderr);
          return 2;
        }
        break;
      case 'b':
        errno = 0;
        o->seed_base = strtoull(optarg, &end, 0);
        if (errno != 0 || *end != '\0' || optarg[0] < '0' || optarg[0] > '9') {
          usage(stderr);
          return 2;
        }
        break;
      case 'c':
        if (parse_sources(optarg, o->use) != 0) return 2;
        break;
      case 'C': o->comlearn = optarg; break;
      case 'R': o->rockgen = optarg; break;
      case 'T':
        o->timeout_s = strtod(optarg, &end);
        if (*end != '\0' || !(o->timeout_s > 0.0) || o->timeout_s > 86400.0) {
          usage(stderr);
          return 2;
        }
        break;
      case 's': o->svg_dir = optarg; break;
      case 'j': o->json = 1; break;
      case 'k': o->keep = 1; break;
      case 'd': o->dry = 1; break;
      case 'p': return parse_file(optarg);
      case 'v': o->verbose = 1; break;
      case 'h': usage(stdout); return 0;
      case 'V': cli_version_print(stdout, "bench_stack"); return 0;
      default: cli_getopt_complain("bench_stack", "n:vhV", opts, argv); return 2;
    }
  }
  if (optind != argc) {
    usage(stderr);
    return 2;
  }
  o->n = (size_t)n_triples;
  if (o->seed_base > UINT64_MAX - 3 * o->n) {
    LOG_E("--seed-base too large");
    return 2;
  }
  return -1;
}

/* The bench's state over all calls. */
typedef struct {
  const opts_t *o;
  size_t rocks;
  int progress; /* progress line on stderr */
  char dir[4096];
  stats_t st[SOURCES];
  char svg_saved[4096], svg_tmp[4096];
  size_t ok_calls, calls;
  double t_start;
  cli_progress_t prog; /* over every call (triple x source asked for) */
} bench_t;

/* The scratch folder with the rocks (--dry-run: the command only). Returns 0 or 1 (logged). */
static int rocks_generate(bench_t *b) {
  const opts_t *o = b->o;
  if (o->dry) {
    snprintf(b->dir, sizeof b->dir, "SCRATCH");
  } else if (make_scratch(b->dir, sizeof b->dir) != 0) {
    LOG_E("cannot create a scratch folder: %s", strerror(errno));
    return 1;
  }
  char seed_s[32], count_s[32];
  snprintf(seed_s, sizeof seed_s, "%llu", o->seed_base);
  snprintf(count_s, sizeof count_s, "%zu", b->rocks);
  char *gen_argv[] = {(char *)o->rockgen, "--random", seed_s, "--count", count_s,
                      "--out-dir",        b->dir,     NULL};
  if (o->dry) {
    print_cmd(gen_argv);
    return 0;
  }
  run_t g;
  if (run_cmd(gen_argv, 600.0, &g) != 0 || g.status != 0) {
    LOG_E("%s failed (%d): %s", o->rockgen, g.status, g.err_tail);
    free(g.out);
    remove_scratch(b->dir, o->seed_base, b->rocks);
    return 1;
  }
  free(g.out);
  return 0;
}

/* Per source room for n values of each statistic; the --svg-dir folder. Returns 0 or 1. */
static int bench_alloc(bench_t *b) {
  const size_t n = b->o->n;
  for (int s = 0; s < SOURCES; ++s) {
    b->st[s].fallen_s = malloc(n * sizeof(double));
    b->st[s].min_margin_m = malloc(n * sizeof(double));
    b->st[s].wall_s = malloc(n * sizeof(double));
    if (!b->st[s].fallen_s || !b->st[s].min_margin_m || !b->st[s].wall_s) {
      LOG_E("out of memory");
      return 1;
    }
  }
  const char *svg_dir = b->o->svg_dir;
  if (svg_dir != NULL) {
    if (!b->o->dry && mkdir(svg_dir, 0777) != 0 && errno != EEXIST) {
      LOG_E("cannot create %s: %s", svg_dir, strerror(errno));
      return 1;
    }
    snprintf(b->svg_tmp, sizeof b->svg_tmp, "%s/.bench_stack_candidate.svg", svg_dir);
  }
  return 0;
}

/* A call that did not give a readable reply: counted by exit, the first one kept. */
static void record_failure(stats_t *S, size_t i, const run_t *r) {
  ++S->failed;
  S->exit_hist[r->timed_out || r->status == 0 ? 3
                                              : (r->status == 1 ? 0 : (r->status == 2 ? 1 : 2))]++;
  if (S->first_failure[0] != '\0') return;
  char *ff = S->first_failure;
  const size_t size = sizeof S->first_failure;
  const int len = snprintf(ff, size, "triple %zu: %s%s%d: ", i, r->timed_out ? "timeout " : "",
                           r->status == 0 ? "bad JSON, exit " : "exit ", r->status);
  /* then as much of the stderr line as fits */
  if (len > 0 && (size_t)len < size) {
    const size_t tail = strlen(r->err_tail), room = size - 1 - (size_t)len;
    const size_t take = tail < room ? tail : room;
    memcpy(ff + len, r->err_tail, take);
    ff[(size_t)len + take] = '\0';
  }
}

/* A planned and simulated stack: stands or how long it stood, its smallest margin. */
static void record_reply(stats_t *S, const reply_t *rep) {
  ++S->simulated;
  if (rep->stands) {
    ++S->stands;
  } else if (isfinite(rep->seconds_standing)) {
    S->fallen_s[S->n_fallen++] = rep->seconds_standing;
  }
  double m = HUGE_VAL;
  for (size_t l = 0; l < rep->levels; ++l) {
    if (isfinite(rep->margin_m[l]) && rep->margin_m[l] < m) m = rep->margin_m[l];
  }
  if (rep->levels > 0 && isfinite(m)) S->min_margin_m[S->n_margin++] = m;
}

/* The side view of triple i: kept when the stack stands, else removed. */
static void svg_keep(bench_t *b, size_t i, int stands) {
  const unsigned long long s0 = b->o->seed_base + 3 * i;
  if (stands) {
    snprintf(b->svg_saved, sizeof b->svg_saved, "%s/stack_learned_r%llu_r%llu_r%llu.svg",
             b->o->svg_dir, s0, s0 + 1, s0 + 2);
    if (rename(b->svg_tmp, b->svg_saved) != 0) {
      LOG_E("%s: %s", b->svg_saved, strerror(errno));
      b->svg_saved[0] = '\0';
    }
  } else {
    remove(b->svg_tmp);
  }
}

/* One `comlearn stack` call on triple i with source s. Returns 0, or 1 when it could not run. */
static int bench_call(bench_t *b, size_t i, int s, char urdf[3][4200]) {
  const opts_t *o = b->o;
  const int want_svg = s == 0 && o->svg_dir != NULL && b->svg_saved[0] == '\0';
  char *cmd[16] = {(char *)o->comlearn, "stack",  urdf[0], urdf[1], urdf[2], "--com",
                   (char *)kSources[s], "--json", "-q"};
  size_t argc_cmd = 9;
  if (want_svg) {
    cmd[argc_cmd++] = "--svg";
    cmd[argc_cmd++] = b->svg_tmp;
  }
  cmd[argc_cmd] = NULL;
  if (o->dry) {
    print_cmd(cmd);
    return 0;
  }
  stats_t *S = &b->st[s];
  run_t r;
  ++b->calls;
  if (run_cmd(cmd, o->timeout_s, &r) != 0) {
    LOG_E("cannot run %s: %s", o->comlearn, strerror(errno));
    free(r.out);
    return 1;
  }
  ++S->runs;
  S->wall_s[S->runs - 1] = r.wall_s;
  reply_t rep;
  const int parsed = r.status == 0 && reply_parse(r.out, r.out_len, &rep) == 0;
  if (parsed && strcmp(rep.com_source, kSources[s]) != 0) {
    LOG_E("triple %zu: asked --com %s, reply says \"%s\"", i, kSources[s], rep.com_source);
  }
  if (!parsed) {
    record_failure(S, i, &r);
  } else {
    ++b->ok_calls;
    record_reply(S, &rep);
    if (want_svg) svg_keep(b, i, rep.stands);
  }
  if (o->verbose) {
    fprintf(stderr, "triple %zu %-7s exit %d %s %.2f s%s%s\n", i, kSources[s], r.status,
            parsed ? (rep.stands ? "stands" : "falls") : "FAILED", r.wall_s, parsed ? "" : ": ",
            parsed ? "" : r.err_tail);
  } else if (b->progress) {
    char count[64];
    fprintf(stderr, "\rbench_stack: triple %zu/%zu, call %s, %.0f s    ", i + 1, o->n,
            cli_progress_step(&b->prog, count, sizeof count), cli_time_now_s() - b->t_start);
  }
  free(r.out);
  return 0;
}

/* Every triple with every source asked for. Returns 0, or 1 when a call could not run. */
static int bench_run(bench_t *b) {
  const opts_t *o = b->o;
  for (size_t i = 0; i < o->n; ++i) {
    char urdf[3][4200];
    for (int k = 0; k < 3; ++k) {
      snprintf(urdf[k], sizeof urdf[k], "%s/rock_r%llu_uneven.urdf", b->dir,
               o->seed_base + 3 * i + (unsigned long long)k);
    }
    for (int s = 0; s < SOURCES; ++s) {
      if (o->use[s] && bench_call(b, i, s, urdf) != 0) return 1;
    }
  }
  return 0;
}

/* One source's entry of the JSON "sources" array. */
static void json_source(const stats_t *S, int s, int first, double rate, double lo, double hi,
                        double mf, double mm, double mw) {
  printf(
      "%s\n  {\"com\": \"%s\", \"runs\": %zu, \"simulated\": %zu, \"stands\": %zu, "
      "\"rate\": ",
      first ? "" : ",", kSources[s], S->runs, S->simulated, S->stands);
  cli_json_number(stdout, rate);
  printf(
      ", \"wilson95\": [%.4f, %.4f], \"failed\": %zu, \"failed_exit\": {\"1\": %zu, "
      "\"2\": %zu, \"other\": %zu, \"timeout_or_bad_json\": %zu}, "
      "\"median_seconds_standing_fallen\": ",
      lo, hi, S->failed, S->exit_hist[0], S->exit_hist[1], S->exit_hist[2], S->exit_hist[3]);
  cli_json_number(stdout, mf);
  printf(", \"median_min_margin_m\": ");
  cli_json_number(stdout, mm);
  printf(", \"median_wall_s\": ");
  cli_json_number(stdout, mw);
  printf("}");
}

/* One source's row of the markdown table. */
static void table_source(const stats_t *S, int s, double rate, double lo, double hi, double mf,
                         double mm, double mw) {
  printf("| %s | %zu/%zu | %.2f [%.2f, %.2f] | %zu (%zu / %zu / %zu / %zu) | ", kSources[s],
         S->stands, S->runs, rate, lo, hi, S->failed, S->exit_hist[0], S->exit_hist[1],
         S->exit_hist[2], S->exit_hist[3]);
  if (S->n_fallen) {
    printf("%.2f s (%zu fell) | ", mf, S->n_fallen);
  } else {
    printf("- (none fell) | ");
  }
  if (S->n_margin) {
    printf("%.2f mm | ", 1e3 * mm);
  } else {
    printf("- | ");
  }
  printf("%.2f |\n", mw);
}

/* The report on stdout: a markdown table, or with --json one JSON object. */
static void report(bench_t *b) {
  const opts_t *o = b->o;
  if (o->json) {
    printf("{\"n\": %zu, \"seed_base\": %llu, \"comlearn\": \"%s\", \"sources\": [", o->n,
           o->seed_base, o->comlearn);
  } else {
    printf(
        "`comlearn stack` on %zu random triples of uneven rocks (seeds %llu..%llu, triple i: "
        "rock_r<%llu+3i..+2>).\n\n",
        o->n, o->seed_base, o->seed_base + b->rocks - 1, o->seed_base);
    printf(
        "| --com | stands | rate [Wilson 95 %%] | failed runs (exit 1 / 2 / other / timeout or "
        "bad JSON) | median s standing, fallen | median smallest planned margin | median wall "
        "s / call |\n|---|---|---|---|---|---|---|\n");
  }
  int first = 1;
  for (int s = 0; s < SOURCES; ++s) {
    if (!o->use[s]) continue;
    stats_t *S = &b->st[s];
    double lo, hi;
    wilson(S->stands, S->runs, &lo, &hi);
    const double rate = S->runs ? (double)S->stands / (double)S->runs : NAN;
    const double mf = median(S->fallen_s, S->n_fallen), mm = median(S->min_margin_m, S->n_margin);
    const double mw = median(S->wall_s, S->runs);
    if (o->json)
      json_source(S, s, first, rate, lo, hi, mf, mm, mw);
    else
      table_source(S, s, rate, lo, hi, mf, mm, mw);
    first = 0;
  }
  if (o->json) {
    printf("\n], \"svg\": ");
    if (b->svg_saved[0] != '\0') {
      printf("\"%s\"", b->svg_saved);
    } else {
      printf("null");
    }
    printf(", \"wall_s\": %.1f}\n", cli_time_now_s() - b->t_start);
  } else {
    printf("\nWall time %.0f s for %zu calls.", cli_time_now_s() - b->t_start, b->calls);
    if (b->svg_saved[0] != '\0') printf(" Side view: %s.", b->svg_saved);
    printf("\n");
    for (int s = 0; s < SOURCES; ++s) {
      if (o->use[s] && b->st[s].first_failure[0] != '\0') {
        printf("First failure with --com %s: %s\n", kSources[s], b->st[s].first_failure);
      }
    }
  }
}

int main(int argc, char **argv) {
  cli_log_init("bench_stack");
  opts_t o;
  const int prc = parse_args(argc, argv, &o);
  if (prc >= 0) return prc;
  static bench_t b;
  b.o = &o;
  b.rocks = 3 * o.n;
  b.progress = !o.verbose && !o.dry && isatty(2);
  if (rocks_generate(&b) != 0 || bench_alloc(&b) != 0) return 1;

  b.t_start = cli_time_now_s();
  size_t sources = 0;
  for (int s = 0; s < SOURCES; ++s) sources += o.use[s] != 0;
  cli_progress_start(&b.prog, o.n * sources);
  if (bench_run(&b) != 0) return 1;
  if (b.progress) fprintf(stderr, "\n");
  if (o.svg_dir != NULL && !o.dry) remove(b.svg_tmp);
  if (!o.keep && !o.dry) remove_scratch(b.dir, o.seed_base, b.rocks);
  if (o.dry) return 0;

  report(&b);
  for (int s = 0; s < SOURCES; ++s) {
    free(b.st[s].fallen_s);
    free(b.st[s].min_margin_m);
    free(b.st[s].wall_s);
  }
  return b.ok_calls > 0 ? 0 : 1;
}
