/* file_guard.c - what lib/model does before a third-party parser sees a file: the file must be a
 * regular file of bounded size (model_file_open_checked), and a mesh is parsed in a child process
 * with a CPU limit (model_mesh_parse_isolated), so that a parser that crashes, aborts or loops on
 * a hostile file costs an error message, not the caller's process (docs/security.md). */
#define _POSIX_C_SOURCE 200809L

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include "model_internal.h"

#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define COMLEARN_HAS_ASAN 1
#endif
#endif
#ifndef COMLEARN_HAS_ASAN
#define COMLEARN_HAS_ASAN 0
#endif

model_status_t model_file_open_checked(const char *path, const char *what, size_t max_bytes,
                                       int *fd_out, size_t *size_out, model_error_t *err) {
  *fd_out = -1;
  errno = 0;
  /* O_NONBLOCK: opening a named pipe must not wait for a writer; fstat then refuses it */
  const int fd = open(path, O_RDONLY | O_NONBLOCK | O_CLOEXEC);
  if (fd < 0) {
    return model_fail(err, MODEL_E_NOFILE, "cannot open %s %s: %s", what, path, strerror(errno));
  }
  struct stat st;
  if (fstat(fd, &st) != 0) {
    const int e = errno;
    close(fd);
    return model_fail(err, MODEL_E_NOFILE, "cannot stat %s %s: %s", what, path, strerror(e));
  }
  if (S_ISDIR(st.st_mode)) {
    close(fd);
    return model_fail(err, MODEL_E_NOFILE, "%s %s is a folder, not a file", what, path);
  }
  if (!S_ISREG(st.st_mode)) {
    close(fd);
    return model_fail(err, MODEL_E_NOFILE,
                      "%s %s is not a regular file (a device, pipe or socket): refused", what,
                      path);
  }
  if ((uint64_t)st.st_size > (uint64_t)max_bytes) {
    close(fd);
    return model_fail(err, MODEL_E_PARSE, "%s %s is %lld bytes, over the %zu-byte limit", what,
                      path, (long long)st.st_size, max_bytes);
  }
  if (st.st_size == 0) {
    close(fd);
    return model_fail(err, MODEL_E_PARSE, "%s %s is an empty file", what, path);
  }
  const int flags = fcntl(fd, F_GETFL);
  if (flags >= 0) (void)fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
  *fd_out = fd;
  *size_out = (size_t)st.st_size;
  return MODEL_OK;
}

/* What the child sends first. */
typedef struct {
  int32_t status;
  uint32_t pad;
  uint64_t vertex_count;
  uint64_t triangle_count;
  char msg[sizeof(((model_error_t *)0)->msg)];
} child_header_t;

static int write_full(int fd, const void *buf, size_t n) {
  const char *p = buf;
  while (n > 0) {
    const ssize_t k = write(fd, p, n);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return -1;
    p += k;
    n -= (size_t)k;
  }
  return 0;
}

static int read_full(int fd, void *buf, size_t n) {
  char *p = buf;
  while (n > 0) {
    const ssize_t k = read(fd, p, n);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return -1;
    p += k;
    n -= (size_t)k;
  }
  return 0;
}

