/*
 * comlearn/cli_json.h - the one JSON writer of the comlearn programs (target comlearn_cli): the
 * values that `--json` outputs and the benches' JSON are made of. The program writes the
 * punctuation and keys itself; these write the values that need care.
 *
 * Every function writes to f (borrowed, not NULL) and reports nothing: the caller checks
 * ferror(f) once at the end. Thread-safety: that of stdio on f.
 */
#ifndef COMLEARN_CLI_JSON_H
#define COMLEARN_CLI_JSON_H

#include <stddef.h>
#include <stdio.h>

/* A JSON string: '"' and '\\' escaped with a backslash, control bytes (< 0x20) as \u00XX.
 * escape_high: also write bytes >= 0x7f as \u00XX (byte strings from LCM, shown as Latin-1 like
 * lcm-spy); else pass them through (UTF-8). v NULL: "". */
void cli_json_string(FILE *f, const char *v, int escape_high);

/* A JSON number (%.9g: a double's value to 9 significant digits), or null when not finite. */
void cli_json_number(FILE *f, double v);

/* A JSON array of n numbers as cli_json_number, ", " between them: [1, null, 2.5]. v may be
 * NULL when n is 0. */
void cli_json_array(FILE *f, const double *v, size_t n);

/* true or false. */
void cli_json_bool(FILE *f, int v);

#endif
