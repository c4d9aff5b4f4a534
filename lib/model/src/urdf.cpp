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

#include <unistd.h>
#include <map>
#include <mutex>
#include <new>
#include <string>

#include <console_bridge/console.h>
#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include "model_internal.h"

#ifndef MODEL_URDF_INERTIAL
// The estimator's build may not even name a link's inertial member.
#define inertial inertial_is_not_visible_to_the_estimator
#endif

// Shared by both builds, defined only in the geometry build (comlearn_model).
namespace model_urdf {
model_status_t parse(const char *path, urdf::ModelInterfaceSharedPtr &model, model_error_t *err);
model_status_t find_link(const urdf::ModelInterface &model, const char *path, const char *link_name,
                         urdf::LinkConstSharedPtr &link, model_error_t *err);
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
      // The first error says what was wrong; the next ones say where (urdfdom's "... for joint
      // [j2]"), so keep up to three.
      if (urdf_error_count == 0) {
        first_urdf_error = text;
      } else if (urdf_error_count < 3) {
        first_urdf_error += "; " + text;
      }
      ++urdf_error_count;
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
  int fd = -1;
  size_t bytes = 0;
  model_status_t st = model_file_open_checked(path, "URDF", MODEL_URDF_MAX_BYTES, &fd, &bytes, err);
  if (st != MODEL_OK) {
    return st;
  }
  text.resize(bytes);
  size_t got = 0;
  while (got < bytes) {
    const ssize_t k = ::read(fd, &text[got], bytes - got);
    if (k < 0 && errno == EINTR) {
      continue;
    }
    if (k <= 0) {
      const int saved = errno;
      ::close(fd);
      return model_fail(err, MODEL_E_NOFILE, "cannot read URDF %s: %s", path,
                        k == 0 ? "it shrank while read" : std::strerror(saved));
    }
    got += static_cast<size_t>(k);
  }
  ::close(fd);
  return model_xml_check(text.data(), text.size(), path, err);
}

