/* out.h - what the comlearn commands share for their output: JSON values on stdout and a
 * monotonic clock. Not thread-safe (stdout). */
#ifndef COMLEARN_APP_OUT_H
#define COMLEARN_APP_OUT_H

/* A JSON string with '"', '\\' and control characters escaped. escape_high: also write bytes
 * >= 0x7f as \u00XX (byte strings from LCM, shown as Latin-1 like lcm-spy); else pass them (UTF-8). */
void out_json_string(const char *v, int escape_high);

/* A JSON number (%.9g), or null when not finite. */
void out_json_number(double v);

/* A JSON array of n numbers, as out_json_number. */
void out_json_array(const double *v, int n);

/* Seconds of CLOCK_MONOTONIC. */
double out_now_s(void);

#endif
