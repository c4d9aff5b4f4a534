/* check_messages: the comlearn LCM message set (lcmtypes/) and comlearn/msg.h.
 *
 *   check_messages                        run the Check suite
 *   check_messages --write-fixtures DIR   write DIR/<type>.bin (the C encoding of each type's
 *                                         fixture) and DIR/<type>.txt (its fields, one per line)
 *                                         for tests/java/DecodeCheck.java, which decodes the .bin
 *                                         with the Java classes lcm-spy uses and compares.
 *
 * Fields are compared through the lcm-gen typeinfo (every field, every element, bit for bit),
 * and a mutation test proves the comparison notices a change in any one field. Typed spot checks
 * on named fields guard the generic code itself.
 */
#include <check.h>
#include <float.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/comlearn_com_estimate_t.h"
#include "comlearn/comlearn_com_trial_t.h"
#include "comlearn/comlearn_object_state_t.h"
#include "comlearn/comlearn_sim_control_t.h"
#include "comlearn/comlearn_yumi_command_t.h"
#include "comlearn/comlearn_yumi_status_t.h"
#include "comlearn/math3d.h"
#include "comlearn/msg.h"

/* ---------------------------------------------------------------------------------------------
 * Fixtures: every field set, no numeric element zero, array elements distinct, strings non-empty
 * (fixture_check() asserts this, so a later field cannot be forgotten). */

/* Distinct, non-round doubles of both signs; k >= 0. */
static double val(int k) {
  return ((double)k + 1.0) * 0.123456789012345 * ((k % 2) ? -1.0 : 1.0) + 1e-9 * (double)k;
}

static void fill_quat(double q[4], double angle_rad, double ax, double ay, double az) {
  double axis[3] = {ax, ay, az};
  (void)cl_vec3_normalize(axis, axis);
  cl_quat_from_axis_angle(axis, angle_rad, q);
}

static char s_rock[] = "rock_2_uneven";
static char s_policy[] = "paper-mlp";
static char s_error[] = "YUMI_COMMAND seq 41: joint 3 of arm 1 outside [-2.94, 2.94] rad";
/* Non-ASCII bytes (UTF-8 "µ") in a path: strings are bytes and must arrive unchanged. */
static char s_urdf[] = "/srv/assets/rocks/rock_2_uneven \xc2\xb5m.urdf";

static void fill_yumi_command(void *p) {
  comlearn_yumi_command_t *m = p;
  m->utime = 1732274400123456;
  m->seq = 4200000000042;
  m->expire_utime = 98765432101;
  m->mode = COMLEARN_YUMI_COMMAND_T_MODE_POSITION;
  m->velocity_scale = 0.375;
  for (int a = 0; a < 2; a++)
    for (int j = 0; j < 7; j++) m->q_commanded_rad[a][j] = val(a * 7 + j);
  m->gripper_width_commanded_m[0] = 0.0125;
  m->gripper_width_commanded_m[1] = 0.04375;
}

static void fill_yumi_status(void *p) {
  comlearn_yumi_status_t *m = p;
  m->utime = 98765400000;
  m->state = COMLEARN_YUMI_STATUS_T_STATE_STOPPED;
  m->in_position = 1;
  m->last_accepted_seq = 4200000000041;
  m->last_accepted_utime = -1732274400000001;
  for (int a = 0; a < 2; a++)
    for (int j = 0; j < 7; j++) {
      m->q_measured_rad[a][j] = val(100 + a * 7 + j);
      m->qdot_estimated_rad_s[a][j] = val(200 + a * 7 + j) * 1e-3;
      m->q_commanded_rad[a][j] = val(300 + a * 7 + j);
    }
  m->qdot_estimated_rad_s[1][6] = DBL_MIN / 4.0; /* subnormal: bit-exact transport */
  m->gripper_width_measured_m[0] = 0.0311;
  m->gripper_width_measured_m[1] = 0.0007;
  m->gripper_width_commanded_m[0] = 0.031;
  m->gripper_width_commanded_m[1] = 0.05;
  m->error_code = COMLEARN_YUMI_STATUS_T_ERR_INVALID;
  m->error_text = s_error;
  m->messages_received = 123456;
  m->messages_rejected = 789;
  m->messages_undecodable = 3141592653;
}

static void fill_object_state(void *p) {
  comlearn_object_state_t *m = p;
  m->utime = 98765400777;
  m->object_id = s_rock;
  m->tracked = 1;
  m->position_measured_m[0] = 0.4512345;
  m->position_measured_m[1] = -0.1500123;
  m->position_measured_m[2] = 0.1312;
  fill_quat(m->orientation_measured_wxyz, 0.7, 0.3, -0.2, 0.9);
  for (int i = 0; i < 3; i++) {
    m->velocity_estimated_m_s[i] = val(400 + i) * 1e-4;
    m->omega_estimated_rad_s[i] = val(410 + i) * 1e-2;
  }
  m->at_rest = 1;
  m->on_base = 1;
  m->sim_control_seq = 77;
  m->sim_control_result = COMLEARN_OBJECT_STATE_T_SIM_CONTROL_ERR_UNKNOWN_ID;
}

static void fill_sim_control(void *p) {
  comlearn_sim_control_t *m = p;
  m->utime = 1732274400999999;
  m->seq = 78;
  m->action = COMLEARN_SIM_CONTROL_T_ACTION_LOAD;
  m->object_id = s_rock;
  m->urdf_path = s_urdf;
  m->arm = COMLEARN_SIM_CONTROL_T_ARM_RIGHT;
  m->link_in_tool_position_m[0] = 0.0012;
  m->link_in_tool_position_m[1] = -0.0034;
  m->link_in_tool_position_m[2] = 0.0215;
  fill_quat(m->link_in_tool_wxyz, 2.1, -0.5, 0.25, 0.75);
  m->gripper_width_m = 0.0412;
}

static void fill_com_trial(void *p) {
  comlearn_com_trial_t *m = p;
  m->utime = 1732274401234567;
  m->run_id = 1732274400000000;
  m->object_id = s_rock;
  m->policy = s_policy;
  m->trial_index = 17;
  m->kind = COMLEARN_COM_TRIAL_T_KIND_REST;
  m->component = COMLEARN_COM_TRIAL_T_COMPONENT_Z;
  m->direction = -1;
  m->edge_normal_world[0] = 0.6;
  m->edge_normal_world[1] = -0.8;
  m->edge_normal_world[2] = 1e-17;
  m->edge_offset_m = 0.15;
  m->base_top_z_m = 0.1025;
  m->target_point_link_m[0] = 0.00312;
  m->target_point_link_m[1] = -0.00045;
  m->target_point_link_m[2] = 0.01789;
  m->target_offset_m = -2.5e-7;
  m->released_position_m[0] = 0.5012;
  m->released_position_m[1] = -0.1234;
  m->released_position_m[2] = 0.1291;
  fill_quat(m->released_orientation_wxyz, 0.3, 0.0001, 1.0, 0.2);
  m->outcome = COMLEARN_COM_TRIAL_T_OUTCOME_TIPS;
  m->settled_position_m[0] = 0.5361;
  m->settled_position_m[1] = -0.1422;
  m->settled_position_m[2] = -0.0317;
  fill_quat(m->settled_orientation_wxyz, 1.9, 0.4, 0.8, -0.1);
  m->displacement_m = 0.1643;
  m->rotation_rad = 1.5707;
  m->flat_patch = 1;
  m->sideways_margin_m = 0.0042;
  m->com_estimated_m[0] = 0.00311;
  m->com_estimated_m[1] = -0.00047;
  m->com_estimated_m[2] = 0.01777;
  m->halfwidth_m[0] = 5e-5;
  m->halfwidth_m[1] = 2.5e-4;
  m->halfwidth_m[2] = 0.02;
}

