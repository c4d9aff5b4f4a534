/* net.c - the kernel's UDP drop counters and receive buffers of this process's sockets, and the
 * receive buffer comlearn asks LCM for (cli_net.h). */
#define _DEFAULT_SOURCE /* readlink, DT_LNK */

#include <dirent.h>
#include <errno.h>
#include <inttypes.h>
#include <linux/filter.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "comlearn/cli_log.h"
#include "comlearn/cli_net.h"

enum { MAX_SOCKETS = CLI_NET_SOCKETS_MAX };

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

/* RcvbufErrors from /proc/self/net/snmp: a "Udp:" line of names, then one of values. */
static int snmp_udp_rcvbuf_errors(uint64_t *n) {
  FILE *f = fopen("/proc/self/net/snmp", "r");
  if (!f) return -1;
  char names[1024], values[1024];
  int rc = -1;
  while (rc != 0 && fgets(names, sizeof names, f)) {
    if (strncmp(names, "Udp: ", 5) != 0 || !fgets(values, sizeof values, f)) continue;
    char *sn = NULL, *sv = NULL;
    char *a = strtok_r(names, " \n", &sn), *b = strtok_r(values, " \n", &sv);
    for (; a && b; a = strtok_r(NULL, " \n", &sn), b = strtok_r(NULL, " \n", &sv))
      if (strcmp(a, "RcvbufErrors") == 0) {
        *n += strtoull(b, NULL, 10);
        rc = 0;
        break;
      }
  }
  fclose(f);
  return rc;
}

/* Udp6RcvbufErrors from /proc/self/net/snmp6: "name value" lines. */
static int snmp6_udp_rcvbuf_errors(uint64_t *n) {
  FILE *f = fopen("/proc/self/net/snmp6", "r");
  if (!f) return -1;
  char line[256];
  int rc = -1;
  unsigned long long v = 0;
  while (rc != 0 && fgets(line, sizeof line, f))
    if (sscanf(line, "Udp6RcvbufErrors %llu", &v) == 1) {
      *n += v;
      rc = 0;
    }
  fclose(f);
  return rc;
}

int cli_udp_rcvbuf_errors(uint64_t *n) {
  *n = 0;
  const int v4 = snmp_udp_rcvbuf_errors(n), v6 = snmp6_udp_rcvbuf_errors(n);
  return v4 == 0 || v6 == 0 ? 0 : -1;
}

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

/* ---- the channel filter ---------------------------------------------------------------------- */

/* Offsets in what a UDP socket filter sees: the UDP header (8 bytes), then LCM's short header
 * (magic, sequence number: 4 bytes each, network order), then the channel with its NUL. */
enum { OFF_MAGIC = 8, OFF_CHANNEL = 16, LCM_MAGIC_SHORT = 0x4c433032 /* "LC02" */ };
enum { CHANNEL_MAX = 63 };

static struct sock_filter insn(uint16_t code, uint8_t jt, uint8_t jf, uint32_t k) {
  struct sock_filter f = {code, jt, jf, k};
  return f;
}

/* The bytes [i, i + w) of s (w 1, 2 or 4, s read with its NUL as if padded with more) as the
 * big-endian number a BPF load of that width gives. */
static uint32_t be_bytes(const char *s, size_t len, size_t i, size_t w) {
  uint32_t v = 0;
  for (size_t k = 0; k < w; ++k)
    v = (v << 8) | (uint32_t)(unsigned char)(i + k < len ? s[i + k] : '\0');
  return v;
}

