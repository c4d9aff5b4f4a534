/* svg.c - cli_svg_text (comlearn/cli_svg.h). */
#include "comlearn/cli_svg.h"

void cli_svg_text(FILE *f, const char *s) {
  for (; s != NULL && *s != '\0'; ++s) {
    switch (*s) {
      case '&': fputs("&amp;", f); break;
      case '<': fputs("&lt;", f); break;
      case '>': fputs("&gt;", f); break;
      case '"': fputs("&quot;", f); break;
      default: fputc(*s, f); break;
    }
  }
}