static void fill_com_estimate(void *p) {
  comlearn_com_estimate_t *m = p;
  m->utime = 1732274409876543;
  m->run_id = 1732274400000000;
  m->object_id = s_rock;
  m->policy = s_policy;
  m->resolution_m = 1e-4;
  m->com_estimated_m[0] = 0.003125;
  m->com_estimated_m[1] = -0.000475;
  m->com_estimated_m[2] = 0.017755;
  m->halfwidth_m[0] = 4.9e-5;
  m->halfwidth_m[1] = 5.1e-5;
  m->halfwidth_m[2] = 4.7e-5;
  m->found[0] = 1;
  m->found[1] = 0;
  m->found[2] = 1;
  m->trials = 31;
  m->done = 1;
}

/* Typed checks of a few named fields of a decoded fixture: these do not go through typeinfo. */
static void spot_yumi_command(const void *p) {
  const comlearn_yumi_command_t *m = p;
  ck_assert_int_eq(m->seq, 4200000000042);
  ck_assert_int_eq(m->expire_utime, 98765432101);
  ck_assert_int_eq(m->mode, COMLEARN_YUMI_COMMAND_T_MODE_POSITION);
  ck_assert(m->q_commanded_rad[1][6] == val(13));
  ck_assert(m->q_commanded_rad[0][0] == val(0));
  ck_assert(m->gripper_width_commanded_m[1] == 0.04375);
}

static void spot_yumi_status(const void *p) {
  const comlearn_yumi_status_t *m = p;
  ck_assert_int_eq(m->state, COMLEARN_YUMI_STATUS_T_STATE_STOPPED);
  ck_assert_int_eq(m->last_accepted_utime, -1732274400000001);
  ck_assert(m->q_measured_rad[1][2] == val(109));
  ck_assert(m->qdot_estimated_rad_s[1][6] == DBL_MIN / 4.0);
  ck_assert(m->q_commanded_rad[0][6] == val(306));
  ck_assert_str_eq(m->error_text, s_error);
  ck_assert_int_eq(m->messages_undecodable, 3141592653);
}

static void spot_object_state(const void *p) {
  const comlearn_object_state_t *m = p;
  ck_assert_str_eq(m->object_id, "rock_2_uneven");
  ck_assert(m->position_measured_m[1] == -0.1500123);
  double q[4];
  fill_quat(q, 0.7, 0.3, -0.2, 0.9);
  ck_assert(memcmp(q, m->orientation_measured_wxyz, sizeof q) == 0);
  ck_assert_int_eq(m->sim_control_result, COMLEARN_OBJECT_STATE_T_SIM_CONTROL_ERR_UNKNOWN_ID);
}

static void spot_sim_control(const void *p) {
  const comlearn_sim_control_t *m = p;
  ck_assert_int_eq(m->action, COMLEARN_SIM_CONTROL_T_ACTION_LOAD);
  ck_assert_int_eq(m->arm, COMLEARN_SIM_CONTROL_T_ARM_RIGHT);
  ck_assert_str_eq(m->urdf_path, s_urdf);
  ck_assert_uint_eq(strlen(m->urdf_path), strlen(s_urdf));
  ck_assert(m->link_in_tool_position_m[2] == 0.0215);
  ck_assert(m->gripper_width_m == 0.0412);
}

static void spot_com_trial(const void *p) {
  const comlearn_com_trial_t *m = p;
  ck_assert_str_eq(m->policy, "paper-mlp");
  ck_assert_int_eq(m->trial_index, 17);
  ck_assert_int_eq(m->direction, -1);
  ck_assert_int_eq(m->outcome, COMLEARN_COM_TRIAL_T_OUTCOME_TIPS);
  ck_assert(m->target_offset_m == -2.5e-7);
  ck_assert(m->settled_position_m[2] == -0.0317);
  ck_assert(m->halfwidth_m[2] == 0.02);
}

static void spot_com_estimate(const void *p) {
  const comlearn_com_estimate_t *m = p;
  ck_assert_int_eq(m->found[0], 1);
  ck_assert_int_eq(m->found[1], 0);
  ck_assert_int_eq(m->found[2], 1);
  ck_assert(m->com_estimated_m[2] == 0.017755);
  ck_assert_int_eq(m->trials, 31);
  ck_assert_int_eq(m->done, 1);
}

static int pub_yumi_command(lcm_t *l, const char *c, const void *m) {
  return comlearn_yumi_command_t_publish(l, c, m);
}
static int pub_yumi_status(lcm_t *l, const char *c, const void *m) {
  return comlearn_yumi_status_t_publish(l, c, m);
}
static int pub_object_state(lcm_t *l, const char *c, const void *m) {
  return comlearn_object_state_t_publish(l, c, m);
}
static int pub_sim_control(lcm_t *l, const char *c, const void *m) {
  return comlearn_sim_control_t_publish(l, c, m);
}
static int pub_com_trial(lcm_t *l, const char *c, const void *m) {
  return comlearn_com_trial_t_publish(l, c, m);
}
static int pub_com_estimate(lcm_t *l, const char *c, const void *m) {
  return comlearn_com_estimate_t_publish(l, c, m);
}

typedef struct {
  const char *name;
  const char *channel;
  const lcm_type_info_t *(*info)(void);
  void (*fill)(void *msg);
  void (*spot)(const void *msg);
  int (*publish)(lcm_t *lcm, const char *channel, const void *msg);
} type_case_t;

static const type_case_t cases[] = {
    {"yumi_command_t", COMLEARN_MSG_CHANNEL_YUMI_COMMAND, comlearn_yumi_command_t_get_type_info,
     fill_yumi_command, spot_yumi_command, pub_yumi_command},
    {"yumi_status_t", COMLEARN_MSG_CHANNEL_YUMI_STATUS, comlearn_yumi_status_t_get_type_info,
     fill_yumi_status, spot_yumi_status, pub_yumi_status},
    {"object_state_t", COMLEARN_MSG_CHANNEL_OBJECT_STATE, comlearn_object_state_t_get_type_info,
     fill_object_state, spot_object_state, pub_object_state},
    {"sim_control_t", COMLEARN_MSG_CHANNEL_SIM_CONTROL, comlearn_sim_control_t_get_type_info,
     fill_sim_control, spot_sim_control, pub_sim_control},
    {"com_trial_t", COMLEARN_MSG_CHANNEL_COM_TRIAL, comlearn_com_trial_t_get_type_info,
     fill_com_trial, spot_com_trial, pub_com_trial},
    {"com_estimate_t", COMLEARN_MSG_CHANNEL_COM_ESTIMATE, comlearn_com_estimate_t_get_type_info,
     fill_com_estimate, spot_com_estimate, pub_com_estimate},
};
enum { NCASES = (int)(sizeof cases / sizeof cases[0]) };

/* Storage for a message of any of the types. */
typedef union {
  comlearn_yumi_command_t yumi_command;
  comlearn_yumi_status_t yumi_status;
  comlearn_object_state_t object_state;
  comlearn_sim_control_t sim_control;
  comlearn_com_trial_t com_trial;
  comlearn_com_estimate_t com_estimate;
} any_msg_t;

/* ---------------------------------------------------------------------------------------------
 * Generic field access through the lcm-gen typeinfo. */

static size_t elem_count(const lcm_field_t *f) {
  size_t n = 1;
  for (int d = 0; d < f->num_dim; d++) n *= (size_t)f->dim_size[d];
  return n;
}