/* The child: limits, the parse, the result down the pipe. Never returns. */
static void child_run(int fd, const char *path, const double scale[3], double cpu_s,
                      size_t file_bytes, model_mesh_parse_fn parse) {
  const rlim_t cpu = (rlim_t)(cpu_s + 0.999);
  (void)setrlimit(RLIMIT_CPU, &(struct rlimit){cpu, cpu + 1});
  (void)setrlimit(RLIMIT_CORE, &(struct rlimit){0, 0}); /* a crash leaves no core file */
#if !defined(__SANITIZE_ADDRESS__) && !COMLEARN_HAS_ASAN
  /* memory: 4 GiB and 16 bytes per byte of file (a sanitizer's shadow memory needs more) */
  const rlim_t as = ((rlim_t)4 << 30) + (rlim_t)16 * file_bytes;
  (void)setrlimit(RLIMIT_AS, &(struct rlimit){as, as});
#else
  (void)file_bytes;
#endif
  /* wall time too: a file that names a pipe (an OBJ's mtllib) would block without CPU; the
   * limits' signals end the child whatever the caller made of them */
  static const int sigs[] = {SIGALRM, SIGXCPU, SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT};
  sigset_t set;
  sigemptyset(&set);
  for (size_t i = 0; i < sizeof sigs / sizeof sigs[0]; ++i) {
    signal(sigs[i], SIG_DFL); /* the caller's crash handlers are not the parser's */
    sigaddset(&set, sigs[i]);
  }
  sigprocmask(SIG_UNBLOCK, &set, NULL);
  alarm((unsigned)(2.0 * cpu_s + 5.0));
  model_mesh_t m = {0};
  model_error_t e = {{0}};
  child_header_t h;
  memset(&h, 0, sizeof h);
  h.status = (int32_t)parse(path, scale, &m, &e);
  if (h.status == MODEL_OK) {
    h.vertex_count = m.vertex_count;
    h.triangle_count = m.triangle_count;
  }
  memcpy(h.msg, e.msg, sizeof h.msg);
  int bad = write_full(fd, &h, sizeof h);
  if (!bad && h.status == MODEL_OK) {
    bad = write_full(fd, m.vertices_m, m.vertex_count * sizeof *m.vertices_m) ||
          write_full(fd, m.triangles, m.triangle_count * sizeof *m.triangles);
  }
  _exit(bad ? 3 : 0);
}

/* Why the child ended without a whole answer. */
static model_status_t child_failed(const char *path, pid_t pid, double cpu_s, model_error_t *err) {
  int ws = 0;
  pid_t r;
  do {
    r = waitpid(pid, &ws, 0);
  } while (r < 0 && errno == EINTR);
  if (r == pid && WIFSIGNALED(ws)) {
    const int sig = WTERMSIG(ws);
    if (sig == SIGXCPU || sig == SIGKILL || sig == SIGALRM)
      return model_fail(err, MODEL_E_PARSE,
                        "mesh %s: the mesh reader (assimp) ran over its time limit on it (%.0f s "
                        "of CPU): refused as corrupt",
                        path, cpu_s);
    return model_fail(err, MODEL_E_PARSE,
                      "mesh %s: the mesh reader (assimp) crashed on it (signal %d, %s): refused as "
                      "corrupt",
                      path, sig, strsignal(sig));
  }
  if (r == pid && WIFEXITED(ws) && WEXITSTATUS(ws) != 0) /* a sanitizer's report, say */
    return model_fail(
        err, MODEL_E_PARSE,
        "mesh %s: the mesh reader (assimp) crashed on it (exit status %d): refused as "
        "corrupt",
        path, WEXITSTATUS(ws));
  return model_fail(err, MODEL_E_PARSE, "mesh %s: the mesh reader (assimp) gave no answer: refused",
                    path);
}

model_status_t model_mesh_parse_isolated(const char *path, const double scale[3], double cpu_s,
                                         size_t file_bytes, model_mesh_parse_fn parse,
                                         model_mesh_t *out, model_error_t *err) {
  int fds[2];
  if (pipe(fds) != 0)
    return model_fail(err, MODEL_E_NOMEM, "mesh %s: no pipe for the mesh reader: %s", path,
                      strerror(errno));
  fflush(NULL); /* nothing buffered is written twice */
  const pid_t pid = fork();
  if (pid < 0) {
    const int e = errno;
    close(fds[0]);
    close(fds[1]);
    return model_fail(err, MODEL_E_NOMEM, "mesh %s: cannot start the mesh reader: %s", path,
                      strerror(e));
  }
  if (pid == 0) {
    close(fds[0]);
    child_run(fds[1], path, scale, cpu_s, file_bytes, parse);
  }
  close(fds[1]);
  child_header_t h;
  model_status_t st = MODEL_OK;
  if (read_full(fds[0], &h, sizeof h) != 0) {
    close(fds[0]);
    return child_failed(path, pid, cpu_s, err);
  }
  if (h.status != MODEL_OK) {
    h.msg[sizeof h.msg - 1] = '\0';
    st = model_fail(err, (model_status_t)h.status, "%s", h.msg);
  } else if (h.vertex_count > UINT32_MAX || h.triangle_count > SIZE_MAX / sizeof *out->triangles) {
    st = model_fail(err, MODEL_E_PARSE, "mesh %s: the mesh reader sent absurd counts", path);
  } else {
    st = model_mesh_alloc(out, (size_t)h.vertex_count, (size_t)h.triangle_count);
    if (st != MODEL_OK) {
      st = model_fail(err, st, "mesh %s: out of memory for %llu triangles", path,
                      (unsigned long long)h.triangle_count);
    } else if (read_full(fds[0], out->vertices_m, out->vertex_count * sizeof *out->vertices_m) ||
               read_full(fds[0], out->triangles, out->triangle_count * sizeof *out->triangles)) {
      model_mesh_free(out);
      close(fds[0]);
      return child_failed(path, pid, cpu_s, err);
    }
  }
  close(fds[0]);
  int ws = 0;
  while (waitpid(pid, &ws, 0) < 0 && errno == EINTR) {}
  return st;
}

