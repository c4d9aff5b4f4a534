/* cli_args.h - what every comlearn program's command line shares: the version it prints for
 * --version, and the message for an option getopt_long refused, named as the user typed it. */
#ifndef COMLEARN_CLI_ARGS_H
#define COMLEARN_CLI_ARGS_H

#include <getopt.h>
#include <stddef.h>
#include <stdio.h>

/* The comlearn version, the CMake project's ("0.1.0"). */
const char *cli_version(void);

/* "PROG VERSION\n" on out: what --version prints. */
void cli_version_print(FILE *out, const char *prog);

/* After getopt_long returned '?' (or ':') at argv[optind - 1]: why, on stderr, as
 * "PROG: error: ...", naming the option as the user wrote it: "--seed needs a value" for a long
 * option (or a unique abbreviation of one) given without its value, "-o needs a value" for a
 * short option that takes one in optstring, "--quiet takes no value", else "unknown option
 * '...'"; then "try 'PROG --help'". optstring and longopts are those given to getopt_long
 * (either may be NULL). Reads getopt's optopt and optind. */
void cli_getopt_complain(const char *prog, const char *optstring, const struct option *longopts,
                         char **argv);

/* After the options, for a program that takes no arguments: 0 when argv[optind..argc) is empty,
 * else "PROG: error: unexpected argument 'X'" and "try 'PROG --help'" on stderr, and 2 (the
 * usage exit status). Reads getopt's optind. */
int cli_args_none_left(const char *prog, int argc, char **argv);

/* Exactly n finite numbers separated by commas (spaces around them allowed) into out[0..n):
 * 0, or -1 when text has fewer, more, an empty or non-numeric item, or a non-finite value
 * (out unchanged then). The caller names the option in its message. */
int cli_args_numbers(const char *text, double *out, size_t n);

#endif