/* Bytes of one element in the C struct (strings: a char pointer). */
static size_t elem_bytes(lcm_field_type_t t) {
  switch (t) {
    case LCM_FIELD_INT8_T:
    case LCM_FIELD_BYTE:
    case LCM_FIELD_BOOLEAN: return 1;
    case LCM_FIELD_INT16_T: return 2;
    case LCM_FIELD_INT32_T:
    case LCM_FIELD_FLOAT: return 4;
    case LCM_FIELD_INT64_T:
    case LCM_FIELD_DOUBLE: return 8;
    case LCM_FIELD_STRING: return sizeof(char *);
    case LCM_FIELD_USER_TYPE: break;
  }
  ck_abort_msg("nested types are not used by comlearn");
  return 0;
}

static void get_field(const lcm_type_info_t *t, const void *m, int i, lcm_field_t *f) {
  memset(f, 0, sizeof *f);
  ck_assert_int_eq(t->get_field(m, i, f), 0);
  for (int d = 0; d < f->num_dim; d++) ck_assert_int_eq(f->dim_is_variable[d], 0);
}

/* Writes "name[e]" (flat element index) into where. */
static void where_of(char *where, size_t n, const lcm_field_t *f, size_t e) {
  if (f->num_dim == 0)
    snprintf(where, n, "%s", f->name);
  else
    snprintf(where, n, "%s[%zu]", f->name, e);
}

/* 0 when every element of every field of a and b is equal (numbers bit for bit, strings byte
 * for byte); else 1 with the first difference named in where. */
static int msg_diff(const lcm_type_info_t *t, const void *a, const void *b, char *where, size_t n) {
  for (int i = 0; i < t->num_fields(); i++) {
    lcm_field_t fa, fb;
    get_field(t, a, i, &fa);
    get_field(t, b, i, &fb);
    size_t cnt = elem_count(&fa), sz = elem_bytes(fa.type);
    for (size_t e = 0; e < cnt; e++) {
      int differ;
      if (fa.type == LCM_FIELD_STRING) {
        const char *sa = ((char *const *)fa.data)[e], *sb = ((char *const *)fb.data)[e];
        differ = sa == NULL || sb == NULL || strcmp(sa, sb) != 0;
      } else {
        differ = memcmp((const char *)fa.data + e * sz, (const char *)fb.data + e * sz, sz) != 0;
      }
      if (differ) {
        where_of(where, n, &fa, e);
        return 1;
      }
    }
  }
  return 0;
}

/* Load one numeric element as a double (for the non-triviality check only). */
static double num_at(const lcm_field_t *f, size_t e) {
  const char *p = (const char *)f->data + e * elem_bytes(f->type);
  int8_t i8;
  int16_t i16;
  int32_t i32;
  int64_t i64;
  float fl;
  double d;
  switch (f->type) {
    case LCM_FIELD_INT8_T:
    case LCM_FIELD_BOOLEAN: memcpy(&i8, p, 1); return i8;
    case LCM_FIELD_BYTE: return (unsigned char)*p;
    case LCM_FIELD_INT16_T: memcpy(&i16, p, 2); return i16;
    case LCM_FIELD_INT32_T: memcpy(&i32, p, 4); return i32;
    case LCM_FIELD_INT64_T: memcpy(&i64, p, 8); return (double)i64;
    case LCM_FIELD_FLOAT: memcpy(&fl, p, 4); return fl;
    case LCM_FIELD_DOUBLE: memcpy(&d, p, 8); return d;
    case LCM_FIELD_STRING:
    case LCM_FIELD_USER_TYPE: break;
  }
  ck_abort_msg("not a number field");
  return 0.0;
}

/* The fixture must be able to catch mistakes: no zero numbers (except boolean array elements,
 * which must then not all be equal), distinct elements within an array, non-empty strings. */
static void fixture_check(const lcm_type_info_t *t, const void *m, const char *type_name) {
  for (int i = 0; i < t->num_fields(); i++) {
    lcm_field_t f;
    get_field(t, m, i, &f);
    size_t cnt = elem_count(&f);
    for (size_t e = 0; e < cnt; e++) {
      if (f.type == LCM_FIELD_STRING) {
        const char *s = ((char *const *)f.data)[e];
        ck_assert_msg(s != NULL && s[0] != '\0', "%s.%s: empty string in fixture", type_name,
                      f.name);
        continue;
      }
      double v = num_at(&f, e);
      if (f.type == LCM_FIELD_BOOLEAN && cnt > 1) continue;
      ck_assert_msg(v != 0.0, "%s.%s[%zu] is zero in the fixture", type_name, f.name, e);
      for (size_t k = 0; k < e; k++)
        ck_assert_msg(num_at(&f, k) != v, "%s.%s: elements %zu and %zu equal in the fixture",
                      type_name, f.name, k, e);
    }
    if (f.type == LCM_FIELD_BOOLEAN && cnt > 1) {
      int ones = 0;
      for (size_t e = 0; e < cnt; e++) ones += num_at(&f, e) != 0.0;
      ck_assert_msg(ones > 0 && (size_t)ones < cnt, "%s.%s: boolean array all equal", type_name,
                    f.name);
    }
  }
}

/* Encode into a malloc'd buffer of exactly the encoded size. */
static unsigned char *encode_alloc(const lcm_type_info_t *t, const void *m, size_t *len) {
  int n = t->encoded_size(m);
  ck_assert_int_gt(n, 8);
  unsigned char *buf = malloc((size_t)n);
  ck_assert_ptr_nonnull(buf);
  ck_assert_int_eq(t->encode(buf, 0, n, m), n);
  *len = (size_t)n;
  return buf;
}

/* Offset in the encoding of the first string field's length prefix; 0 if the type has none. */
static size_t first_string_offset(const lcm_type_info_t *t, const void *m) {
  size_t pos = 8;
  for (int i = 0; i < t->num_fields(); i++) {
    lcm_field_t f;
    get_field(t, m, i, &f);
    if (f.type == LCM_FIELD_STRING) return pos;
    pos += elem_count(&f) * elem_bytes(f.type);
  }
  return 0;
}

/* ---------------------------------------------------------------------------------------------
 * Round trips. */

START_TEST(test_fixture_nontrivial) {
  const type_case_t *c = &cases[_i];
  any_msg_t m;
  memset(&m, 0, sizeof m);
  c->fill(&m);
  fixture_check(c->info(), &m, c->name);
}
END_TEST

START_TEST(test_roundtrip_msg_decode) {
  const type_case_t *c = &cases[_i];
  const lcm_type_info_t *t = c->info();
  any_msg_t sent, got;
  memset(&sent, 0, sizeof sent);
  c->fill(&sent);
  size_t len;
  unsigned char *buf = encode_alloc(t, &sent, &len);
  ck_assert_int_eq(comlearn_msg_check(t, buf, len), COMLEARN_MSG_OK);
  comlearn_msg_stats_t st = {0};
  memset(&got, 0xa5, sizeof got);
  ck_assert_int_eq(comlearn_msg_decode(t, buf, len, &got, &st), COMLEARN_MSG_OK);
  char where[128] = "";
  ck_assert_msg(msg_diff(t, &sent, &got, where, sizeof where) == 0, "%s: %s differs", c->name,
                where);
  c->spot(&got);
  ck_assert_uint_eq(st.received, 1);
  ck_assert_uint_eq(st.decoded, 1);
  ck_assert_uint_eq(comlearn_msg_stats_rejected(&st), 0);
  /* Re-encoding the decoded message gives the same bytes. */
  size_t len2;
  unsigned char *buf2 = encode_alloc(t, &got, &len2);
  ck_assert_uint_eq(len2, len);
  ck_assert(memcmp(buf, buf2, len) == 0);
  t->decode_cleanup(&got);
  free(buf2);
  free(buf);
}
END_TEST

