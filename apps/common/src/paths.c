/* paths.c - see comlearn/cli_paths.h. */
#define _XOPEN_SOURCE 700 /* realpath */
#include "comlearn/cli_paths.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#if !defined(COMLEARN_BINDIR_TO_DATADIR) || !defined(COMLEARN_BUILD_DIR) || \
    !defined(COMLEARN_BUILD_ASSETS_DIR) || !defined(COMLEARN_BUILD_SIM_EXE)
#error "apps/common/CMakeLists.txt defines the COMLEARN_* paths"
#endif

typedef struct {
  int resolved;
  int installed;
  char exe_dir[PATH_MAX];
  char assets_dir[PATH_MAX];
  char yumi_urdf[PATH_MAX];
  char sim_exe[PATH_MAX];
} cli_paths_t;

static cli_paths_t paths;

/* out = a + b, or "" when it does not fit (the caller's open then fails). */
static void path_join(char *out, size_t size, const char *a, const char *b) {
  const int n = snprintf(out, size, "%s%s", a, b);
  if (n < 0 || (size_t)n >= size) out[0] = '\0';
}

static int is_dir(const char *path) {
  struct stat st;
  return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* The folder of the running executable, "" when /proc/self/exe cannot be read. */
static void read_exe_dir(char *dir, size_t size) {
  dir[0] = '\0';
  const ssize_t n = readlink("/proc/self/exe", dir, size - 1);
  if (n <= 0) {
    dir[0] = '\0';
    return;
  }
  dir[n] = '\0';
  char *slash = strrchr(dir, '/');
  if (slash) *slash = '\0';
}

static void resolve(void) {
  if (paths.resolved) return;
  paths.resolved = 1;
  read_exe_dir(paths.exe_dir, sizeof paths.exe_dir);
  char data_dir[PATH_MAX];
  path_join(data_dir, sizeof data_dir, paths.exe_dir, "/" COMLEARN_BINDIR_TO_DATADIR "/comlearn");
  /* /proc/self/exe has no symbolic links, so compare with the build folder's real path. */
  char build_dir[PATH_MAX];
  if (!realpath(COMLEARN_BUILD_DIR, build_dir)) {
    path_join(build_dir, sizeof build_dir, COMLEARN_BUILD_DIR, "");
  }
  const size_t build_len = strlen(build_dir);
  const int in_build_tree = strncmp(paths.exe_dir, build_dir, build_len) == 0 &&
                            (paths.exe_dir[build_len] == '/' || paths.exe_dir[build_len] == '\0');
  paths.installed = is_dir(data_dir) || !in_build_tree;
  if (paths.installed) {
    /* PREFIX/share/comlearn rather than PREFIX/bin/../share/comlearn in messages. */
    if (!realpath(data_dir, paths.assets_dir)) {
      path_join(paths.assets_dir, sizeof paths.assets_dir, data_dir, "");
    }
    path_join(paths.sim_exe, sizeof paths.sim_exe, paths.exe_dir, "/comlearn-sim");
  } else {
    path_join(paths.assets_dir, sizeof paths.assets_dir, COMLEARN_BUILD_ASSETS_DIR, "");
    path_join(paths.sim_exe, sizeof paths.sim_exe, COMLEARN_BUILD_SIM_EXE, "");
  }
  path_join(paths.yumi_urdf, sizeof paths.yumi_urdf, paths.assets_dir, "/yumi/yumi.urdf");
}

const char *cli_paths_assets_dir(void) {
  resolve();
  return paths.assets_dir;
}

const char *cli_paths_yumi_urdf(void) {
  resolve();
  return paths.yumi_urdf;
}

const char *cli_paths_sim_exe(void) {
  resolve();
  return paths.sim_exe;
}
