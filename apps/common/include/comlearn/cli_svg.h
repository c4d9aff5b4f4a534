/*
 * comlearn/cli_svg.h - what the programs' SVG pictures share (target comlearn_cli): text made
 * safe for SVG (XML) character data and attribute values. Writes to f (borrowed, not NULL) and
 * reports nothing: the caller checks ferror(f) once at the end.
 */
#ifndef COMLEARN_CLI_SVG_H
#define COMLEARN_CLI_SVG_H

#include <stdio.h>

/* s with &, <, > and " written as entities; NULL writes nothing. */
void cli_svg_text(FILE *f, const char *s);

#endif
