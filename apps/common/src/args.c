/* args.c - the version and getopt's refusals (cli_args.h). */
#include "comlearn/cli_args.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#ifndef COMLEARN_VERSION
#error "COMLEARN_VERSION is set by apps/common/CMakeLists.txt"
#endif

const char *cli_version(void) { return COMLEARN_VERSION; }

void cli_version_print(FILE *out, const char *prog) {
  fprintf(out, "%s %s\n", prog, COMLEARN_VERSION);
}

void cli_getopt_complain(const char *prog, const char *optstring, const struct option *longopts,
                         char **argv) {
  /* getopt_long leaves optind past the word it refused (and past a missing value: the end) */
  const char *word = optind > 0 && argv[optind - 1] ? argv[optind - 1] : "";
  const struct option *o = NULL;
  if (strncmp(word, "--", 2) == 0 && longopts) { /* --name or --name=value */
    const char *name = word + 2;
    const size_t n = strcspn(name, "=");
    int prefixes = 0; /* getopt_long takes a unique abbreviation too */
    const struct option *prefix = NULL;
    for (const struct option *p = longopts; p->name; ++p) {
      if (strncmp(p->name, name, n) != 0) continue;
      if (strlen(p->name) == n) o = p;
      prefix = p;
      ++prefixes;
    }
    if (!o && prefixes == 1 && n > 0) o = prefix;
  }
  if (o && o->has_arg == required_argument)
    fprintf(stderr, "%s: error: --%s needs a value\n", prog, o->name);
  else if (o && o->has_arg == no_argument && strchr(word, '='))
    fprintf(stderr, "%s: error: --%s takes no value: '%s'\n", prog, o->name, word);
  else if (optopt > 0 && optopt < 128 && optopt != ':' && strncmp(word, "--", 2) != 0 &&
           optstring && strchr(optstring, optopt) && strchr(optstring, optopt)[1] == ':')
    fprintf(stderr, "%s: error: -%c needs a value\n", prog, optopt);
  else if (optopt > 0 && optopt < 128 && strncmp(word, "--", 2) != 0)
    fprintf(stderr, "%s: error: unknown option '-%c'\n", prog, optopt);
  else
    fprintf(stderr, "%s: error: unknown option '%s'\n", prog, word);
  fprintf(stderr, "try '%s --help'\n", prog);
}

int cli_args_none_left(const char *prog, int argc, char **argv) {
  if (optind >= argc) return 0;
  fprintf(stderr, "%s: error: unexpected argument '%s'\ntry '%s --help'\n", prog, argv[optind],
          prog);
  return 2;
}

int cli_args_numbers(const char *text, double *out, size_t n) {
  if (!text || !out || n == 0 || n > 64) return -1;
  double v[64];
  const char *p = text;
  for (size_t k = 0; k < n; ++k) {
    char *end;
    errno = 0;
    v[k] = strtod(p, &end);
    if (end == p || errno != 0 || !isfinite(v[k])) return -1;
    while (*end == ' ') ++end;
    if (k + 1 < n) {
      if (*end != ',') return -1;
      p = end + 1;
    } else if (*end != '\0') {
      return -1;
    }
  }
  memcpy(out, v, n * sizeof *out);
  return 0;
}