// urdfdom links each joint's child to its parent with shared pointers both ways down the tree
// (Link::child_links, Link::parent_joint), so joints that close a loop (a -> b -> a) make a
// cycle of shared pointers that is never freed, whether urdfdom then refuses the file ("no root
// link") or not. The file is read here first with the same XML parser urdfdom uses (behind the
// shape check, so tinyxml's recursion is bounded), and joints must form a forest: each link the
// child of at most one joint, no loop. Anything else urdfdom checks itself.
model_status_t joint_tree_check(const std::string &text, const char *path, model_error_t *err) {
  TiXmlDocument doc;
  doc.Parse(text.c_str());
  const TiXmlElement *robot = doc.Error() ? nullptr : doc.FirstChildElement("robot");
  if (robot == nullptr) {
    return MODEL_OK; // urdfdom refuses it with its own message
  }
  std::map<std::string, std::string> parent_of;
  for (const TiXmlElement *j = robot->FirstChildElement("joint"); j != nullptr;
       j = j->NextSiblingElement("joint")) {
    const TiXmlElement *parent = j->FirstChildElement("parent");
    const TiXmlElement *child = j->FirstChildElement("child");
    const char *p = parent != nullptr ? parent->Attribute("link") : nullptr;
    const char *c = child != nullptr ? child->Attribute("link") : nullptr;
    if (p == nullptr || c == nullptr) {
      continue; // urdfdom refuses a joint without both
    }
    if (!parent_of.emplace(c, p).second) {
      return model_fail(err, MODEL_E_PARSE,
                        "URDF %s: link '%s' is the child of two joints: refused", path, c);
    }
  }
  // Walk up from each link; a walk longer than the number of joints has gone round a loop.
  for (const auto &start : parent_of) {
    const std::string *at = &start.first;
    for (size_t steps = 0; steps <= parent_of.size(); ++steps) {
      const auto up = parent_of.find(*at);
      if (up == parent_of.end()) {
        break;
      }
      if (steps == parent_of.size()) {
        return model_fail(err, MODEL_E_PARSE,
                          "URDF %s: the joints make a loop through link '%s': refused", path,
                          start.first.c_str());
      }
      at = &up->second;
    }
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
  st = joint_tree_check(text, path, err);
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

model_status_t find_link(const urdf::ModelInterface &model, const char *path, const char *link_name,
                         urdf::LinkConstSharedPtr &link, model_error_t *err) {
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
  double v[4] = {q.w, q.x, q.y, q.z};
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3]);
  if (n > 0.0) {
    for (double &c : v) c /= n;
  }
  model_quat_to_rot(v, r);
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
      return model_fail(err, MODEL_E_UNSUPPORTED, "URDF %s: link '%s': unknown geometry type", path,
                        link.c_str());
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

// Walks from the tip up to the base through each link's parent joint, then copies the joints
// base first. urdfdom has already rejected cycles and links with two parents.
model_status_t chain_read(const char *urdf_path, const char *base_name, const char *tip_name,
                          model_chain_t *out, model_error_t *err) {
  urdf::ModelInterfaceSharedPtr model;
  model_status_t st = parse(urdf_path, model, err);
  if (st != MODEL_OK) {
    return st;
  }
  urdf::LinkConstSharedPtr base, tip;
  st = find_link(*model, urdf_path, base_name, base, err);
  if (st == MODEL_OK) {
    st = find_link(*model, urdf_path, tip_name, tip, err);
  }
  if (st != MODEL_OK) {
    return st;
  }
  copy_name(out->robot_name, sizeof out->robot_name, model->getName());
  copy_name(out->base_link, sizeof out->base_link, base->name);
  copy_name(out->tip_link, sizeof out->tip_link, tip->name);
  urdf::JointConstSharedPtr path[MODEL_CHAIN_MAX_JOINTS];
  size_t n = 0;
  urdf::LinkConstSharedPtr link = tip;
  while (link->name != base->name) {
    urdf::JointConstSharedPtr joint = link->parent_joint;
    if (!joint) {
      return model_fail(err, MODEL_E_CHAIN,
                        "URDF %s: link '%s' does not descend from '%s' (reached the root '%s')",
                        urdf_path, tip->name.c_str(), base->name.c_str(), link->name.c_str());
    }
    if (n == MODEL_CHAIN_MAX_JOINTS) {
      return model_fail(err, MODEL_E_CHAIN, "URDF %s: chain '%s' -> '%s' has more than %d joints",
                        urdf_path, base->name.c_str(), tip->name.c_str(),
                        (int)MODEL_CHAIN_MAX_JOINTS);
    }
    path[n++] = joint;
    link = model->getLink(joint->parent_link_name);
    if (!link) {
      return model_fail(err, MODEL_E_CHAIN, "URDF %s: joint '%s' has no parent link '%s'",
                        urdf_path, joint->name.c_str(), joint->parent_link_name.c_str());
    }
  }
  for (size_t i = 0; i < n; ++i) {
    const urdf::Joint &j = *path[n - 1 - i];
    model_joint_t *o = &out->joints[i];
    if (j.name.size() >= sizeof o->name || j.parent_link_name.size() >= sizeof o->parent_link ||
        j.child_link_name.size() >= sizeof o->child_link) {
      return model_fail(err, MODEL_E_CHAIN, "URDF %s: joint '%.100s...': a name is too long",
                        urdf_path, j.name.c_str());
    }
    copy_name(o->name, sizeof o->name, j.name);
    copy_name(o->parent_link, sizeof o->parent_link, j.parent_link_name);
    copy_name(o->child_link, sizeof o->child_link, j.child_link_name);
    switch (j.type) {
      case urdf::Joint::REVOLUTE: o->type = MODEL_JOINT_REVOLUTE; break;
      case urdf::Joint::CONTINUOUS: o->type = MODEL_JOINT_CONTINUOUS; break;
      case urdf::Joint::PRISMATIC: o->type = MODEL_JOINT_PRISMATIC; break;
      case urdf::Joint::FIXED: o->type = MODEL_JOINT_FIXED; break;
      default:
        return model_fail(err, MODEL_E_CHAIN,
                          "URDF %s: joint '%s' is floating, planar or of unknown type "
                          "(supported: revolute, continuous, prismatic, fixed)",
                          urdf_path, j.name.c_str());
    }
    const urdf::Pose &origin = j.parent_to_joint_origin_transform;
    o->origin_xyz_m[0] = origin.position.x;
    o->origin_xyz_m[1] = origin.position.y;
    o->origin_xyz_m[2] = origin.position.z;
    origin.rotation.getRPY(o->origin_rpy_rad[0], o->origin_rpy_rad[1], o->origin_rpy_rad[2]);
    rotation_matrix(origin.rotation, o->origin_rot);
    o->axis[0] = j.axis.x;
    o->axis[1] = j.axis.y;
    o->axis[2] = j.axis.z;
    o->lower = -HUGE_VAL;
    o->upper = HUGE_VAL;
    if (j.limits) {
      o->velocity = j.limits->velocity;
      if (o->type == MODEL_JOINT_REVOLUTE || o->type == MODEL_JOINT_PRISMATIC) {
        o->has_limits = 1;
        o->lower = j.limits->lower;
        o->upper = j.limits->upper;
      }
    }
  }
  out->joint_count = n;
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

model_status_t model_urdf_chain_read(const char *urdf_path, const char *base_link,
                                     const char *tip_link, model_chain_t *out, model_error_t *err) {
  if (out == nullptr || base_link == nullptr || tip_link == nullptr) {
    return model_fail(err, MODEL_E_ARG, "model_urdf_chain_read: NULL argument");
  }
  std::memset(out, 0, sizeof *out);
  model_status_t st =
      guarded(urdf_path, err, [&] { return chain_read(urdf_path, base_link, tip_link, out, err); });
  if (st != MODEL_OK) {
    std::memset(out, 0, sizeof *out);
  }
  return st;
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