/* The generated decoder alone agrees with comlearn_msg_decode on good input. */
START_TEST(test_roundtrip_generated_decode) {
  const type_case_t *c = &cases[_i];
  const lcm_type_info_t *t = c->info();
  any_msg_t sent, got;
  memset(&sent, 0, sizeof sent);
  memset(&got, 0, sizeof got);
  c->fill(&sent);
  size_t len;
  unsigned char *buf = encode_alloc(t, &sent, &len);
  ck_assert_int_eq(t->decode(buf, 0, (int)len, &got), (int)len);
  char where[128] = "";
  ck_assert_msg(msg_diff(t, &sent, &got, where, sizeof where) == 0, "%s: %s differs", c->name,
                where);
  c->spot(&got);
  t->decode_cleanup(&got);
  free(buf);
}
END_TEST

/* msg_diff notices a change in any single field (the last element of arrays, the first byte of
 * strings), so the round trips above really compare every field. */
START_TEST(test_compare_sees_every_field) {
  const type_case_t *c = &cases[_i];
  const lcm_type_info_t *t = c->info();
  any_msg_t sent, got;
  memset(&sent, 0, sizeof sent);
  c->fill(&sent);
  size_t len;
  unsigned char *buf = encode_alloc(t, &sent, &len);
  ck_assert_int_eq(comlearn_msg_decode(t, buf, len, &got, NULL), COMLEARN_MSG_OK);
  char where[128];
  for (int i = 0; i < t->num_fields(); i++) {
    lcm_field_t f;
    get_field(t, &got, i, &f);
    size_t last = elem_count(&f) - 1;
    unsigned char *byte;
    if (f.type == LCM_FIELD_STRING)
      byte = (unsigned char *)((char **)f.data)[last];
    else
      byte = (unsigned char *)f.data + last * elem_bytes(f.type);
    *byte ^= 1u;
    ck_assert_msg(msg_diff(t, &sent, &got, where, sizeof where) == 1, "%s.%s change not seen",
                  c->name, f.name);
    ck_assert_msg(strncmp(where, f.name, strlen(f.name)) == 0, "%s.%s reported as %s", c->name,
                  f.name, where);
    *byte ^= 1u;
    ck_assert_int_eq(msg_diff(t, &sent, &got, where, sizeof where), 0);
  }
  t->decode_cleanup(&got);
  free(buf);
}
END_TEST

/* Non-finite numbers travel unchanged: the receiver, not the transport, refuses them. */
START_TEST(test_nonfinite_transported) {
  comlearn_yumi_command_t cmd, got;
  memset(&cmd, 0, sizeof cmd);
  fill_yumi_command(&cmd);
  cmd.q_commanded_rad[0][3] = NAN;
  cmd.gripper_width_commanded_m[1] = -INFINITY;
  const lcm_type_info_t *t = comlearn_yumi_command_t_get_type_info();
  size_t len;
  unsigned char *buf = encode_alloc(t, &cmd, &len);
  ck_assert_int_eq(comlearn_msg_decode(t, buf, len, &got, NULL), COMLEARN_MSG_OK);
  ck_assert(isnan(got.q_commanded_rad[0][3]));
  ck_assert(isinf(got.gripper_width_commanded_m[1]) && got.gripper_width_commanded_m[1] < 0);
  ck_assert(got.q_commanded_rad[0][4] == val(4));
  comlearn_yumi_command_t_decode_cleanup(&got);
  free(buf);
}
END_TEST

/* ---------------------------------------------------------------------------------------------
 * Rejection: wrong fingerprint, truncation, malformed strings, trailing bytes, garbage. */

START_TEST(test_reject_fingerprint) {
  /* Every type's buffer decoded as every other type. */
  for (int a = 0; a < NCASES; a++) {
    any_msg_t sent;
    memset(&sent, 0, sizeof sent);
    cases[a].fill(&sent);
    size_t len;
    unsigned char *buf = encode_alloc(cases[a].info(), &sent, &len);
    for (int b = 0; b < NCASES; b++) {
      if (a == b) continue;
      comlearn_msg_stats_t st = {0};
      any_msg_t got;
      memset(&got, 0x5a, sizeof got);
      ck_assert_int_eq(comlearn_msg_decode(cases[b].info(), buf, len, &got, &st),
                       COMLEARN_MSG_E_FINGERPRINT);
      ck_assert_uint_eq(st.received, 1);
      ck_assert_uint_eq(st.rejected_fingerprint, 1);
      ck_assert_uint_eq(st.decoded + st.rejected_truncated + st.rejected_malformed + st.failed, 0);
      /* On error the output is zeroed: safe to clean up, owns nothing. */
      any_msg_t zero;
      memset(&zero, 0, sizeof zero);
      ck_assert(memcmp(&got, &zero, (size_t)cases[b].info()->struct_size()) == 0);
      cases[b].info()->decode_cleanup(&got);
    }
    /* One flipped bit anywhere in the fingerprint. */
    for (size_t bit = 0; bit < 64; bit++) {
      buf[bit / 8] ^= (unsigned char)(1u << (bit % 8));
      ck_assert_int_eq(comlearn_msg_check(cases[a].info(), buf, len), COMLEARN_MSG_E_FINGERPRINT);
      buf[bit / 8] ^= (unsigned char)(1u << (bit % 8));
    }
    ck_assert_int_eq(comlearn_msg_check(cases[a].info(), buf, len), COMLEARN_MSG_OK);
    free(buf);
  }
}
END_TEST

START_TEST(test_reject_truncated) {
  const type_case_t *c = &cases[_i];
  const lcm_type_info_t *t = c->info();
  any_msg_t sent;
  memset(&sent, 0, sizeof sent);
  c->fill(&sent);
  size_t len;
  unsigned char *buf = encode_alloc(t, &sent, &len);
  comlearn_msg_stats_t st = {0};
  for (size_t n = 0; n < len; n++) {
    /* An exact-size heap copy, so the sanitizer sees any read past its end. */
    unsigned char *cut = malloc(n > 0 ? n : 1);
    ck_assert_ptr_nonnull(cut);
    memcpy(cut, buf, n);
    any_msg_t got;
    ck_assert_msg(comlearn_msg_decode(t, cut, n, &got, &st) == COMLEARN_MSG_E_TRUNCATED,
                  "%s cut to %zu of %zu", c->name, n, len);
    free(cut);
  }
  ck_assert_uint_eq(st.received, len);
  ck_assert_uint_eq(st.rejected_truncated, len);
  ck_assert_uint_eq(comlearn_msg_stats_rejected(&st), len);
  ck_assert_uint_eq(st.decoded, 0);
  free(buf);
}
END_TEST

static void put_be32(unsigned char *p, uint32_t v) {
  p[0] = (unsigned char)(v >> 24);
  p[1] = (unsigned char)(v >> 16);
  p[2] = (unsigned char)(v >> 8);
  p[3] = (unsigned char)v;
}

/* Valid fingerprint, broken string: each would make the generated decoder misbehave (allocate
 * gigabytes, read past the buffer, or leave a string without its NUL). */
