/* fuzz_file.h - for the file harnesses: the input written to one scratch file per process, named
 * with the extension the loader should try. */
#ifndef COMLEARN_FUZZ_FILE_H
#define COMLEARN_FUZZ_FILE_H

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <unistd.h>

/* Write data to $TMPDIR/comlearn_fuzz_<pid>.<ext> and return its path (static storage); NULL when
 * the file cannot be written. */
static inline const char *fuzz_file(const uint8_t *data, size_t size, const char *ext) {
  static char path[512];
  const char *tmp = getenv("TMPDIR");
  snprintf(path, sizeof path, "%s/comlearn_fuzz_%d.%s", tmp && tmp[0] ? tmp : "/tmp", (int)getpid(),
           ext);
  FILE *f = fopen(path, "wb");
  if (f == NULL) return NULL;
  const int ok = fwrite(data, 1, size, f) == size;
  return fclose(f) == 0 && ok ? path : NULL;
}

#endif
