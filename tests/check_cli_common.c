#define _DEFAULT_SOURCE /* SO_ATTACH_FILTER; POSIX 2008 with it */
/* check_cli_common: comlearn_cli (apps/common), what the programs share: the JSON value writer
 * (escaping, 9 significant digits, non-finite numbers as null) and the logger (prefix, level
 * names, the level filter, clamping), byte for byte against the expected text; the kernel's UDP
 * drop counter and receive buffers of the process's sockets, the LCM receive buffer the
 * programs ask for, and the kernel filter that passes an LCM socket only the channels it reads. */
#include <arpa/inet.h>
#include <check.h>
#include <errno.h>
#include <linux/filter.h>
#include <math.h>
#include <netinet/in.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "comlearn/cli_json.h"
#include "comlearn/cli_log.h"
#include "comlearn/cli_net.h"
#include "comlearn/cli_stop.h"
#include "comlearn/cli_svg.h"
#include "comlearn/cli_time.h"

/* What the writer wrote to a memory stream, as a string (static; valid until the next call). */
typedef struct {
  FILE *f;
  char *buf;
  size_t len;
} capture_t;

static void capture_open(capture_t *c) {
  c->buf = NULL;
  c->len = 0;
  c->f = open_memstream(&c->buf, &c->len);
  ck_assert_ptr_nonnull(c->f);
}

static const char *capture_close(capture_t *c) {
  ck_assert_int_eq(fclose(c->f), 0);
  static char out[1024];
  ck_assert_uint_lt(c->len, sizeof out);
  memcpy(out, c->buf, c->len + 1);
  free(c->buf);
  return out;
}

START_TEST(json_string_escapes) {
  capture_t c;
  capture_open(&c);
  cli_json_string(c.f, "a\"b\\c\nd\te\x01\x1f", 0);
  ck_assert_str_eq(capture_close(&c), "\"a\\\"b\\\\c\\u000ad\\u0009e\\u0001\\u001f\"");
  /* high bytes: passed through (UTF-8), or \u00XX (Latin-1, like lcm-spy) with escape_high;
   * 0x7f (DEL) is escaped only then */
  capture_open(&c);
  cli_json_string(c.f, "caf\xc3\xa9\x7f", 0);
  ck_assert_str_eq(capture_close(&c), "\"caf\xc3\xa9\x7f\"");
  capture_open(&c);
  cli_json_string(c.f, "caf\xc3\xa9\x7f", 1);
  ck_assert_str_eq(capture_close(&c), "\"caf\\u00c3\\u00a9\\u007f\"");
  capture_open(&c);
  cli_json_string(c.f, NULL, 0);
  cli_json_string(c.f, "", 1);
  cli_json_string(c.f, "/ plain ~", 1);
  ck_assert_str_eq(capture_close(&c), "\"\"\"\"\"/ plain ~\"");
}
END_TEST

START_TEST(svg_text_escapes) {
  capture_t c;
  capture_open(&c);
  cli_svg_text(c.f, "a<b>&\"c' caf\xc3\xa9");
  cli_svg_text(c.f, NULL);
  cli_svg_text(c.f, "");
  ck_assert_str_eq(capture_close(&c), "a&lt;b&gt;&amp;&quot;c' caf\xc3\xa9");
}
END_TEST

START_TEST(json_numbers_and_non_finite) {
  capture_t c;
  capture_open(&c);
  const double v[] = {0.0, -0.0, 1.5, 0.1, -2.25e-7, 123456789012.0, 1e300, 3.14159265358979};
  for (size_t i = 0; i < sizeof v / sizeof v[0]; ++i) {
    if (i) fputc(' ', c.f);
    cli_json_number(c.f, v[i]);
  }
  ck_assert_str_eq(capture_close(&c), "0 -0 1.5 0.1 -2.25e-07 1.23456789e+11 1e+300 3.14159265");
  capture_open(&c);
  cli_json_number(c.f, NAN);
  fputc(' ', c.f);
  cli_json_number(c.f, INFINITY);
  fputc(' ', c.f);
  cli_json_number(c.f, -INFINITY);
  ck_assert_str_eq(capture_close(&c), "null null null");
}
END_TEST

