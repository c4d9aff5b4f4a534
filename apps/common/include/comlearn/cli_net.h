/* cli_net.h - what the kernel dropped before LCM could read it.
 *
 * LCM's udpm provider (Debian's 1.3.1) reads datagrams on a thread of its own and gives no count
 * of what it never saw: a burst larger than the socket's receive buffer (a message of 1 MiB is 16
 * fragments of 64 KiB, against a default buffer of 208 KiB) is dropped by the kernel, fragment by
 * fragment, and LCM then drops the incomplete message. The kernel counts those drops per socket;
 * this reads them for the calling process. */
#ifndef COMLEARN_CLI_NET_H
#define COMLEARN_CLI_NET_H

#include <stdint.h>

/* Datagrams the kernel dropped on this process's UDP sockets (IPv4 and IPv6) since they were
 * opened: the "drops" column of /proc/self/net/udp{,6} for every socket among /proc/self/fd.
 * 0 and *drops set on success; -1 when /proc cannot be read (then *drops is 0). */
int cli_udp_drops(uint64_t *drops);

#endif
