/* package.c - package://NAME/REST mesh URIs, resolved as ROS tools resolve them (model_internal.h).
 */
#define _XOPEN_SOURCE 700 /* realpath, scandir */

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "model_internal.h"

enum { PKG_PATH_BUF = 4096 };

/* The confinement of one resolution: the allowed folders (none: anywhere) and the crawl budget. */
typedef struct {
  const char *const *dirs;
  size_t dir_count;
  int folders_left;
} pkg_search_t;

static int is_regular(const char *path) {
  struct stat st;
  return stat(path, &st) == 0 && S_ISREG(st.st_mode);
}

static int is_dir(const char *path) {
  struct stat st;
  return stat(path, &st) == 0 && S_ISDIR(st.st_mode);
}

/* May this canonical folder be listed? An allowed folder, inside one, or on the way down to one. */
static int may_list(const pkg_search_t *s, const char *dir) {
  if (s->dir_count == 0 || model_path_within(dir, s->dirs, s->dir_count)) {
    return 1;
  }
  const size_t n = strlen(dir);
  for (size_t i = 0; i < s->dir_count; ++i) {
    if (strncmp(s->dirs[i], dir, n) == 0 &&
        (s->dirs[i][n] == '/' || s->dirs[i][n] == '\0' || strcmp(dir, "/") == 0)) {
      return 1;
    }
  }
  return 0;
}

/* Skip "<!-- ... -->" and "<? ... ?>" at p; returns where scanning goes on. */
static const char *skip_markup(const char *p, const char *end) {
  const char *close = NULL;
  size_t skip = 0;
  if ((size_t)(end - p) >= 4 && memcmp(p, "<!--", 4) == 0) {
    close = "-->";
    skip = 3;
  } else if ((size_t)(end - p) >= 2 && memcmp(p, "<?", 2) == 0) {
    close = "?>";
    skip = 2;
  } else {
    return p;
  }
  for (const char *q = p + 2; q + skip <= end; ++q) {
    if (memcmp(q, close, skip) == 0) {
      return q + skip;
    }
  }
  return end;
}

int model_package_xml_name(const char *text, size_t n, char *name, size_t name_size) {
  const char *p = text, *end = text + n;
  while (p < end) {
    const char *q = skip_markup(p, end);
    if (q != p) {
      p = q;
      continue;
    }
    if ((size_t)(end - p) >= 6 && memcmp(p, "<name>", 6) == 0) {
      const char *a = p + 6;
      const char *b = memchr(a, '<', (size_t)(end - a));
      if (b == NULL) {
        return -1;
      }
      while (a < b && (*a == ' ' || *a == '\t' || *a == '\n' || *a == '\r')) ++a;
      while (b > a && (b[-1] == ' ' || b[-1] == '\t' || b[-1] == '\n' || b[-1] == '\r')) --b;
      const size_t len = (size_t)(b - a);
      if (len == 0 || len >= name_size) {
        return -1;
      }
      memcpy(name, a, len);
      name[len] = '\0';
      return 0;
    }
    ++p;
  }
  return -1;
}

/* Is dir (canonical) a package named name? Reads dir/package.xml (inside the allowed folders
 * only, a regular file of at most MODEL_PACKAGE_XML_MAX_BYTES). -1: dir holds no package.xml. */
static int package_is(const pkg_search_t *s, const char *dir, const char *name) {
  char path[PKG_PATH_BUF];
  int n = snprintf(path, sizeof path, "%s/package.xml", strcmp(dir, "/") == 0 ? "" : dir);
  if (n < 0 || (size_t)n >= sizeof path || !is_regular(path)) {
    return -1;
  }
  char *real = realpath(path, NULL);
  const int inside = real != NULL && model_path_within(real, s->dirs, s->dir_count);
  free(real);
  if (!inside) {
    return 0;
  }
  int fd = -1;
  size_t size = 0;
  model_error_t ignored;
  if (model_file_open_checked(path, "package.xml", MODEL_PACKAGE_XML_MAX_BYTES, &fd, &size,
                              &ignored) != MODEL_OK) {
    return 0;
  }
  char *text = malloc(size);
  int match = 0;
  if (text != NULL && read(fd, text, size) == (ssize_t)size) {
    char found[MODEL_PACKAGE_NAME_MAX + 1];
    match =
        model_package_xml_name(text, size, found, sizeof found) == 0 && strcmp(found, name) == 0;
  }
  free(text);
  close(fd);
  return match;
}