START_TEST(json_arrays_and_bools) {
  capture_t c;
  capture_open(&c);
  const double v[4] = {1.0, NAN, 2.5, -INFINITY};
  cli_json_array(c.f, v, 4);
  cli_json_array(c.f, NULL, 0);
  cli_json_array(c.f, v, 1);
  cli_json_bool(c.f, 1);
  cli_json_bool(c.f, 0);
  cli_json_bool(c.f, 7);
  ck_assert_str_eq(capture_close(&c), "[1, null, 2.5, null][][1]truefalsetrue");
}
END_TEST

/* Every level once at the current filter: what reaches the stream. */
static const char *log_all_levels(const char *program) {
  capture_t c;
  capture_open(&c);
  cli_log_set_stream(c.f);
  cli_log_init(program);
  LOG_E("e %d", 1);
  LOG_W("w %s", "two");
  LOG_I("i %.1f", 3.0);
  LOG_D("d");
  cli_log_set_stream(NULL);
  return capture_close(&c);
}

START_TEST(log_level_filter) {
  cli_log_set_level(CLI_LOG_INFO);
  ck_assert_str_eq(log_all_levels("prog"),
                   "prog: error: e 1\nprog: warning: w two\n"
                   "prog: info: i 3.0\n");
  cli_log_set_level(CLI_LOG_DEBUG);
  ck_assert_str_eq(log_all_levels("prog"),
                   "prog: error: e 1\nprog: warning: w two\n"
                   "prog: info: i 3.0\nprog: debug: d\n");
  cli_log_set_level(CLI_LOG_WARN);
  ck_assert_str_eq(log_all_levels("x-y"), "x-y: error: e 1\nx-y: warning: w two\n");
  cli_log_set_level(CLI_LOG_ERROR);
  ck_assert_str_eq(log_all_levels(NULL), "comlearn: error: e 1\n");
  ck_assert(cli_log_enabled(CLI_LOG_ERROR));
  ck_assert(!cli_log_enabled(CLI_LOG_WARN));
  ck_assert(!cli_log_enabled((cli_log_level_t)-1));
  /* out-of-range levels are clamped, never index past the level names */
  cli_log_set_level((cli_log_level_t)9);
  ck_assert_int_eq(cli_log_get_level(), CLI_LOG_DEBUG);
  cli_log_set_level((cli_log_level_t)-3);
  ck_assert_int_eq(cli_log_get_level(), CLI_LOG_ERROR);
  ck_assert_str_eq(log_all_levels("p"), "p: error: e 1\n");
  cli_log_set_level(CLI_LOG_INFO);
  cli_log_init(NULL);
}
END_TEST

START_TEST(time_is_monotonic) {
  const double t0 = cli_time_now_s();
  double t = t0;
  for (int i = 0; i < 1000; ++i) {
    const double ti = cli_time_now_s();
    ck_assert(ti >= t);
    t = ti;
  }
  ck_assert(isfinite(t0) && t0 > 0.0);
}
END_TEST

/* cli_udp_drops counts what the kernel dropped on this process's sockets: a UDP socket with a
 * 4 KiB receive buffer, sent 200 datagrams of 1 KiB and never read, drops at least 150 of them
 * (the buffer holds a few), and the count grows by exactly those; a closed socket no longer
 * counts. */
START_TEST(udp_drops_counted) {
  uint64_t before = 0, after = 0, closed = 0;
  ck_assert_int_eq(cli_udp_drops(&before), 0);
  const int rx = socket(AF_INET, SOCK_DGRAM, 0), tx = socket(AF_INET, SOCK_DGRAM, 0);
  ck_assert_int_ge(rx, 0);
  ck_assert_int_ge(tx, 0);
  const int small = 4096;
  ck_assert_int_eq(setsockopt(rx, SOL_SOCKET, SO_RCVBUF, &small, sizeof small), 0);
  struct sockaddr_in a;
  memset(&a, 0, sizeof a);
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ck_assert_int_eq(bind(rx, (struct sockaddr *)&a, sizeof a), 0);
  socklen_t len = sizeof a;
  ck_assert_int_eq(getsockname(rx, (struct sockaddr *)&a, &len), 0);
  char buf[1024];
  memset(buf, 'x', sizeof buf);
  int sent = 0;
  for (int i = 0; i < 200; ++i)
    sent += sendto(tx, buf, sizeof buf, 0, (struct sockaddr *)&a, sizeof a) == (ssize_t)sizeof buf;
  ck_assert_int_eq(sent, 200);
  ck_assert_int_eq(cli_udp_drops(&after), 0);
  ck_assert_uint_ge(after - before, 150);
  ck_assert_uint_le(after - before, 200);
  close(rx);
  close(tx);
  ck_assert_int_eq(cli_udp_drops(&closed), 0);
  ck_assert_uint_eq(closed, before);
}
END_TEST

