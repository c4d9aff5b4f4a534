/* net.c - the kernel's UDP drop counters and receive buffers of this process's sockets, and the
 * receive buffer comlearn asks LCM for (cli_net.h). */
#define _DEFAULT_SOURCE /* readlink, DT_LNK */

#include <dirent.h>
#include <errno.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "comlearn/cli_log.h"
#include "comlearn/cli_net.h"

enum { MAX_SOCKETS = 256 };

/* The inodes of process pid's sockets (0: this process; readlink of /proc/PID/fd/N is
 * "socket:[INODE]"), and their descriptors when fd is not NULL. */
static size_t socket_inodes(pid_t pid, unsigned long *inode, int *fd, size_t cap) {
  char dir[64];
  if (pid == 0)
    snprintf(dir, sizeof dir, "/proc/self/fd");
  else
    snprintf(dir, sizeof dir, "/proc/%ld/fd", (long)pid);
  DIR *d = opendir(dir);
  if (!d) return 0;
  size_t n = 0;
  for (struct dirent *e; n < cap && (e = readdir(d)) != NULL;) {
    if (e->d_name[0] == '.') continue;
    char path[400], link[64];
    snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
    const ssize_t len = readlink(path, link, sizeof link - 1);
    if (len <= 0) continue;
    link[len] = '\0';
    unsigned long ino = 0;
    if (sscanf(link, "socket:[%lu]", &ino) != 1) continue;
    if (fd != NULL) fd[n] = atoi(e->d_name);
    inode[n++] = ino;
  }
  closedir(d);
  return n;
}

/* Sum the drops of the listed inodes in one /proc/net/udp-style table (sum may be NULL; in_table
 * gets a 1 for each inode listed there when not NULL); -1 when unreadable. */
static int table_drops(const char *path, const unsigned long *inode, size_t n, uint64_t *sum,
                       unsigned char *in_table) {
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
    for (size_t i = 0; i < n; ++i) {
      if (inode[i] != ino) continue;
      if (sum != NULL) *sum += drops;
      if (in_table != NULL) in_table[i] = 1;
    }
  }
  fclose(f);
  return 0;
}

int cli_udp_drops_of(pid_t pid, uint64_t *drops) {
  *drops = 0;
  unsigned long inode[MAX_SOCKETS];
  const size_t n = socket_inodes(pid, inode, NULL, MAX_SOCKETS);
  char v4path[64], v6path[64];
  snprintf(v4path, sizeof v4path, pid == 0 ? "/proc/self/net/udp" : "/proc/%ld/net/udp", (long)pid);
  snprintf(v6path, sizeof v6path, pid == 0 ? "/proc/self/net/udp6" : "/proc/%ld/net/udp6",
           (long)pid);
  uint64_t sum = 0;
  const int v4 = table_drops(v4path, inode, n, &sum, NULL);
  const int v6 = table_drops(v6path, inode, n, &sum, NULL);
  if (v4 != 0 && v6 != 0) return -1;
  *drops = sum;
  return 0;
}

int cli_udp_drops(uint64_t *drops) { return cli_udp_drops_of(0, drops); }

int cli_udp_rcvbuf_max(int *bytes) {
  *bytes = 0;
  unsigned long inode[MAX_SOCKETS];
  int fd[MAX_SOCKETS];
  unsigned char udp[MAX_SOCKETS] = {0};
  const size_t n = socket_inodes(0, inode, fd, MAX_SOCKETS);
  const int v4 = table_drops("/proc/self/net/udp", inode, n, NULL, udp);
  const int v6 = table_drops("/proc/self/net/udp6", inode, n, NULL, udp);
  if (v4 != 0 && v6 != 0) return -1;
  int best = -1;
  for (size_t i = 0; i < n; ++i) {
    int size = 0;
    socklen_t len = sizeof size;
    if (udp[i] && getsockopt(fd[i], SOL_SOCKET, SO_RCVBUF, &size, &len) == 0 && size > best)
      best = size;
  }
  if (best < 0) return -1;
  *bytes = best;
  return 0;
}

int cli_lcm_url_buffered(const char *url, char *out, size_t size) {
  if (url == NULL || out == NULL || size == 0) return -1;
  int k;
  if (strncmp(url, "udpm://", 7) != 0 || strstr(url, "recv_buf_size=") != NULL)
    k = snprintf(out, size, "%s", url);
  else
    k = snprintf(out, size, "%s%crecv_buf_size=%d", url, strchr(url, '?') ? '&' : '?',
                 CLI_LCM_RECV_BUF_BYTES);
  return k >= 0 && (size_t)k < size ? 0 : -1;
}

void cli_lcm_buffer_check(const char *url) {
  const char *p =
      url != NULL && strncmp(url, "udpm://", 7) == 0 ? strstr(url, "recv_buf_size=") : NULL;
  if (p == NULL) return;
  errno = 0;
  const long asked = strtol(p + strlen("recv_buf_size="), NULL, 10);
  int got = 0;
  if (errno != 0 || asked <= 0 || cli_udp_rcvbuf_max(&got) != 0) return;
  /* Linux doubles what is set (for its bookkeeping) and caps the request at net.core.rmem_max */
  if ((long)got / 2 < asked)
    LOG_W(
        "LCM's receive buffer is %d KiB, not the %ld KiB asked: net.core.rmem_max caps it, and "
        "bursts of messages may be dropped (as root: echo %ld > /proc/sys/net/core/rmem_max; "
        "scripts/setup.sh does it)",
        got / 2 / 1024, asked / 1024, asked);
}