START_TEST(test_reject_malformed_strings) {
  const lcm_type_info_t *t = comlearn_com_estimate_t_get_type_info();
  comlearn_com_estimate_t sent;
  memset(&sent, 0, sizeof sent);
  fill_com_estimate(&sent);
  size_t len;
  unsigned char *buf = encode_alloc(t, &sent, &len);
  size_t off = first_string_offset(t, &sent);
  ck_assert_uint_eq(off, 8 + 8 + 8); /* fingerprint, utime, run_id */
  uint32_t good = (uint32_t)strlen(sent.object_id) + 1;
  struct {
    uint32_t length;
    comlearn_msg_status_t want;
  } bad[] = {
      {0u, COMLEARN_MSG_E_MALFORMED},          /* LCM always counts the NUL */
      {0xffffffffu, COMLEARN_MSG_E_MALFORMED}, /* -1 */
      {0x80000000u, COMLEARN_MSG_E_MALFORMED}, /* INT32_MIN */
      {0x7fffffffu, COMLEARN_MSG_E_TRUNCATED}, /* longer than the buffer */
      {good - 1, COMLEARN_MSG_E_MALFORMED},    /* last byte is not the NUL */
      {good + 4,
       COMLEARN_MSG_E_MALFORMED}, /* ends on the next length's low byte, 0x0a, not a NUL */
  };
  comlearn_msg_stats_t st = {0};
  for (size_t k = 0; k < sizeof bad / sizeof bad[0]; k++) {
    put_be32(buf + off, bad[k].length);
    comlearn_com_estimate_t got;
    ck_assert_msg(comlearn_msg_decode(t, buf, len, &got, &st) == bad[k].want, "length 0x%08" PRIx32,
                  bad[k].length);
    comlearn_com_estimate_t_decode_cleanup(&got);
  }
  ck_assert_uint_eq(st.received, 6);
  ck_assert_uint_eq(st.rejected_malformed, 5);
  ck_assert_uint_eq(st.rejected_truncated, 1);
  /* Restored, it decodes again. */
  put_be32(buf + off, good);
  comlearn_com_estimate_t got;
  ck_assert_int_eq(comlearn_msg_decode(t, buf, len, &got, &st), COMLEARN_MSG_OK);
  ck_assert_str_eq(got.object_id, "rock_2_uneven");
  comlearn_com_estimate_t_decode_cleanup(&got);
  /* The NUL replaced by a letter; a NUL inside the string (C would cut it, Java would not). */
  buf[off + 4 + good - 1] = 'x';
  ck_assert_int_eq(comlearn_msg_check(t, buf, len), COMLEARN_MSG_E_MALFORMED);
  buf[off + 4 + good - 1] = '\0';
  ck_assert_int_eq(comlearn_msg_check(t, buf, len), COMLEARN_MSG_OK);
  buf[off + 4 + 4] = '\0';
  ck_assert_int_eq(comlearn_msg_check(t, buf, len), COMLEARN_MSG_E_MALFORMED);
  free(buf);
}
END_TEST

START_TEST(test_reject_trailing_bytes) {
  const type_case_t *c = &cases[_i];
  const lcm_type_info_t *t = c->info();
  any_msg_t sent;
  memset(&sent, 0, sizeof sent);
  c->fill(&sent);
  size_t len;
  unsigned char *buf = encode_alloc(t, &sent, &len);
  unsigned char *longer = calloc(len + 3, 1);
  ck_assert_ptr_nonnull(longer);
  memcpy(longer, buf, len);
  comlearn_msg_stats_t st = {0};
  any_msg_t got;
  for (size_t extra = 1; extra <= 3; extra++) {
    ck_assert_int_eq(comlearn_msg_check(t, longer, len + extra), COMLEARN_MSG_E_MALFORMED);
    ck_assert_int_eq(comlearn_msg_decode(t, longer, len + extra, &got, &st),
                     COMLEARN_MSG_E_MALFORMED);
  }
  ck_assert_int_eq(comlearn_msg_check(t, longer, len), COMLEARN_MSG_OK);
  ck_assert_uint_eq(st.rejected_malformed, 3);
  free(longer);
  free(buf);
}
END_TEST

static void check_stats_balance(const comlearn_msg_stats_t *st) {
  ck_assert_uint_eq(st->received, st->decoded + st->rejected_fingerprint + st->rejected_truncated +
                                      st->rejected_malformed + st->failed);
}

/* Random bytes of random length, then random bytes behind a valid fingerprint, then valid
 * buffers with random bytes overwritten: never a crash (ASan/UBSan watch), every buffer counted
 * once, pure garbage never accepted. */
START_TEST(test_reject_garbage) {
  const type_case_t *c = &cases[_i];
  const lcm_type_info_t *t = c->info();
  uint64_t seed = UINT64_C(0x9e3779b97f4a7c15) + (uint64_t)_i;
  any_msg_t sent, got;
  memset(&sent, 0, sizeof sent);
  c->fill(&sent);
  size_t good_len;
  unsigned char *good = encode_alloc(t, &sent, &good_len);

  comlearn_msg_stats_t st = {0};
  const int rounds = 3000;
  for (int r = 0; r < rounds; r++) {
    size_t n = (size_t)(cl_rng_next(&seed) % 700);
    unsigned char *b = malloc(n > 0 ? n : 1);
    ck_assert_ptr_nonnull(b);
    for (size_t k = 0; k < n; k++) b[k] = (unsigned char)cl_rng_next(&seed);
    ck_assert_int_ne(comlearn_msg_decode(t, b, n, &got, &st), COMLEARN_MSG_OK);
    free(b);
  }
  ck_assert_uint_eq(st.received, (uint64_t)rounds);
  ck_assert_uint_eq(comlearn_msg_stats_rejected(&st), (uint64_t)rounds);
  ck_assert_uint_gt(st.rejected_fingerprint, (uint64_t)rounds * 9 / 10);

  comlearn_msg_stats_t st2 = {0};
  for (int r = 0; r < rounds; r++) {
    /* Behind the right fingerprint; lengths near the real one. */
    size_t n = good_len - 40 + (size_t)(cl_rng_next(&seed) % 80);
    unsigned char *b = malloc(n);
    ck_assert_ptr_nonnull(b);
    memcpy(b, good, 8);
    for (size_t k = 8; k < n; k++) b[k] = (unsigned char)cl_rng_next(&seed);
    if (comlearn_msg_decode(t, b, n, &got, &st2) == COMLEARN_MSG_OK) t->decode_cleanup(&got);
    free(b);
  }
  check_stats_balance(&st2);
  ck_assert_uint_eq(st2.rejected_fingerprint, 0);
  ck_assert_uint_eq(st2.failed, 0);

  comlearn_msg_stats_t st3 = {0};
  for (int r = 0; r < rounds; r++) {
    unsigned char *b = malloc(good_len);
    ck_assert_ptr_nonnull(b);
    memcpy(b, good, good_len);
    int flips = 1 + (int)(cl_rng_next(&seed) % 4);
    for (int k = 0; k < flips; k++) {
      size_t at = 8 + (size_t)(cl_rng_next(&seed) % (good_len - 8));
      b[at] ^= (unsigned char)(1 + cl_rng_next(&seed) % 255);
    }
    comlearn_msg_status_t s = comlearn_msg_decode(t, b, good_len, &got, &st3);
    if (s == COMLEARN_MSG_OK) {
      /* Whatever was decoded is a proper message: strings terminated, re-encodes to the bytes. */
      size_t l2;
      unsigned char *again = encode_alloc(t, &got, &l2);
      ck_assert_uint_eq(l2, good_len);
      ck_assert(memcmp(again, b, good_len) == 0);
      free(again);
      t->decode_cleanup(&got);
    }
    free(b);
  }
  check_stats_balance(&st3);
  ck_assert_uint_eq(st3.received, (uint64_t)rounds);
  free(good);
}
END_TEST