/* cli_lcm_url_buffered adds comlearn's receive buffer to udpm URLs that name none, and leaves
 * every other URL as it is. */
START_TEST(lcm_url_buffered) {
  char out[128];
  ck_assert_int_eq(cli_lcm_url_buffered("udpm://239.255.76.67:7667?ttl=0", out, sizeof out), 0);
  ck_assert_str_eq(out, "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304");
  ck_assert_int_eq(cli_lcm_url_buffered("udpm://239.255.76.67:7667", out, sizeof out), 0);
  ck_assert_str_eq(out, "udpm://239.255.76.67:7667?recv_buf_size=4194304");
  ck_assert_int_eq(cli_lcm_url_buffered("udpm://h:1?recv_buf_size=65536&ttl=1", out, sizeof out),
                   0);
  ck_assert_str_eq(out, "udpm://h:1?recv_buf_size=65536&ttl=1");
  ck_assert_int_eq(cli_lcm_url_buffered("memq://", out, sizeof out), 0);
  ck_assert_str_eq(out, "memq://");
  ck_assert_int_eq(cli_lcm_url_buffered("file:///tmp/x.lcmlog?mode=r", out, sizeof out), 0);
  ck_assert_str_eq(out, "file:///tmp/x.lcmlog?mode=r");
  /* too small for the result: refused, not cut */
  ck_assert_int_eq(cli_lcm_url_buffered("udpm://239.255.76.67:7667?ttl=0", out, 40), -1);
  ck_assert_int_eq(cli_lcm_url_buffered(NULL, out, sizeof out), -1);
}
END_TEST

/* cli_udp_rcvbuf_max reports the largest SO_RCVBUF among the process's UDP sockets (none: -1),
 * cli_udp_drops_of(own pid) is cli_udp_drops, and cli_lcm_buffer_check warns exactly when the
 * buffer asked for in a URL is larger than the one the process has. 64 KiB is below any
 * net.core.rmem_max Linux ships, so the socket gets what it asks. */
START_TEST(udp_rcvbuf_checked) {
  int bytes = -7;
  ck_assert_int_eq(cli_udp_rcvbuf_max(&bytes), -1); /* Check forks each test: no socket yet */
  ck_assert_int_eq(bytes, 0);
  const int a = socket(AF_INET, SOCK_DGRAM, 0), b = socket(AF_INET, SOCK_DGRAM, 0);
  ck_assert_int_ge(a, 0);
  ck_assert_int_ge(b, 0);
  const int small = 16384, large = 65536;
  ck_assert_int_eq(setsockopt(a, SOL_SOCKET, SO_RCVBUF, &small, sizeof small), 0);
  ck_assert_int_eq(setsockopt(b, SOL_SOCKET, SO_RCVBUF, &large, sizeof large), 0);
  struct sockaddr_in lo;
  memset(&lo, 0, sizeof lo);
  lo.sin_family = AF_INET;
  lo.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ck_assert_int_eq(cli_udp_rcvbuf_max(&bytes), -1); /* /proc/net/udp lists bound sockets only */
  ck_assert_int_eq(bind(a, (struct sockaddr *)&lo, sizeof lo), 0);
  ck_assert_int_eq(bind(b, (struct sockaddr *)&lo, sizeof lo), 0);
  int want = 0;
  socklen_t len = sizeof want;
  ck_assert_int_eq(getsockopt(b, SOL_SOCKET, SO_RCVBUF, &want, &len), 0);
  ck_assert_int_eq(want, 2 * large); /* Linux doubles what is set */
  ck_assert_int_eq(cli_udp_rcvbuf_max(&bytes), 0);
  ck_assert_int_eq(bytes, want);
  uint64_t self = 1, own = 2;
  ck_assert_int_eq(cli_udp_drops(&self), 0);
  ck_assert_int_eq(cli_udp_drops_of(getpid(), &own), 0);
  ck_assert_uint_eq(self, own);

  capture_t c;
  capture_open(&c);
  cli_log_set_stream(c.f);
  cli_log_init("t");
  cli_lcm_buffer_check("udpm://239.255.76.67:7667?ttl=0&recv_buf_size=65536"); /* has it */
  cli_lcm_buffer_check("memq://");
  cli_lcm_buffer_check("udpm://239.255.76.67:7667?ttl=0"); /* asks for nothing */
  ck_assert_int_eq(fflush(c.f), 0);
  ck_assert_uint_eq(c.len, 0);
  cli_lcm_buffer_check("udpm://239.255.76.67:7667?ttl=0&recv_buf_size=4194304");
  cli_log_set_stream(NULL);
  const char *text = capture_close(&c);
  ck_assert_msg(
      strstr(text, "t: warning: LCM's receive buffer is 64 KiB, not the 4096 KiB asked") &&
          strstr(text, "net.core.rmem_max"),
      "%s", text);
  close(a);
  close(b);
}
END_TEST

