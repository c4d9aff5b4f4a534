// urdf.cpp - the only file that touches urdfdom (C++), behind the C API of model_internal.h.
//
// Compiled twice (lib/model/CMakeLists.txt):
//   without MODEL_URDF_INERTIAL  -> comlearn_model:     model_urdf_link_read / model_urdf_link_free
//                                   and the shared helpers in namespace model_urdf (parse, ...)
//   with    MODEL_URDF_INERTIAL  -> comlearn_model_sim: model_urdf_inertial_read only; it calls
//                                   the helpers defined in comlearn_model
// So the two archives never define the same symbol, and the one console handler and its capture
// state exist once per process (a CTest checks the symbols with nm). Every entry point catches
// every exception.
//
// urdfdom reports parse errors through console_bridge. We install, once per process, an output
// handler that prints nothing and keeps the first error of the calling thread, so a bad URDF
// produces a message in model_error_t and nothing on the console. urdfdom is lenient: an element
// it cannot parse (a <collision> with a bad number, say) is logged and dropped, and the model is
// still returned. Loading the rest would silently give the wrong geometry, so any error logged
// while parsing rejects the file.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <new>
#include <string>

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include "model_internal.h"

#ifndef MODEL_URDF_INERTIAL
// The estimator's build may not even name a link's inertial member.
#define inertial inertial_is_not_visible_to_the_estimator
#endif

// Shared by both builds, defined only in the geometry build (comlearn_model).
namespace model_urdf {
model_status_t parse(const char *path, urdf::ModelInterfaceSharedPtr &model, model_error_t *err);
model_status_t find_link(const urdf::ModelInterface &model, const char *path,
                         const char *link_name, urdf::LinkConstSharedPtr &link,
                         model_error_t *err);
void rotation_matrix(const urdf::Rotation &q, double r[3][3]);
void copy_name(char *dst, size_t size, const std::string &src);
} // namespace model_urdf

#ifndef MODEL_URDF_INERTIAL

namespace {

thread_local std::string first_urdf_error;
thread_local int urdf_error_count = 0;

class CaptureHandler final : public console_bridge::OutputHandler {
 public:
  void log(const std::string &text, console_bridge::LogLevel level, const char *, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) {
      if (urdf_error_count++ == 0) {
        first_urdf_error = text;
      }
    }
  }
};

void quiet_console() {
  static std::once_flag once;
  static CaptureHandler handler;
  std::call_once(once, [] {
    console_bridge::useOutputHandler(&handler);
    console_bridge::setLogLevel(console_bridge::CONSOLE_BRIDGE_LOG_ERROR);
  });
}

model_status_t read_text(const char *path, std::string &text, model_error_t *err) {
  errno = 0;
  std::FILE *f = std::fopen(path, "rb");
  if (f == nullptr) {
    return model_fail(err, MODEL_E_NOFILE, "cannot open URDF %s: %s", path, std::strerror(errno));
  }
  char buf[8192];
  size_t got;
  while ((got = std::fread(buf, 1, sizeof buf, f)) > 0) {
    text.append(buf, got);
  }
  int failed = std::ferror(f);
  int saved = errno;
  std::fclose(f);
  if (failed) {
    return model_fail(err, MODEL_E_NOFILE, "cannot read URDF %s: %s", path, std::strerror(saved));
  }
  return MODEL_OK;
}

} // namespace

namespace model_urdf {

model_status_t parse(const char *path, urdf::ModelInterfaceSharedPtr &model, model_error_t *err) {
  if (path == nullptr || path[0] == '\0') {
    return model_fail(err, MODEL_E_ARG, "URDF path is NULL or empty");
  }
  std::string text;
  model_status_t st = read_text(path, text, err);
  if (st != MODEL_OK) {
    return st;
  }
  quiet_console();
  first_urdf_error.clear();
  urdf_error_count = 0;
  model = urdf::parseURDF(text);
  if (!model || urdf_error_count > 0) {
    model.reset();
    return model_fail(err, MODEL_E_PARSE, "URDF %s is not valid: %s", path,
                      first_urdf_error.empty() ? "urdfdom rejected it" : first_urdf_error.c_str());
  }
  return MODEL_OK;
}

model_status_t find_link(const urdf::ModelInterface &model, const char *path,
                         const char *link_name, urdf::LinkConstSharedPtr &link,
                         model_error_t *err) {
  if (link_name == nullptr) {
    link = model.getRoot();
    if (!link) {
      return model_fail(err, MODEL_E_NOLINK, "URDF %s has no root link", path);
    }
    return MODEL_OK;
  }
  link = model.getLink(link_name);
  if (!link) {
    std::string names;
    for (const auto &kv : model.links_) {
      names += names.empty() ? "" : ", ";
      names += kv.first;
    }
    return model_fail(err, MODEL_E_NOLINK, "URDF %s has no link named '%s' (links: %s)", path,
                      link_name, names.c_str());
  }
  return MODEL_OK;
}

// Rotation matrix of a unit quaternion (urdfdom stores the origin's rpy as one).
void rotation_matrix(const urdf::Rotation &q, double r[3][3]) {
  double x = q.x, y = q.y, z = q.z, w = q.w;
  double n = std::sqrt(x * x + y * y + z * z + w * w);
  if (n > 0.0) {
    x /= n;
    y /= n;
    z /= n;
    w /= n;
  }
  r[0][0] = 1 - 2 * (y * y + z * z);
  r[0][1] = 2 * (x * y - z * w);
  r[0][2] = 2 * (x * z + y * w);
  r[1][0] = 2 * (x * y + z * w);
  r[1][1] = 1 - 2 * (x * x + z * z);
  r[1][2] = 2 * (y * z - x * w);
  r[2][0] = 2 * (x * z - y * w);
  r[2][1] = 2 * (y * z + x * w);
  r[2][2] = 1 - 2 * (x * x + y * y);
}

void copy_name(char *dst, size_t size, const std::string &src) {
  std::snprintf(dst, size, "%s", src.c_str());
}

} // namespace model_urdf