START_TEST(test_args_and_status_str) {
  const lcm_type_info_t *t = comlearn_yumi_command_t_get_type_info();
  comlearn_yumi_command_t got;
  comlearn_msg_stats_t st = {0};
  unsigned char b[16] = {0};
  ck_assert_int_eq(comlearn_msg_decode(NULL, b, sizeof b, &got, &st), COMLEARN_MSG_E_ARG);
  ck_assert_int_eq(comlearn_msg_decode(t, b, sizeof b, NULL, &st), COMLEARN_MSG_E_ARG);
  ck_assert_int_eq(comlearn_msg_decode(t, NULL, 5, &got, &st), COMLEARN_MSG_E_ARG);
  ck_assert_int_eq(comlearn_msg_decode(t, NULL, 0, &got, &st), COMLEARN_MSG_E_TRUNCATED);
  ck_assert_uint_eq(st.received, 4);
  ck_assert_uint_eq(st.failed, 3);
  ck_assert_uint_eq(st.rejected_truncated, 1);
  ck_assert_int_eq(comlearn_msg_check(NULL, b, sizeof b), COMLEARN_MSG_E_ARG);
  ck_assert_uint_eq(comlearn_msg_stats_rejected(NULL), 0);

  comlearn_msg_subscription_t *sub =
      (comlearn_msg_subscription_t *)&st; /* must be overwritten with NULL */
  comlearn_msg_sub_config_t cfg = {0};
  ck_assert_int_eq(comlearn_msg_subscribe(NULL, "X", &cfg, &sub), COMLEARN_MSG_E_ARG);
  ck_assert_ptr_null(sub);
  lcm_t *lcm = lcm_create("memq://");
  ck_assert_ptr_nonnull(lcm);
  ck_assert_int_eq(comlearn_msg_subscribe(lcm, "X", &cfg, &sub),
                   COMLEARN_MSG_E_ARG); /* no type, no handler */
  ck_assert_int_eq(comlearn_msg_subscribe(lcm, "", &cfg, &sub), COMLEARN_MSG_E_ARG);
  ck_assert_int_eq(comlearn_msg_subscribe(lcm, "X", NULL, &sub), COMLEARN_MSG_E_ARG);
  ck_assert_int_eq(comlearn_msg_unsubscribe(lcm, NULL), COMLEARN_MSG_OK);
  ck_assert_int_eq(comlearn_msg_subscription_set_queue_capacity(NULL, 1), COMLEARN_MSG_E_ARG);
  lcm_destroy(lcm);

  const comlearn_msg_status_t all[] = {COMLEARN_MSG_OK,          COMLEARN_MSG_E_ARG,
                                       COMLEARN_MSG_E_TRUNCATED, COMLEARN_MSG_E_FINGERPRINT,
                                       COMLEARN_MSG_E_MALFORMED, COMLEARN_MSG_E_NOMEM,
                                       COMLEARN_MSG_E_LCM,       COMLEARN_MSG_E_UNSUPPORTED};
  const char *unknown = comlearn_msg_status_str((comlearn_msg_status_t)-99);
  ck_assert_str_eq(unknown, "unknown status");
  for (size_t i = 0; i < sizeof all / sizeof all[0]; i++) {
    ck_assert_ptr_nonnull(comlearn_msg_status_str(all[i]));
    ck_assert_str_ne(comlearn_msg_status_str(all[i]), unknown);
    for (size_t k = 0; k < i; k++)
      ck_assert_str_ne(comlearn_msg_status_str(all[i]), comlearn_msg_status_str(all[k]));
  }
  ck_assert_str_eq(comlearn_msg_status_str(COMLEARN_MSG_OK), "success");
}
END_TEST

/* Every type lcmtypes/CMakeLists.txt builds has a fixture here, and no other. */
START_TEST(test_every_type_has_a_fixture) {
  const char *list = COMLEARN_LCM_TYPE_NAMES;
  int listed = 0;
  for (const char *name = list; *name != '\0'; listed++) {
    const char *comma = strchr(name, ',');
    size_t n = comma != NULL ? (size_t)(comma - name) : strlen(name);
    int found = 0;
    for (int i = 0; i < NCASES; i++)
      found += strlen(cases[i].name) == n && strncmp(cases[i].name, name, n) == 0;
    ck_assert_msg(found == 1, "type %.*s has no fixture in check_messages.c", (int)n, name);
    name += comma != NULL ? n + 1 : n;
  }
  ck_assert_int_eq(listed, NCASES);
}
END_TEST

/* Channel prefixes (many robots on one URL): letters, digits and _ only, at most 32, so that no
 * regex metacharacter reaches a subscription and the longest name fits LCM's 63. */
START_TEST(test_channel_prefix) {
  ck_assert_int_eq(comlearn_msg_channel_prefix_ok(NULL), 1);
  ck_assert_int_eq(comlearn_msg_channel_prefix_ok(""), 1);
  ck_assert_int_eq(comlearn_msg_channel_prefix_ok("R2_"), 1);
  ck_assert_int_eq(comlearn_msg_channel_prefix_ok("yumi_3_"), 1);
  ck_assert_int_eq(comlearn_msg_channel_prefix_ok("R.*"), 0);
  ck_assert_int_eq(comlearn_msg_channel_prefix_ok("R-2"), 0);
  ck_assert_int_eq(comlearn_msg_channel_prefix_ok("R 2"), 0);
  ck_assert_int_eq(comlearn_msg_channel_prefix_ok("ABCDEFGHIJKLMNOPQRSTUVWXYZ012345"), 1); /* 32 */
  ck_assert_int_eq(comlearn_msg_channel_prefix_ok("ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456"), 0);
  char ch[64];
  ck_assert_int_eq(comlearn_msg_channel("R2_", COMLEARN_MSG_CHANNEL_YUMI_COMMAND, ch, sizeof ch),
                   COMLEARN_MSG_OK);
  ck_assert_str_eq(ch, "R2_YUMI_COMMAND");
  ck_assert_int_eq(comlearn_msg_channel(NULL, COMLEARN_MSG_CHANNEL_COM_ESTIMATE, ch, sizeof ch),
                   COMLEARN_MSG_OK);
  ck_assert_str_eq(ch, "COM_ESTIMATE");
  ck_assert_int_eq(
      comlearn_msg_channel("ABCDEFGHIJKLMNOPQRSTUVWXYZ012345", "COM_ESTIMATE", ch, sizeof ch),
      COMLEARN_MSG_OK);
  ck_assert_uint_le(strlen(ch), 63);
  ck_assert_int_eq(comlearn_msg_channel("R|S", "YUMI_STATUS", ch, sizeof ch), COMLEARN_MSG_E_ARG);
  ck_assert_str_eq(ch, "");
  ck_assert_int_eq(comlearn_msg_channel("R2_", "YUMI_STATUS", ch, 8), COMLEARN_MSG_E_ARG);
  ck_assert_str_eq(ch, "");
  ck_assert_int_eq(comlearn_msg_channel("R2_", NULL, ch, sizeof ch), COMLEARN_MSG_E_ARG);
  comlearn_msg_channels_t all;
  ck_assert_int_eq(comlearn_msg_channels("R2_", &all), COMLEARN_MSG_OK);
  ck_assert_str_eq(all.yumi_command, "R2_YUMI_COMMAND");
  ck_assert_str_eq(all.object_state, "R2_OBJECT_STATE");
  ck_assert_str_eq(all.com_estimate, "R2_COM_ESTIMATE");
  ck_assert_int_eq(comlearn_msg_channels(NULL, &all), COMLEARN_MSG_OK);
  ck_assert_str_eq(all.sim_control, "SIM_CONTROL");
  ck_assert_int_eq(comlearn_msg_channels("R*", &all), COMLEARN_MSG_E_ARG);
  ck_assert_str_eq(all.yumi_status, "");
}
END_TEST

