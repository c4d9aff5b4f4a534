/* cli_net.h - what the kernel dropped before LCM could read it.
 *
 * LCM's udpm provider (Debian's 1.3.1) reads datagrams on a thread of its own and gives no count
 * of what it never saw: a burst larger than the socket's receive buffer (a message of 1 MiB is 16
 * fragments of 64 KiB, against a default buffer of 208 KiB) is dropped by the kernel, fragment by
 * fragment, and LCM then drops the incomplete message. The kernel counts those drops per socket;
 * this reads them for the calling process, and sizes the buffer comlearn asks LCM for. */
#ifndef COMLEARN_CLI_NET_H
#define COMLEARN_CLI_NET_H

#include <stddef.h>
#include <stdint.h>
#include <sys/types.h>

/* Datagrams the kernel dropped on this process's UDP sockets (IPv4 and IPv6) since they were
 * opened: the "drops" column of /proc/self/net/udp{,6} for every socket among /proc/self/fd.
 * 0 and *drops set on success; -1 when /proc cannot be read (then *drops is 0). */
int cli_udp_drops(uint64_t *drops);

/* The same for process pid (0: this one): its sockets among /proc/PID/fd, which needs the right
 * to read them (the same user, or root). */
int cli_udp_drops_of(pid_t pid, uint64_t *drops);

/* A socket's drop count holds both what a full receive buffer lost and what a socket filter
 * (cli_lcm_filter_attach below) turned away on purpose. The datagrams lost to a full receive
 * buffer alone are counted only for the whole network namespace (this host, outside
 * containers): RcvbufErrors of /proc/net/snmp (Udp) plus Udp6RcvbufErrors of /proc/net/snmp6.
 * Their sum into *n and 0; -1 when neither can be read (*n 0). */
int cli_udp_rcvbuf_errors(uint64_t *n);

/* The largest receive buffer among this process's bound UDP sockets (those /proc/net/udp{,6}
 * lists), as the kernel reports it (getsockopt SO_RCVBUF: on Linux twice what was set). 0 and
 * *bytes set; -1 when the process has none or /proc cannot be read (*bytes 0). */
int cli_udp_rcvbuf_max(int *bytes);

/* The receive buffer comlearn's programs ask LCM for: a status stream and a command burst at
 * once overflowed the 208 KiB default (docs/messages.md, "Receive buffers"). */
#define CLI_LCM_RECV_BUF_BYTES 4194304

/* url into out (size bytes) with "recv_buf_size=CLI_LCM_RECV_BUF_BYTES" added when it is a udpm
 * URL that names no recv_buf_size; any other URL as it is. 0 ok; -1 when out is too small (or
 * NULL arguments). */
int cli_lcm_url_buffered(const char *url, char *out, size_t size);

/* After lcm_create(url): a warning (cli_log) when url asks for a recv_buf_size and this process's
 * largest UDP receive buffer is smaller (net.core.rmem_max caps what a process may set). Nothing
 * for other URLs. */
void cli_lcm_buffer_check(const char *url);

/* ---- a kernel filter on LCM's receive socket ------------------------------------------------
 *
 * Every process on a udpm URL is handed every datagram sent to it: its own publications (a
 * comlearn-sim hears each of its statuses) and, with many robots on one URL, every other robot's
 * traffic. LCM's receive thread wakes for each, reads it and throws away what nobody subscribed
 * to. A socket filter (SO_ATTACH_FILTER, classic BPF) on LCM's receive socket lets the kernel drop
 * those before anyone wakes (docs/messages.md, "Many robots on one URL"). */

enum { CLI_NET_SOCKETS_MAX = 256, CLI_LCM_FILTER_CHANNELS_MAX = 8, CLI_LCM_FILTER_INSNS_MAX = 512 };

/* The socket inodes of this process at one moment. */
typedef struct {
  unsigned long inode[CLI_NET_SOCKETS_MAX];
  size_t n;
} cli_socket_set_t;

/* This process's sockets now: taken before the first lcm_subscribe on an lcm_t, it tells the
 * receive socket that subscription opens from every socket that was there before. */
void cli_socket_set_now(cli_socket_set_t *set);

/* The filter program for channels[0..n) (each 1..63 bytes, n 1..CLI_LCM_FILTER_CHANNELS_MAX):
 * it passes an LCM short message (magic "LC02") whose channel is one of them, and every datagram
 * that is not a short LCM message (a fragment of a long one, anything else: LCM judges those);
 * it drops short messages on other channels. prog must hold CLI_LCM_FILTER_INSNS_MAX entries of
 * struct sock_filter (linux/filter.h). Returns the number of instructions, -1 on bad arguments. */
int cli_lcm_filter_build(const char *const *channels, size_t n, void *prog);

/* Attach that filter to the UDP socket fd. 0 ok; -1 with errno (EINVAL for bad channels). */
int cli_lcm_filter_attach(int fd, const char *const *channels, size_t n);

/* Attach it to every UDP socket of this process bound to a port that was not in `before` (LCM's
 * receive socket, opened by the first lcm_subscribe since). Returns how many got it: 1 for a
 * udpm lcm_t, 0 when there is none (another provider, or subscribed before `before`); -1 when
 * /proc cannot be read or attaching failed (errno). Without it everything works as before, only
 * slower. */
int cli_lcm_filter_new_sockets(const cli_socket_set_t *before, const char *const *channels,
                               size_t n);

/* Right after the first lcm_subscribe on a udpm lcm_t of url (before: the sockets just before
 * it): cli_lcm_buffer_check(url), then cli_lcm_filter_new_sockets for the process's channels,
 * with a warning (cli_log) when the filter cannot be attached. Returns what the latter does. */
int cli_lcm_receive_setup(const char *url, const cli_socket_set_t *before,
                          const char *const *channels, size_t n);

#endif