#endif // !MODEL_URDF_INERTIAL

namespace {

using namespace model_urdf;

#ifndef MODEL_URDF_INERTIAL

model_status_t fill_geom(const urdf::Pose &origin, const urdf::GeometrySharedPtr &geometry,
                         const char *path, const std::string &link, model_urdf_geom_t *g,
                         model_error_t *err) {
  std::memset(g, 0, sizeof *g);
  g->xyz_m[0] = origin.position.x;
  g->xyz_m[1] = origin.position.y;
  g->xyz_m[2] = origin.position.z;
  rotation_matrix(origin.rotation, g->rot);
  g->scale[0] = g->scale[1] = g->scale[2] = 1.0;
  if (!geometry) {
    return model_fail(err, MODEL_E_NOGEOM, "URDF %s: link '%s' has an element without geometry",
                      path, link.c_str());
  }
  switch (geometry->type) {
    case urdf::Geometry::MESH: {
      const auto &m = static_cast<const urdf::Mesh &>(*geometry);
      g->shape = MODEL_URDF_MESH;
      g->scale[0] = m.scale.x;
      g->scale[1] = m.scale.y;
      g->scale[2] = m.scale.z;
      if (m.filename.size() >= sizeof g->filename) {
        return model_fail(err, MODEL_E_ARG, "URDF %s: link '%s': mesh file name too long", path,
                          link.c_str());
      }
      copy_name(g->filename, sizeof g->filename, m.filename);
      break;
    }
    case urdf::Geometry::BOX: {
      const auto &b = static_cast<const urdf::Box &>(*geometry);
      g->shape = MODEL_URDF_BOX;
      g->size_m[0] = b.dim.x;
      g->size_m[1] = b.dim.y;
      g->size_m[2] = b.dim.z;
      break;
    }
    case urdf::Geometry::SPHERE:
      g->shape = MODEL_URDF_SPHERE;
      g->radius_m = static_cast<const urdf::Sphere &>(*geometry).radius;
      break;
    case urdf::Geometry::CYLINDER: {
      const auto &c = static_cast<const urdf::Cylinder &>(*geometry);
      g->shape = MODEL_URDF_CYLINDER;
      g->radius_m = c.radius;
      g->length_m = c.length;
      break;
    }
    default:
      return model_fail(err, MODEL_E_UNSUPPORTED, "URDF %s: link '%s': unknown geometry type",
                        path, link.c_str());
  }
  return MODEL_OK;
}

model_status_t link_read(const char *urdf_path, const char *link_name, model_urdf_link_t *out,
                         model_error_t *err) {
  urdf::ModelInterfaceSharedPtr model;
  model_status_t st = parse(urdf_path, model, err);
  if (st != MODEL_OK) {
    return st;
  }
  urdf::LinkConstSharedPtr link;
  st = find_link(*model, urdf_path, link_name, link, err);
  if (st != MODEL_OK) {
    return st;
  }
  copy_name(out->robot_name, sizeof out->robot_name, model->getName());
  copy_name(out->link_name, sizeof out->link_name, link->name);
  out->from_visual = link->collision_array.empty() && !link->collision;
  size_t count = out->from_visual ? link->visual_array.size() : link->collision_array.size();
  if (out->from_visual && count == 0 && link->visual) {
    count = 1;
  } else if (!out->from_visual && count == 0) {
    count = 1; // only `collision` set
  }
  if (count == 0) {
    return MODEL_OK;
  }
  out->geoms = static_cast<model_urdf_geom_t *>(std::calloc(count, sizeof *out->geoms));
  if (out->geoms == nullptr) {
    return model_fail(err, MODEL_E_NOMEM, "URDF %s: out of memory", urdf_path);
  }
  out->geom_count = count;
  for (size_t i = 0; i < count; ++i) {
    if (out->from_visual) {
      const urdf::VisualSharedPtr &v =
          link->visual_array.empty() ? link->visual : link->visual_array[i];
      st = fill_geom(v->origin, v->geometry, urdf_path, link->name, &out->geoms[i], err);
    } else {
      const urdf::CollisionSharedPtr &c =
          link->collision_array.empty() ? link->collision : link->collision_array[i];
      st = fill_geom(c->origin, c->geometry, urdf_path, link->name, &out->geoms[i], err);
    }
    if (st != MODEL_OK) {
      return st;
    }
  }
  return MODEL_OK;
}

#else // MODEL_URDF_INERTIAL

model_status_t inertial_read(const char *urdf_path, const char *link_name,
                             model_urdf_inertial_t *out, model_error_t *err) {
  urdf::ModelInterfaceSharedPtr model;
  model_status_t st = parse(urdf_path, model, err);
  if (st != MODEL_OK) {
    return st;
  }
  urdf::LinkConstSharedPtr link;
  st = find_link(*model, urdf_path, link_name, link, err);
  if (st != MODEL_OK) {
    return st;
  }
  copy_name(out->link_name, sizeof out->link_name, link->name);
  if (!link->inertial) {
    return model_fail(err, MODEL_E_INERTIAL, "URDF %s: link '%s' has no <inertial>", urdf_path,
                      link->name.c_str());
  }
  const urdf::Inertial &in = *link->inertial;
  out->mass_kg = in.mass;
  out->com_m[0] = in.origin.position.x;
  out->com_m[1] = in.origin.position.y;
  out->com_m[2] = in.origin.position.z;
  rotation_matrix(in.origin.rotation, out->rot);
  double t[3][3] = {{in.ixx, in.ixy, in.ixz}, {in.ixy, in.iyy, in.iyz}, {in.ixz, in.iyz, in.izz}};
  std::memcpy(out->inertia_kg_m2, t, sizeof t);
  return MODEL_OK;
}

#endif // MODEL_URDF_INERTIAL

} // namespace

