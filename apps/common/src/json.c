#include <math.h>
#include <stdio.h>

#include "comlearn/cli_json.h"

void cli_json_string(FILE *f, const char *v, int escape_high) {
  fputc('"', f);
  for (const unsigned char *p = (const unsigned char *)(v ? v : ""); *p; ++p) {
    if (*p == '"' || *p == '\\')
      fprintf(f, "\\%c", *p);
    else if (*p < 0x20 || (escape_high && *p >= 0x7f))
      fprintf(f, "\\u%04x", *p);
    else
      fputc(*p, f);
  }
  fputc('"', f);
}

void cli_json_number(FILE *f, double v) {
  if (isfinite(v))
    fprintf(f, "%.9g", v);
  else
    fputs("null", f);
}

void cli_json_array(FILE *f, const double *v, size_t n) {
  fputc('[', f);
  for (size_t i = 0; i < n; ++i) {
    if (i) fputs(", ", f);
    cli_json_number(f, v[i]);
  }
  fputc(']', f);
}

void cli_json_bool(FILE *f, int v) { fputs(v ? "true" : "false", f); }