/* A datagram as LCM sends a short message: magic, sequence number, the channel and its NUL, the
 * payload. Its length into *n. */
static void lcm_short(unsigned char *buf, size_t *n, uint32_t magic, const char *channel) {
  const uint32_t m = htonl(magic), seq = htonl(7);
  memcpy(buf, &m, 4);
  memcpy(buf + 4, &seq, 4);
  const size_t len = strlen(channel) + 1;
  memcpy(buf + 8, channel, len);
  memcpy(buf + 8 + len, "payload", 7);
  *n = 8 + len + 7;
}

/* cli_lcm_filter_build refuses what it cannot express: no channel, more than 8, a NULL, an empty
 * or a 64-byte name. Its program is one magic check, two instructions per load of 4, 2 or 1
 * bytes of a name with its NUL, an accept per name, one drop. */
START_TEST(lcm_filter_built) {
  struct sock_filter prog[CLI_LCM_FILTER_INSNS_MAX];
  const char *one[] = {"ABC"}, *nine[9], *bad[] = {"A", NULL};
  for (int i = 0; i < 9; ++i) nine[i] = "A";
  char long_name[65];
  memset(long_name, 'x', 64);
  long_name[64] = '\0';
  const char *too_long[] = {long_name}, *empty[] = {""};
  ck_assert_int_eq(cli_lcm_filter_build(one, 0, prog), -1);
  ck_assert_int_eq(cli_lcm_filter_build(nine, 9, prog), -1);
  ck_assert_int_eq(cli_lcm_filter_build(bad, 2, prog), -1);
  ck_assert_int_eq(cli_lcm_filter_build(empty, 1, prog), -1);
  ck_assert_int_eq(cli_lcm_filter_build(too_long, 1, prog), -1);
  ck_assert_int_eq(cli_lcm_filter_build(NULL, 1, prog), -1);
  /* "ABC" + NUL: one word: 3 + 2 + 1 + 1 */
  ck_assert_int_eq(cli_lcm_filter_build(one, 1, prog), 7);
  /* 63 bytes + NUL: 16 words; "ABCDEFG" + NUL: 2 words; "ABCDE" + NUL: a word and a half */
  long_name[63] = '\0';
  const char *three[] = {long_name, "ABCDEFG", "ABCDE"};
  ck_assert_int_eq(cli_lcm_filter_build(three, 3, prog), 3 + 33 + 5 + 5 + 1);
  /* 8 of the longest fit the buffer */
  const char *eight[8];
  for (int i = 0; i < 8; ++i) eight[i] = long_name;
  ck_assert_int_le(cli_lcm_filter_build(eight, 8, prog), CLI_LCM_FILTER_INSNS_MAX);
}
END_TEST

/* On a UDP socket with the filter for two channels, exactly the short LCM messages on those two
 * arrive, with every datagram that is not a short LCM message; names that differ by a prefix, a
 * suffix, one letter or the case are dropped by the kernel (counted on the socket), and so is a
 * datagram too short to hold a magic. A socket without the filter gets all of them. */