static int not_hidden(const struct dirent *e) { return e->d_name[0] != '.'; }

/* rospack's crawl of one ROS_PACKAGE_PATH entry: a folder holding a package.xml is a package (its
 * subfolders are not searched); other folders are searched in name order, hidden ones and those
 * holding CATKIN_IGNORE skipped, MODEL_PACKAGE_CRAWL_DEPTH levels deep at most. */
static int crawl(pkg_search_t *s, const char *dir, const char *name, int depth, char *root,
                 size_t root_size) {
  char real[PKG_PATH_BUF];
  if (s->folders_left <= 0 || realpath(dir, real) == NULL || !may_list(s, real)) {
    return 0;
  }
  --s->folders_left;
  const int pkg = package_is(s, real, name);
  if (pkg >= 0) {
    if (pkg == 1 && strlen(real) < root_size) {
      memcpy(root, real, strlen(real) + 1);
      return 1;
    }
    return 0;
  }
  char probe[PKG_PATH_BUF];
  int n = snprintf(probe, sizeof probe, "%s/CATKIN_IGNORE", real);
  if (depth >= MODEL_PACKAGE_CRAWL_DEPTH || n < 0 || (size_t)n >= sizeof probe ||
      access(probe, F_OK) == 0) {
    return 0;
  }
  struct dirent **list = NULL;
  const int count = scandir(real, &list, not_hidden, alphasort);
  int found = 0;
  for (int i = 0; i < count; ++i) {
    n = snprintf(probe, sizeof probe, "%s/%s", strcmp(real, "/") == 0 ? "" : real, list[i]->d_name);
    if (!found && n > 0 && (size_t)n < sizeof probe && is_dir(probe)) {
      found = crawl(s, probe, name, depth + 1, root, root_size);
    }
    free(list[i]);
  }
  free(list);
  return found;
}

/* The package root of name: the URDF's folder or the nearest parent holding a package.xml of
 * that name, else the first ROS_PACKAGE_PATH entry that holds it. 1 found, 0 not. */
static int find_root(pkg_search_t *s, const char *urdf_dir, const char *name, char *root,
                     size_t root_size) {
  char dir[PKG_PATH_BUF];
  if (strlen(urdf_dir) >= sizeof dir) {
    return 0;
  }
  strcpy(dir, urdf_dir);
  for (int level = 0; level < MODEL_PACKAGE_PARENT_LEVELS; ++level) {
    if (package_is(s, dir, name) == 1 && strlen(dir) < root_size) {
      strcpy(root, dir);
      return 1;
    }
    char *cut = strrchr(dir, '/');
    if (cut == NULL || strcmp(dir, "/") == 0) {
      break;
    }
    cut[cut == dir ? 1 : 0] = '\0';
  }
  const char *env = getenv("ROS_PACKAGE_PATH");
  while (env != NULL && *env != '\0') {
    const char *colon = strchr(env, ':');
    const size_t len = colon != NULL ? (size_t)(colon - env) : strlen(env);
    if (len > 0 && len < sizeof dir) {
      memcpy(dir, env, len);
      dir[len] = '\0';
      if (crawl(s, dir, name, 0, root, root_size)) {
        return 1;
      }
    }
    env = colon != NULL ? colon + 1 : NULL;
  }
  return 0;
}

