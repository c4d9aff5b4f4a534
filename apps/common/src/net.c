/* net.c - the kernel's UDP drop counters for this process's sockets (cli_net.h). */
#define _DEFAULT_SOURCE /* readlink, DT_LNK */

#include <dirent.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "comlearn/cli_net.h"

enum { MAX_SOCKETS = 256 };

/* The inodes of this process's sockets (readlink of /proc/self/fd/N is "socket:[INODE]"). */
static size_t socket_inodes(unsigned long *inode, size_t cap) {
  DIR *d = opendir("/proc/self/fd");
  if (!d) return 0;
  size_t n = 0;
  for (struct dirent *e; n < cap && (e = readdir(d)) != NULL;) {
    if (e->d_name[0] == '.') continue;
    char path[300], link[64];
    snprintf(path, sizeof path, "/proc/self/fd/%s", e->d_name);
    const ssize_t len = readlink(path, link, sizeof link - 1);
    if (len <= 0) continue;
    link[len] = '\0';
    unsigned long ino = 0;
    if (sscanf(link, "socket:[%lu]", &ino) == 1) inode[n++] = ino;
  }
  closedir(d);
  return n;
}

/* Sum the drops of the listed inodes in one /proc/net/udp-style table; -1 when unreadable. */
static int table_drops(const char *path, const unsigned long *inode, size_t n, uint64_t *sum) {
  FILE *f = fopen(path, "r");
  if (!f) return -1;
  char line[512];
  if (!fgets(line, sizeof line, f)) { /* the header */
    fclose(f);
    return -1;
  }
  while (fgets(line, sizeof line, f)) {
    /* sl local rem st tx:rx tr:when retrnsmt uid timeout inode ref pointer drops */
    unsigned long ino = 0;
    unsigned long long drops = 0;
    if (sscanf(line, "%*s %*s %*s %*s %*s %*s %*s %*s %*s %lu %*s %*s %llu", &ino, &drops) != 2)
      continue;
    for (size_t i = 0; i < n; ++i)
      if (inode[i] == ino) *sum += drops;
  }
  fclose(f);
  return 0;
}

int cli_udp_drops(uint64_t *drops) {
  *drops = 0;
  unsigned long inode[MAX_SOCKETS];
  const size_t n = socket_inodes(inode, MAX_SOCKETS);
  uint64_t sum = 0;
  const int v4 = table_drops("/proc/self/net/udp", inode, n, &sum);
  const int v6 = table_drops("/proc/self/net/udp6", inode, n, &sum);
  if (v4 != 0 && v6 != 0) return -1;
  *drops = sum;
  return 0;
}