/* Skip from p (after an opener) past the first `end`; NULL when the text ends first. */
static const char *skip_past(const char *p, const char *e, const char *end) {
  const size_t n = strlen(end);
  for (; p + n <= e; ++p)
    if (memcmp(p, end, n) == 0) return p + n;
  return NULL;
}

model_status_t model_xml_check(const char *text, size_t n, const char *path, model_error_t *err) {
  const char *p = text, *e = text + n;
  long depth = 0, elements = 0, links = 0, joints = 0;
  while ((p = memchr(p, '<', (size_t)(e - p))) != NULL) {
    ++p;
    if (p < e && *p == '?') { /* a processing instruction */
      p = skip_past(p, e, "?>");
    } else if (e - p >= 3 && memcmp(p, "!--", 3) == 0) {
      p = skip_past(p + 3, e, "-->");
    } else if (e - p >= 8 && memcmp(p, "![CDATA[", 8) == 0) {
      p = skip_past(p + 8, e, "]]>");
    } else if (p < e && *p == '!') { /* a DOCTYPE: no internal subset (no entities) */
      const char *gt = memchr(p, '>', (size_t)(e - p));
      if (gt != NULL && memchr(p, '[', (size_t)(gt - p)) != NULL)
        return model_fail(err, MODEL_E_PARSE, "URDF %s: a DOCTYPE with an internal subset: refused",
                          path);
      p = gt != NULL ? gt + 1 : NULL;
    } else if (p < e && *p == '/') {
      --depth;
      p = memchr(p, '>', (size_t)(e - p));
    } else { /* an element: its name, then to its '>' outside quotes */
      const char *name = p;
      while (p < e && *p != '>' && *p != '/' && *p != ' ' && *p != '\t' && *p != '\n' && *p != '\r')
        ++p;
      const size_t len = (size_t)(p - name);
      links += len == 4 && memcmp(name, "link", 4) == 0;
      joints += len == 5 && memcmp(name, "joint", 5) == 0;
      char quote = 0;
      for (; p < e && (quote || *p != '>'); ++p) {
        if (quote && *p == quote)
          quote = 0;
        else if (!quote && (*p == '"' || *p == '\''))
          quote = *p;
      }
      if (p >= e) break;
      const int empty = p[-1] == '/';
      if (!empty && ++depth > MODEL_URDF_MAX_DEPTH)
        return model_fail(err, MODEL_E_PARSE, "URDF %s: elements nested deeper than %d: refused",
                          path, MODEL_URDF_MAX_DEPTH);
      if (++elements > MODEL_URDF_MAX_ELEMENTS)
        return model_fail(err, MODEL_E_PARSE, "URDF %s: more than %d elements: refused", path,
                          MODEL_URDF_MAX_ELEMENTS);
      if (links > MODEL_URDF_MAX_LINKS || joints > MODEL_URDF_MAX_LINKS)
        return model_fail(err, MODEL_E_PARSE, "URDF %s: more than %d links or joints: refused",
                          path, MODEL_URDF_MAX_LINKS);
    }
    if (p == NULL) break;
  }
  return MODEL_OK;
}