/* The contract of docs/messages.md that code relies on. */
START_TEST(test_constants) {
  ck_assert_str_eq(COMLEARN_MSG_LCM_URL_DEFAULT, "udpm://239.255.76.67:7667?ttl=0");
  const char *names[] = {COMLEARN_MSG_CHANNEL_YUMI_COMMAND, COMLEARN_MSG_CHANNEL_YUMI_STATUS,
                         COMLEARN_MSG_CHANNEL_OBJECT_STATE, COMLEARN_MSG_CHANNEL_SIM_CONTROL,
                         COMLEARN_MSG_CHANNEL_COM_TRIAL,    COMLEARN_MSG_CHANNEL_COM_ESTIMATE};
  const char *want[] = {"YUMI_COMMAND", "YUMI_STATUS", "OBJECT_STATE",
                        "SIM_CONTROL",  "COM_TRIAL",   "COM_ESTIMATE"};
  for (int i = 0; i < 6; i++) ck_assert_str_eq(names[i], want[i]);
  /* A zeroed message is the harmless one: hold, not an action, no outcome, no error. */
  ck_assert_int_eq(COMLEARN_YUMI_COMMAND_T_MODE_HOLD, 0);
  ck_assert_int_eq(COMLEARN_YUMI_STATUS_T_STATE_HOLD, 0);
  ck_assert_int_eq(COMLEARN_YUMI_STATUS_T_ERR_NONE, 0);
  ck_assert_int_ne(COMLEARN_SIM_CONTROL_T_ACTION_LOAD, 0);
  ck_assert_int_ne(COMLEARN_SIM_CONTROL_T_ACTION_RESET, 0);
  ck_assert_int_ne(COMLEARN_SIM_CONTROL_T_ACTION_REMOVE, 0);
  ck_assert_int_eq(COMLEARN_COM_TRIAL_T_OUTCOME_INVALID, 0);
  ck_assert_int_eq(COMLEARN_OBJECT_STATE_T_SIM_CONTROL_APPLIED, 0);
  /* Six distinct fingerprints (lcm-spy picks the class by fingerprint). */
  for (int a = 0; a < NCASES; a++)
    for (int b = 0; b < a; b++)
      ck_assert(cases[a].info()->get_hash() != cases[b].info()->get_hash());
}
END_TEST

/* ---------------------------------------------------------------------------------------------
 * Publish / handle through memq://. */

typedef struct {
  const type_case_t *c;
  const void *sent;
  int received;
  int mismatches;
  int64_t recv_utime;
  char where[128];
  char channel[32];
  comlearn_msg_status_t last_reject;
  int rejects;
} sink_t;

static void on_message(const lcm_recv_buf_t *rbuf, const char *channel, const void *msg,
                       void *user) {
  sink_t *s = user;
  s->received++;
  s->recv_utime = rbuf->recv_utime;
  snprintf(s->channel, sizeof s->channel, "%s", channel);
  if (msg_diff(s->c->info(), s->sent, msg, s->where, sizeof s->where) != 0)
    s->mismatches++;
  else
    s->c->spot(msg);
}

static void on_reject(const lcm_recv_buf_t *rbuf, const char *channel, comlearn_msg_status_t reason,
                      void *user) {
  (void)rbuf;
  (void)channel;
  sink_t *s = user;
  s->rejects++;
  s->last_reject = reason;
}

static int drain(lcm_t *lcm) {
  int handled = 0;
  for (int guard = 0; guard < 100000; guard++) {
    int rc = lcm_handle_timeout(lcm, 20);
    ck_assert_int_ge(rc, 0);
    if (rc == 0) return handled;
    handled++;
  }
  ck_abort_msg("memq never ran dry");
  return handled;
}

START_TEST(test_memq_publish_handle) {
  lcm_t *lcm = lcm_create("memq://");
  ck_assert_ptr_nonnull(lcm);
  any_msg_t sent[NCASES];
  sink_t sinks[NCASES];
  comlearn_msg_stats_t stats[NCASES];
  comlearn_msg_subscription_t *subs[NCASES];
  memset(sinks, 0, sizeof sinks);
  memset(stats, 0, sizeof stats);
  for (int i = 0; i < NCASES; i++) {
    memset(&sent[i], 0, sizeof sent[i]);
    cases[i].fill(&sent[i]);
    sinks[i].c = &cases[i];
    sinks[i].sent = &sent[i];
    comlearn_msg_sub_config_t cfg = {.type = cases[i].info(),
                                     .on_message = on_message,
                                     .on_reject = on_reject,
                                     .user = &sinks[i],
                                     .stats = &stats[i]};
    ck_assert_int_eq(comlearn_msg_subscribe(lcm, cases[i].channel, &cfg, &subs[i]),
                     COMLEARN_MSG_OK);
    ck_assert_ptr_nonnull(subs[i]);
  }
  ck_assert_int_eq(comlearn_msg_subscription_set_queue_capacity(subs[0], 5), COMLEARN_MSG_OK);
  /* Publish in reverse order, twice, with the generated typed publish functions. */
  for (int round = 0; round < 2; round++)
    for (int i = NCASES - 1; i >= 0; i--)
      ck_assert_int_eq(cases[i].publish(lcm, cases[i].channel, &sent[i]), 0);
  ck_assert_int_eq(drain(lcm), 2 * NCASES);
  for (int i = 0; i < NCASES; i++) {
    ck_assert_msg(sinks[i].mismatches == 0, "%s over memq: %s differs", cases[i].name,
                  sinks[i].where);
    ck_assert_int_eq(sinks[i].received, 2);
    ck_assert_int_eq(sinks[i].rejects, 0);
    ck_assert_str_eq(sinks[i].channel, cases[i].channel);
    ck_assert_int_gt(sinks[i].recv_utime, 0);
    ck_assert_uint_eq(stats[i].received, 2);
    ck_assert_uint_eq(stats[i].decoded, 2);
  }
  for (int i = 0; i < NCASES; i++)
    ck_assert_int_eq(comlearn_msg_unsubscribe(lcm, subs[i]), COMLEARN_MSG_OK);
  lcm_destroy(lcm);
}
END_TEST

/* Wrong type, truncated buffers and garbage on every channel: rejected, counted, the handler is
 * never called with them, and a good message after them still arrives. */
