/* A control archive for tests/qlearn_alloc_symbols.cmake: it references malloc and free, so the
 * scan must fail on it (proof that the scan can fail). Not part of any program. */
#include <stdlib.h>

void *alloc_scan_control_get(size_t n);
void alloc_scan_control_put(void *p);

void *alloc_scan_control_get(size_t n) { return malloc(n); }
void alloc_scan_control_put(void *p) { free(p); }