START_TEST(lcm_filter_passes_named_channels) {
  const char *heard[] = {"R1_YUMI_STATUS", "R1_OBJECT_STATE"};
  struct {
    uint32_t magic;
    const char *channel;
    int passes;
  } sent[] = {
      {0x4c433032, "R1_YUMI_STATUS", 1},     {0x4c433032, "R1_OBJECT_STATE", 1},
      {0x4c433032, "R1_YUMI_STATUSX", 0},    {0x4c433032, "R1_YUMI_STATU", 0},
      {0x4c433032, "R2_YUMI_STATUS", 0},     {0x4c433032, "YUMI_STATUS", 0},
      {0x4c433032, "r1_yumi_status", 0},     {0x4c433032, "R1_OBJECT_STATEE", 0},
      {0x4c433032, "R1_YUMI_STATUS\x01", 0}, {0x4c433033, "R2_YUMI_STATUS", 1}, /* a fragment */
      {0x12345678, "anything", 1},           {0x4c433032, "", 0},
  };
  const size_t n_sent = sizeof sent / sizeof sent[0];
  int rx[2];
  struct sockaddr_in a[2];
  for (int k = 0; k < 2; ++k) {
    rx[k] = socket(AF_INET, SOCK_DGRAM, 0);
    ck_assert_int_ge(rx[k], 0);
    memset(&a[k], 0, sizeof a[k]);
    a[k].sin_family = AF_INET;
    a[k].sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ck_assert_int_eq(bind(rx[k], (struct sockaddr *)&a[k], sizeof a[k]), 0);
    socklen_t len = sizeof a[k];
    ck_assert_int_eq(getsockname(rx[k], (struct sockaddr *)&a[k], &len), 0);
  }
  ck_assert_int_eq(cli_lcm_filter_attach(rx[0], heard, 2), 0);
  const char *none[] = {""};
  errno = 0;
  ck_assert_int_eq(cli_lcm_filter_attach(rx[1], none, 1), -1);
  ck_assert_int_eq(errno, EINVAL);
  uint64_t drops0 = 0, drops1 = 0;
  ck_assert_int_eq(cli_udp_drops(&drops0), 0);
  const int tx = socket(AF_INET, SOCK_DGRAM, 0);
  ck_assert_int_ge(tx, 0);
  size_t want = 0;
  for (size_t i = 0; i <= n_sent; ++i) {
    unsigned char buf[128];
    size_t n = 3; /* the last: 3 bytes, too short for a magic */
    if (i < n_sent)
      lcm_short(buf, &n, sent[i].magic, sent[i].channel);
    else
      memcpy(buf, "LC0", 3);
    want += i < n_sent && sent[i].passes;
    for (int k = 0; k < 2; ++k)
      ck_assert_int_eq(sendto(tx, buf, n, 0, (struct sockaddr *)&a[k], sizeof a[k]), (ssize_t)n);
  }
  /* what arrived, in order: loopback delivers at once */
  size_t next = 0, got = 0;
  for (;;) {
    unsigned char buf[128];
    const ssize_t r = recv(rx[0], buf, sizeof buf, MSG_DONTWAIT);
    if (r < 0) break;
    while (next < n_sent && !sent[next].passes) ++next;
    ck_assert_uint_lt(next, n_sent);
    unsigned char exp[128];
    size_t n;
    lcm_short(exp, &n, sent[next].magic, sent[next].channel);
    ck_assert_int_eq(r, (ssize_t)n);
    ck_assert_mem_eq(buf, exp, n);
    ++next;
    ++got;
  }
  ck_assert_uint_eq(got, want);
  size_t unfiltered = 0;
  for (unsigned char buf[128]; recv(rx[1], buf, sizeof buf, MSG_DONTWAIT) >= 0;) ++unfiltered;
  ck_assert_uint_eq(unfiltered, n_sent + 1);
  ck_assert_int_eq(cli_udp_drops(&drops1), 0);
  ck_assert_uint_eq(drops1 - drops0, n_sent + 1 - want);
  close(tx);
  close(rx[0]);
  close(rx[1]);
}
END_TEST

/* cli_lcm_filter_new_sockets filters only the bound UDP sockets opened after its snapshot: one
 * bound before and an unbound one opened after keep getting everything. cli_udp_rcvbuf_errors
 * reads the host's count of datagrams lost to full buffers. */