/* REST of the URI: not empty, and no ".." that climbs above the package root. */
static const char *rest_problem(const char *rest) {
  if (rest[0] == '\0') {
    return "no path after the package name";
  }
  int depth = 0;
  for (const char *p = rest; *p != '\0';) {
    const char *slash = strchr(p, '/');
    const size_t len = slash != NULL ? (size_t)(slash - p) : strlen(p);
    if (len == 2 && p[0] == '.' && p[1] == '.') {
      if (--depth < 0) {
        return "'..' climbs out of the package root";
      }
    } else if (!(len == 0 || (len == 1 && p[0] == '.'))) {
      ++depth;
    }
    p += len + (slash != NULL ? 1 : 0);
  }
  return NULL;
}

model_status_t model_package_resolve(const char *uri, const char *urdf_dir, const char *const *dirs,
                                     size_t dir_count, char *out, size_t out_size,
                                     model_error_t *err) {
  const char *pkg = uri + strlen("package://");
  const char *slash = strchr(pkg, '/');
  const size_t name_len = slash != NULL ? (size_t)(slash - pkg) : strlen(pkg);
  if (name_len == 0) {
    return model_fail(err, MODEL_E_PARSE, "mesh '%s': empty package name", uri);
  }
  if (name_len > MODEL_PACKAGE_NAME_MAX) {
    return model_fail(err, MODEL_E_PARSE, "mesh '%s': package name longer than %d bytes", uri,
                      MODEL_PACKAGE_NAME_MAX);
  }
  char name[MODEL_PACKAGE_NAME_MAX + 1];
  memcpy(name, pkg, name_len);
  name[name_len] = '\0';
  for (size_t i = 0; i < name_len; ++i) {
    const char c = name[i];
    if (!((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_' ||
          c == '-')) {
      return model_fail(err, MODEL_E_PARSE,
                        "mesh '%s': package name '%s' is not a ROS package name (letters, digits, "
                        "'_', '-')",
                        uri, name);
    }
  }
  const char *rest = slash != NULL ? slash + 1 : "";
  const char *problem = rest_problem(rest);
  if (problem != NULL) {
    return model_fail(err, MODEL_E_PARSE, "mesh '%s': %s", uri, problem);
  }
  pkg_search_t s = {dirs, dir_count, MODEL_PACKAGE_CRAWL_FOLDERS};
  char root[PKG_PATH_BUF];
  if (!find_root(&s, urdf_dir, name, root, sizeof root)) {
    return model_fail(err, MODEL_E_NOFILE,
                      "mesh '%s': unknown package '%s': no package.xml named %s in the URDF's "
                      "folder or above it, nor under ROS_PACKAGE_PATH%s",
                      uri, name, name,
                      dir_count > 0 ? " (inside the folders this program may read)" : "");
  }
  char path[PKG_PATH_BUF];
  int n = snprintf(path, sizeof path, "%s/%s", strcmp(root, "/") == 0 ? "" : root, rest);
  if (n < 0 || (size_t)n >= sizeof path) {
    return model_fail(err, MODEL_E_ARG, "mesh '%s': path too long", uri);
  }
  struct stat st;
  char *real = stat(path, &st) == 0 ? realpath(path, NULL) : NULL;
  if (real == NULL) {
    return model_fail(err, MODEL_E_NOFILE, "mesh '%s' not found (package %s at %s: tried %s)", uri,
                      name, root, path);
  }
  if (!S_ISREG(st.st_mode)) {
    free(real);
    return model_fail(err, MODEL_E_NOFILE,
                      "mesh '%s' (%s) is not a regular file (a folder, device, pipe or socket): "
                      "refused",
                      uri, path);
  }
  const size_t len = strlen(real);
  if (len >= out_size) {
    free(real);
    return model_fail(err, MODEL_E_ARG, "mesh '%s': path too long", uri);
  }
  memcpy(out, real, len + 1);
  free(real);
  return MODEL_OK;
}
