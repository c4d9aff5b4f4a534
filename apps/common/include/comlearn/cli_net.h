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

#endif