START_TEST(lcm_filter_new_sockets_only) {
  const char *heard[] = {"MINE"};
  struct sockaddr_in lo;
  memset(&lo, 0, sizeof lo);
  lo.sin_family = AF_INET;
  lo.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  const int old = socket(AF_INET, SOCK_DGRAM, 0);
  ck_assert_int_eq(bind(old, (struct sockaddr *)&lo, sizeof lo), 0);
  cli_socket_set_t before;
  cli_socket_set_now(&before);
  ck_assert_uint_ge(before.n, 1);
  ck_assert_int_eq(cli_lcm_filter_new_sockets(&before, heard, 1), 0); /* nothing new */
  const int unbound = socket(AF_INET, SOCK_DGRAM, 0), fresh = socket(AF_INET, SOCK_DGRAM, 0);
  ck_assert_int_eq(bind(fresh, (struct sockaddr *)&lo, sizeof lo), 0);
  ck_assert_int_eq(cli_lcm_filter_new_sockets(&before, heard, 1), 1);
  struct sock_filter prog[CLI_LCM_FILTER_INSNS_MAX];
  socklen_t len = sizeof prog; /* SO_GET_FILTER: the attached program's length */
  ck_assert_int_eq(getsockopt(fresh, SOL_SOCKET, SO_ATTACH_FILTER, prog, &len), 0);
  ck_assert_int_eq((int)len, cli_lcm_filter_build(heard, 1, prog));
  len = sizeof prog;
  ck_assert_int_eq(getsockopt(old, SOL_SOCKET, SO_ATTACH_FILTER, prog, &len), 0);
  ck_assert_int_eq((int)len, 0);
  len = sizeof prog;
  ck_assert_int_eq(getsockopt(unbound, SOL_SOCKET, SO_ATTACH_FILTER, prog, &len), 0);
  ck_assert_int_eq((int)len, 0);
  uint64_t lost = 1;
  ck_assert_int_eq(cli_udp_rcvbuf_errors(&lost), 0);
  close(old);
  close(unbound);
  close(fresh);
}
END_TEST

/* cli_stop: SIGTERM and SIGINT raise the flag (and do not kill), cli_stop_install clears it (a
 * second one too, keeping the first one's saved handlers), and cli_stop_restore puts back the
 * handler that was there before. */
static volatile sig_atomic_t own_handler_ran;
static void own_handler(int sig) {
  (void)sig;
  own_handler_ran = 1;
}

START_TEST(stop_on_signals) {
  ck_assert(signal(SIGTERM, own_handler) != SIG_ERR);
  cli_stop_install();
  ck_assert_int_eq(cli_stop_requested(), 0);
  ck_assert_int_eq(raise(SIGTERM), 0);
  ck_assert_int_eq(cli_stop_requested(), 1);
  cli_stop_install();
  ck_assert_int_eq(cli_stop_requested(), 0);
  ck_assert_int_eq(raise(SIGINT), 0);
  ck_assert_int_eq(cli_stop_requested(), 1);
  ck_assert_int_eq(own_handler_ran, 0);
  cli_stop_restore();
  cli_stop_restore(); /* not installed: nothing */
  ck_assert_int_eq(raise(SIGTERM), 0);
  ck_assert_int_eq(own_handler_ran, 1);
}
END_TEST

int main(void) {
  Suite *s = suite_create("cli_common");
  TCase *json = tcase_create("json");
  tcase_add_test(json, json_string_escapes);
  tcase_add_test(json, svg_text_escapes);
  tcase_add_test(json, json_numbers_and_non_finite);
  tcase_add_test(json, json_arrays_and_bools);
  suite_add_tcase(s, json);
  TCase *log = tcase_create("log");
  tcase_add_test(log, log_level_filter);
  tcase_add_test(log, time_is_monotonic);
  tcase_add_test(log, stop_on_signals);
  suite_add_tcase(s, log);
  TCase *net = tcase_create("net");
  tcase_add_test(net, udp_drops_counted);
  tcase_add_test(net, lcm_url_buffered);
  tcase_add_test(net, udp_rcvbuf_checked);
  tcase_add_test(net, lcm_filter_built);
  tcase_add_test(net, lcm_filter_passes_named_channels);
  tcase_add_test(net, lcm_filter_new_sockets_only);
  suite_add_tcase(s, net);
  SRunner *r = srunner_create(s);
  srunner_run_all(r, CK_NORMAL);
  int failed = srunner_ntests_failed(r);
  srunner_free(r);
  return failed ? EXIT_FAILURE : EXIT_SUCCESS;
}