int cli_lcm_filter_build(const char *const *channels, size_t n, void *out) {
  struct sock_filter *prog = out;
  if (channels == NULL || prog == NULL || n == 0 || n > CLI_LCM_FILTER_CHANNELS_MAX) return -1;
  size_t c = 0;
  /* not a short LCM message (or too short to hold a magic): LCM decides */
  prog[c++] = insn(BPF_LD | BPF_W | BPF_ABS, 0, 0, OFF_MAGIC);
  prog[c++] = insn(BPF_JMP | BPF_JEQ | BPF_K, 1, 0, LCM_MAGIC_SHORT);
  prog[c++] = insn(BPF_RET | BPF_K, 0, 0, 0xffffffffu);
  for (size_t j = 0; j < n; ++j) {
    if (channels[j] == NULL) return -1;
    const size_t len = strlen(channels[j]);
    if (len == 0 || len > CHANNEL_MAX) return -1;
    /* the channel and its NUL, in loads of 4, then 2, then 1 bytes; each mismatch jumps to the
     * next channel's block, past the loads left and the accept */
    const size_t total = len + 1;
    size_t loads = total / 4 + (total % 4 >= 2) + (total % 2);
    size_t left = 2 * loads; /* instructions of this block after the current one, accept excluded */
    for (size_t i = 0; i < total;) {
      const size_t w = total - i >= 4 ? 4 : total - i >= 2 ? 2 : 1;
      const uint16_t size = w == 4 ? BPF_W : w == 2 ? BPF_H : BPF_B;
      prog[c++] = insn(BPF_LD | size | BPF_ABS, 0, 0, (uint32_t)(OFF_CHANNEL + i));
      left -= 2;
      /* on a mismatch skip the rest of the block: its loads and compares, and the accept */
      prog[c++] =
          insn(BPF_JMP | BPF_JEQ | BPF_K, 0, (uint8_t)(left + 1), be_bytes(channels[j], len, i, w));
      i += w;
    }
    prog[c++] = insn(BPF_RET | BPF_K, 0, 0, 0xffffffffu);
  }
  prog[c++] = insn(BPF_RET | BPF_K, 0, 0, 0); /* another channel: dropped */
  return (int)c;
}

int cli_lcm_filter_attach(int fd, const char *const *channels, size_t n) {
  struct sock_filter prog[CLI_LCM_FILTER_INSNS_MAX];
  const int len = cli_lcm_filter_build(channels, n, prog);
  if (len < 0) {
    errno = EINVAL;
    return -1;
  }
  struct sock_fprog fp = {.len = (unsigned short)len, .filter = prog};
  return setsockopt(fd, SOL_SOCKET, SO_ATTACH_FILTER, &fp, sizeof fp) == 0 ? 0 : -1;
}

void cli_socket_set_now(cli_socket_set_t *set) {
  set->n = socket_inodes(0, set->inode, NULL, CLI_NET_SOCKETS_MAX);
}

int cli_lcm_receive_setup(const char *url, const cli_socket_set_t *before,
                          const char *const *channels, size_t n) {
  cli_lcm_buffer_check(url);
  const int filtered = cli_lcm_filter_new_sockets(before, channels, n);
  if (filtered < 0)
    LOG_W("no kernel filter on LCM's receive socket (%s): every datagram on %s wakes it",
          strerror(errno), url ? url : "the URL");
  return filtered;
}

int cli_lcm_filter_new_sockets(const cli_socket_set_t *before, const char *const *channels,
                               size_t n) {
  unsigned long inode[MAX_SOCKETS];
  int fd[MAX_SOCKETS];
  unsigned char udp[MAX_SOCKETS] = {0};
  const size_t m = socket_inodes(0, inode, fd, MAX_SOCKETS);
  if (table_drops("/proc/self/net/udp", inode, m, NULL, udp) != 0) return -1;
  int filtered = 0;
  for (size_t i = 0; i < m; ++i) {
    if (!udp[i]) continue;
    int old = 0;
    for (size_t k = 0; before != NULL && k < before->n && !old; ++k)
      old = before->inode[k] == inode[i];
    struct sockaddr_in a;
    socklen_t alen = sizeof a;
    if (old || getsockname(fd[i], (struct sockaddr *)&a, &alen) != 0 || a.sin_family != AF_INET ||
        a.sin_port == 0)
      continue;
    if (cli_lcm_filter_attach(fd[i], channels, n) != 0) return -1;
    filtered++;
  }
  return filtered;
}