// Runs fn (a urdfdom call) with every exception turned into a status that names the file.
// In an anonymous namespace so each build gets its own copy and no symbol is shared.
namespace {
template <typename F>
model_status_t guarded(const char *urdf_path, model_error_t *err, F &&fn) {
  const char *path = urdf_path != nullptr ? urdf_path : "(null)";
  try {
    return fn();
  } catch (const std::bad_alloc &) {
    return model_fail(err, MODEL_E_NOMEM, "URDF %s: out of memory", path);
  } catch (const std::exception &e) {
    return model_fail(err, MODEL_E_PARSE, "URDF %s: %s", path, e.what());
  } catch (...) {
    return model_fail(err, MODEL_E_PARSE, "URDF %s: unknown exception in urdfdom", path);
  }
}
} // namespace

extern "C" {

#ifndef MODEL_URDF_INERTIAL

model_status_t model_urdf_link_read(const char *urdf_path, const char *link_name,
                                    model_urdf_link_t *out, model_error_t *err) {
  if (out == nullptr) {
    return model_fail(err, MODEL_E_ARG, "model_urdf_link_read: NULL output");
  }
  std::memset(out, 0, sizeof *out);
  model_status_t st =
      guarded(urdf_path, err, [&] { return link_read(urdf_path, link_name, out, err); });
  if (st != MODEL_OK) {
    model_urdf_link_free(out);
  }
  return st;
}

void model_urdf_link_free(model_urdf_link_t *link) {
  if (link != nullptr) {
    std::free(link->geoms);
    std::memset(link, 0, sizeof *link);
  }
}

#else // MODEL_URDF_INERTIAL

model_status_t model_urdf_inertial_read(const char *urdf_path, const char *link_name,
                                        model_urdf_inertial_t *out, model_error_t *err) {
  if (out == nullptr) {
    return model_fail(err, MODEL_E_ARG, "model_urdf_inertial_read: NULL output");
  }
  std::memset(out, 0, sizeof *out);
  model_status_t st =
      guarded(urdf_path, err, [&] { return inertial_read(urdf_path, link_name, out, err); });
  if (st != MODEL_OK) {
    std::memset(out, 0, sizeof *out);
  }
  return st;
}

#endif // MODEL_URDF_INERTIAL

} // extern "C"