START_TEST(test_memq_rejects) {
  lcm_t *lcm = lcm_create("memq://");
  ck_assert_ptr_nonnull(lcm);
  any_msg_t sent[NCASES];
  sink_t sinks[NCASES];
  comlearn_msg_stats_t shared = {
      0}; /* one counter set for all subscriptions, as a daemon keeps it */
  comlearn_msg_subscription_t *subs[NCASES];
  memset(sinks, 0, sizeof sinks);
  for (int i = 0; i < NCASES; i++) {
    memset(&sent[i], 0, sizeof sent[i]);
    cases[i].fill(&sent[i]);
    sinks[i].c = &cases[i];
    sinks[i].sent = &sent[i];
    comlearn_msg_sub_config_t cfg = {.type = cases[i].info(),
                                     .on_message = on_message,
                                     .on_reject = on_reject,
                                     .user = &sinks[i],
                                     .stats = &shared};
    ck_assert_int_eq(comlearn_msg_subscribe(lcm, cases[i].channel, &cfg, &subs[i]),
                     COMLEARN_MSG_OK);
  }
  uint64_t seed = 12345;
  for (int i = 0; i < NCASES; i++) {
    int other = (i + 1) % NCASES;
    size_t len;
    unsigned char *buf = encode_alloc(cases[other].info(), &sent[other], &len);
    ck_assert_int_eq(lcm_publish(lcm, cases[i].channel, buf, (unsigned)len), 0); /* wrong type */
    free(buf);
    buf = encode_alloc(cases[i].info(), &sent[i], &len);
    ck_assert_int_eq(lcm_publish(lcm, cases[i].channel, buf, (unsigned)(len / 2)), 0);
    ck_assert_int_eq(lcm_publish(lcm, cases[i].channel, buf, 3), 0);
    unsigned char junk[64];
    for (size_t k = 0; k < sizeof junk; k++) junk[k] = (unsigned char)cl_rng_next(&seed);
    ck_assert_int_eq(lcm_publish(lcm, cases[i].channel, junk, sizeof junk), 0);
    ck_assert_int_eq(lcm_publish(lcm, cases[i].channel, buf, 0), 0); /* empty */
    free(buf);
    ck_assert_int_eq(cases[i].publish(lcm, cases[i].channel, &sent[i]), 0); /* then a good one */
  }
  ck_assert_int_eq(drain(lcm), 6 * NCASES);
  for (int i = 0; i < NCASES; i++) {
    ck_assert_int_eq(sinks[i].received, 1);
    ck_assert_int_eq(sinks[i].mismatches, 0);
    ck_assert_int_eq(sinks[i].rejects, 5);
  }
  ck_assert_uint_eq(shared.received, 6 * NCASES);
  ck_assert_uint_eq(shared.decoded, NCASES);
  ck_assert_uint_eq(shared.rejected_fingerprint, 2 * NCASES); /* wrong type and junk */
  ck_assert_uint_eq(shared.rejected_truncated, 3 * NCASES);   /* half, 3 bytes, empty */
  ck_assert_uint_eq(comlearn_msg_stats_rejected(&shared), 5 * NCASES);
  for (int i = 0; i < NCASES; i++)
    ck_assert_int_eq(comlearn_msg_unsubscribe(lcm, subs[i]), COMLEARN_MSG_OK);
  lcm_destroy(lcm);
}
END_TEST

/* ---------------------------------------------------------------------------------------------
 * Fixture writer for the Java cross-check. One line per element: name[i][j]=value; integers in
 * decimal, booleans 0/1, floating point as the hex of its bits, strings as '"' and the hex of
 * their bytes. */

static void dump_fields(FILE *out, const lcm_type_info_t *t, const void *m) {
  for (int i = 0; i < t->num_fields(); i++) {
    lcm_field_t f;
    memset(&f, 0, sizeof f);
    if (t->get_field(m, i, &f) != 0) return;
    size_t cnt = 1;
    for (int d = 0; d < f.num_dim; d++) cnt *= (size_t)f.dim_size[d];
    for (size_t e = 0; e < cnt; e++) {
      fputs(f.name, out);
      size_t rest = e, stride = cnt;
      for (int d = 0; d < f.num_dim; d++) {
        stride /= (size_t)f.dim_size[d];
        fprintf(out, "[%zu]", rest / stride);
        rest %= stride;
      }
      fputc('=', out);
      const char *p = (const char *)f.data;
      switch (f.type) {
        case LCM_FIELD_INT8_T:
        case LCM_FIELD_BOOLEAN: fprintf(out, "%d", (int)((const int8_t *)p)[e]); break;
        case LCM_FIELD_BYTE: fprintf(out, "%d", (int)(int8_t)((const uint8_t *)p)[e]); break;
        case LCM_FIELD_INT16_T: fprintf(out, "%d", (int)((const int16_t *)p)[e]); break;
        case LCM_FIELD_INT32_T: fprintf(out, "%" PRId32, ((const int32_t *)p)[e]); break;
        case LCM_FIELD_INT64_T: fprintf(out, "%" PRId64, ((const int64_t *)p)[e]); break;
        case LCM_FIELD_FLOAT: {
          uint32_t bits;
          memcpy(&bits, p + e * 4, 4);
          fprintf(out, "0x%08" PRIx32, bits);
          break;
        }
        case LCM_FIELD_DOUBLE: {
          uint64_t bits;
          memcpy(&bits, p + e * 8, 8);
          fprintf(out, "0x%016" PRIx64, bits);
          break;
        }
        case LCM_FIELD_STRING: {
          const unsigned char *s = (const unsigned char *)((char *const *)p)[e];
          fputc('"', out);
          for (; *s != '\0'; s++) fprintf(out, "%02x", *s);
          break;
        }
        case LCM_FIELD_USER_TYPE: break;
      }
      fputc('\n', out);
    }
  }
}

static int write_fixtures(const char *dir) {
  for (int i = 0; i < NCASES; i++) {
    const lcm_type_info_t *t = cases[i].info();
    any_msg_t m;
    memset(&m, 0, sizeof m);
    cases[i].fill(&m);
    int n = t->encoded_size(&m);
    unsigned char *buf = malloc((size_t)n);
    if (buf == NULL || t->encode(buf, 0, n, &m) != n) {
      fprintf(stderr, "check_messages: cannot encode %s\n", cases[i].name);
      free(buf);
      return 1;
    }
    char path[4096];
    snprintf(path, sizeof path, "%s/%s.bin", dir, cases[i].name);
    FILE *f = fopen(path, "wb");
    int ok = f != NULL && fwrite(buf, 1, (size_t)n, f) == (size_t)n;
    if (f != NULL && fclose(f) != 0) ok = 0;
    free(buf);
    if (!ok) {
      fprintf(stderr, "check_messages: cannot write %s\n", path);
      return 1;
    }
    snprintf(path, sizeof path, "%s/%s.txt", dir, cases[i].name);
    f = fopen(path, "w");
    if (f == NULL) {
      fprintf(stderr, "check_messages: cannot write %s\n", path);
      return 1;
    }
    dump_fields(f, t, &m);
    if (fclose(f) != 0) return 1;
  }
  printf("check_messages: wrote %d fixtures to %s\n", NCASES, dir);
  return 0;
}

static Suite *messages_suite(void) {
  Suite *s = suite_create("messages");
  TCase *tc = tcase_create("roundtrip");
  tcase_add_loop_test(tc, test_fixture_nontrivial, 0, NCASES);
  tcase_add_loop_test(tc, test_roundtrip_msg_decode, 0, NCASES);
  tcase_add_loop_test(tc, test_roundtrip_generated_decode, 0, NCASES);
  tcase_add_loop_test(tc, test_compare_sees_every_field, 0, NCASES);
  tcase_add_test(tc, test_nonfinite_transported);
  tcase_add_test(tc, test_constants);
  tcase_add_test(tc, test_channel_prefix);
  tcase_add_test(tc, test_every_type_has_a_fixture);
  suite_add_tcase(s, tc);

  tc = tcase_create("reject");
  tcase_set_timeout(tc, 120);
  tcase_add_test(tc, test_reject_fingerprint);
  tcase_add_loop_test(tc, test_reject_truncated, 0, NCASES);
  tcase_add_test(tc, test_reject_malformed_strings);
  tcase_add_loop_test(tc, test_reject_trailing_bytes, 0, NCASES);
  tcase_add_loop_test(tc, test_reject_garbage, 0, NCASES);
  tcase_add_test(tc, test_args_and_status_str);
  suite_add_tcase(s, tc);

  tc = tcase_create("memq");
  tcase_add_test(tc, test_memq_publish_handle);
  tcase_add_test(tc, test_memq_rejects);
  suite_add_tcase(s, tc);
  return s;
}

int main(int argc, char **argv) {
  if (argc == 3 && strcmp(argv[1], "--write-fixtures") == 0) return write_fixtures(argv[2]);
  if (argc != 1) {
    fprintf(stderr, "usage: check_messages [--write-fixtures DIR]\n");
    return 2;
  }
  SRunner *runner = srunner_create(messages_suite());
  srunner_run_all(runner, CK_NORMAL);
  int failed = srunner_ntests_failed(runner);
  srunner_free(runner);
  return failed == 0 ? EXIT_SUCCESS : EXIT_FAILURE;
}
