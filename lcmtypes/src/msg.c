/* comlearn/msg.h: a schema walk in front of the lcm-gen decoder, and counting subscriptions. */
#include "comlearn/msg.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "comlearn/comlearn_sim_control_t.h"
#include "comlearn/comlearn_yumi_command_t.h"
#include "comlearn/comlearn_yumi_status_t.h"

/* The arm indices are declared in three messages (LCM constants are per message); they must
 * agree. */
_Static_assert(COMLEARN_YUMI_COMMAND_T_ARM_LEFT == COMLEARN_YUMI_STATUS_T_ARM_LEFT &&
                   COMLEARN_YUMI_COMMAND_T_ARM_LEFT == COMLEARN_SIM_CONTROL_T_ARM_LEFT &&
                   COMLEARN_YUMI_COMMAND_T_ARM_RIGHT == COMLEARN_YUMI_STATUS_T_ARM_RIGHT &&
                   COMLEARN_YUMI_COMMAND_T_ARM_RIGHT == COMLEARN_SIM_CONTROL_T_ARM_RIGHT,
               "arm indices differ between yumi_command_t, yumi_status_t and sim_control_t");

enum { FINGERPRINT_BYTES = 8, STRING_LENGTH_BYTES = 4 };

/* get_field() only takes addresses inside the struct it is given (variable dimensions, which
 * would read a count from it, are refused), so a zeroed static block serves every type whose
 * struct fits; larger structs get a temporary zeroed allocation. */
enum { SCHEMA_SCRATCH_BYTES = 4096 };
static const union {
  long double align_ld;
  void *align_ptr;
  long long align_ll;
  unsigned char bytes[SCHEMA_SCRATCH_BYTES];
} schema_scratch;

int comlearn_msg_channel_prefix_ok(const char *prefix) {
  if (prefix == NULL) return 1;
  size_t n = 0;
  for (; prefix[n] != '\0'; ++n) {
    const char c = prefix[n];
    if (n >= COMLEARN_MSG_CHANNEL_PREFIX_MAX ||
        !((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_'))
      return 0;
  }
  return 1;
}

comlearn_msg_status_t comlearn_msg_channel(const char *prefix, const char *base, char *out,
                                           size_t size) {
  if (out == NULL || size == 0) return COMLEARN_MSG_E_ARG;
  out[0] = '\0';
  if (base == NULL || !comlearn_msg_channel_prefix_ok(prefix)) return COMLEARN_MSG_E_ARG;
  const int k = snprintf(out, size, "%s%s", prefix ? prefix : "", base);
  if (k < 0 || (size_t)k >= size) {
    out[0] = '\0';
    return COMLEARN_MSG_E_ARG;
  }
  return COMLEARN_MSG_OK;
}

comlearn_msg_status_t comlearn_msg_channels(const char *prefix, comlearn_msg_channels_t *out) {
  if (out == NULL) return COMLEARN_MSG_E_ARG;
  struct {
    const char *base;
    char *name;
  } all[] = {{COMLEARN_MSG_CHANNEL_YUMI_COMMAND, out->yumi_command},
             {COMLEARN_MSG_CHANNEL_YUMI_STATUS, out->yumi_status},
             {COMLEARN_MSG_CHANNEL_OBJECT_STATE, out->object_state},
             {COMLEARN_MSG_CHANNEL_SIM_CONTROL, out->sim_control},
             {COMLEARN_MSG_CHANNEL_COM_TRIAL, out->com_trial},
             {COMLEARN_MSG_CHANNEL_COM_ESTIMATE, out->com_estimate}};
  comlearn_msg_status_t st = COMLEARN_MSG_OK;
  for (size_t i = 0; i < sizeof all / sizeof all[0]; ++i)
    if (comlearn_msg_channel(prefix, all[i].base, all[i].name, sizeof out->yumi_command) !=
        COMLEARN_MSG_OK)
      st = COMLEARN_MSG_E_ARG;
  return st;
}

const char *comlearn_msg_status_str(comlearn_msg_status_t status) {
  switch (status) {
    case COMLEARN_MSG_OK: return "success";
    case COMLEARN_MSG_E_ARG: return "invalid argument";
    case COMLEARN_MSG_E_TRUNCATED: return "buffer truncated: it ends before the message does";
    case COMLEARN_MSG_E_FINGERPRINT:
      return "wrong fingerprint: the buffer holds another message type";
    case COMLEARN_MSG_E_MALFORMED:
      return "malformed buffer: bad string length or NUL, or trailing bytes";
    case COMLEARN_MSG_E_NOMEM: return "out of memory";
    case COMLEARN_MSG_E_LCM: return "LCM call failed";
    case COMLEARN_MSG_E_UNSUPPORTED:
      return "type not supported (nested type or variable-length array)";
  }
  return "unknown status";
}

uint64_t comlearn_msg_stats_rejected(const comlearn_msg_stats_t *stats) {
  if (stats == NULL) return 0;
  return stats->rejected_fingerprint + stats->rejected_truncated + stats->rejected_malformed;
}

static uint64_t read_be64(const unsigned char *p) {
  uint64_t v = 0;
  for (int i = 0; i < 8; i++) v = (v << 8) | p[i];
  return v;
}

static uint32_t read_be32(const unsigned char *p) {
  return ((uint32_t)p[0] << 24) | ((uint32_t)p[1] << 16) | ((uint32_t)p[2] << 8) | (uint32_t)p[3];
}

/* Encoded bytes of one element of a primitive field; 0 for a string, -1 if not supported. */
static int element_bytes(lcm_field_type_t type) {
  switch (type) {
    case LCM_FIELD_INT8_T:
    case LCM_FIELD_BYTE:
    case LCM_FIELD_BOOLEAN: return 1;
    case LCM_FIELD_INT16_T: return 2;
    case LCM_FIELD_INT32_T:
    case LCM_FIELD_FLOAT: return 4;
    case LCM_FIELD_INT64_T:
    case LCM_FIELD_DOUBLE: return 8;
    case LCM_FIELD_STRING: return 0;
    case LCM_FIELD_USER_TYPE: return -1;
  }
  return -1;
}

/* Field i of the schema, with its element count (product of its fixed dimensions; SIZE_MAX when
 * the product overflows). */
static comlearn_msg_status_t schema_field(const lcm_type_info_t *type, const void *scratch, int i,
                                          lcm_field_t *f, size_t *count, int *elem_bytes) {
  memset(f, 0, sizeof *f);
  if (type->get_field(scratch, i, f) != 0) return COMLEARN_MSG_E_UNSUPPORTED;
  *elem_bytes = element_bytes(f->type);
  if (*elem_bytes < 0) return COMLEARN_MSG_E_UNSUPPORTED;
  if (f->num_dim < 0 || f->num_dim > LCM_TYPE_FIELD_MAX_DIM) return COMLEARN_MSG_E_UNSUPPORTED;
  size_t n = 1;
  for (int d = 0; d < f->num_dim; d++) {
    if (f->dim_is_variable[d] || f->dim_size[d] < 0) return COMLEARN_MSG_E_UNSUPPORTED;
    size_t dim = (size_t)f->dim_size[d];
    n = (dim != 0 && n > SIZE_MAX / dim) ? SIZE_MAX : n * dim;
  }
  *count = n;
  return COMLEARN_MSG_OK;
}

static comlearn_msg_status_t schema_supported(const lcm_type_info_t *type, const void *scratch) {
  int nfields = type->num_fields();
  if (nfields < 0) return COMLEARN_MSG_E_UNSUPPORTED;
  for (int i = 0; i < nfields; i++) {
    lcm_field_t f;
    size_t count;
    int eb;
    comlearn_msg_status_t st = schema_field(type, scratch, i, &f, &count, &eb);
    if (st != COMLEARN_MSG_OK) return st;
  }
  return COMLEARN_MSG_OK;
}

/* The walk itself: fingerprint, then every field in order, then nothing after the end. */
static comlearn_msg_status_t walk(const lcm_type_info_t *type, const void *scratch,
                                  const unsigned char *buf, size_t len) {
  if (len < FINGERPRINT_BYTES) return COMLEARN_MSG_E_TRUNCATED;
  if (read_be64(buf) != (uint64_t)type->get_hash()) return COMLEARN_MSG_E_FINGERPRINT;
  size_t pos = FINGERPRINT_BYTES;
  int nfields = type->num_fields();
  if (nfields < 0) return COMLEARN_MSG_E_UNSUPPORTED;
  for (int i = 0; i < nfields; i++) {
    lcm_field_t f;
    size_t count;
    int eb;
    comlearn_msg_status_t st = schema_field(type, scratch, i, &f, &count, &eb);
    if (st != COMLEARN_MSG_OK) return st;
    if (eb > 0) {
      if (count > (len - pos) / (size_t)eb) return COMLEARN_MSG_E_TRUNCATED;
      pos += count * (size_t)eb;
      continue;
    }
    /* Strings: int32 length including the NUL, then the bytes. LCM always writes >= 1. */
    for (size_t e = 0; e < count; e++) {
      if (len - pos < STRING_LENGTH_BYTES) return COMLEARN_MSG_E_TRUNCATED;
      int32_t slen = (int32_t)read_be32(buf + pos);
      pos += STRING_LENGTH_BYTES;
      if (slen < 1) return COMLEARN_MSG_E_MALFORMED;
      if ((size_t)slen > len - pos) return COMLEARN_MSG_E_TRUNCATED;
      /* Exactly one NUL, at the end: the C side would silently cut a string at an inner NUL
       * that Java (lcm-spy) shows, and an encoder never writes one. */
      if (memchr(buf + pos, '\0', (size_t)slen) != buf + pos + (size_t)slen - 1)
        return COMLEARN_MSG_E_MALFORMED;
      pos += (size_t)slen;
    }
  }
  return pos == len ? COMLEARN_MSG_OK : COMLEARN_MSG_E_MALFORMED;
}

/* A zeroed block of at least the type's struct size for get_field(); *owned is set when it was
 * allocated. NULL when out of memory or the size is not sane. */
static const void *scratch_for(const lcm_type_info_t *type, void **owned) {
  *owned = NULL;
  int size = type->struct_size();
  if (size <= 0) return NULL;
  if ((size_t)size <= sizeof schema_scratch.bytes) return schema_scratch.bytes;
  *owned = calloc(1, (size_t)size);
  return *owned;
}

comlearn_msg_status_t comlearn_msg_check(const lcm_type_info_t *type, const void *buf, size_t len) {
  if (type == NULL || (buf == NULL && len > 0) || len > (size_t)INT_MAX) return COMLEARN_MSG_E_ARG;
  void *owned;
  const void *scratch = scratch_for(type, &owned);
  if (scratch == NULL) return COMLEARN_MSG_E_NOMEM;
  comlearn_msg_status_t st = walk(type, scratch, (const unsigned char *)buf, len);
  free(owned);
  return st;
}

static void count(comlearn_msg_stats_t *stats, comlearn_msg_status_t st) {
  if (stats == NULL) return;
  stats->received++;
  switch (st) {
    case COMLEARN_MSG_OK: stats->decoded++; break;
    case COMLEARN_MSG_E_FINGERPRINT: stats->rejected_fingerprint++; break;
    case COMLEARN_MSG_E_TRUNCATED: stats->rejected_truncated++; break;
    case COMLEARN_MSG_E_MALFORMED: stats->rejected_malformed++; break;
    case COMLEARN_MSG_E_ARG:
    case COMLEARN_MSG_E_NOMEM:
    case COMLEARN_MSG_E_LCM:
    case COMLEARN_MSG_E_UNSUPPORTED: stats->failed++; break;
  }
}

comlearn_msg_status_t comlearn_msg_decode(const lcm_type_info_t *type, const void *buf, size_t len,
                                          void *msg, comlearn_msg_stats_t *stats) {
  if (type == NULL || msg == NULL) {
    count(stats, COMLEARN_MSG_E_ARG);
    return COMLEARN_MSG_E_ARG;
  }
  int size = type->struct_size();
  if (size <= 0) {
    count(stats, COMLEARN_MSG_E_UNSUPPORTED);
    return COMLEARN_MSG_E_UNSUPPORTED;
  }
  memset(msg, 0, (size_t)size);
  comlearn_msg_status_t st = comlearn_msg_check(type, buf, len);
  if (st == COMLEARN_MSG_OK) {
    /* Cannot fail after the walk; if it ever does, release what it decoded. */
    int used = type->decode(buf, 0, (int)len, msg);
    if (used < 0 || (size_t)used != len) {
      type->decode_cleanup(msg);
      memset(msg, 0, (size_t)size);
      st = COMLEARN_MSG_E_MALFORMED;
    }
  }
  count(stats, st);
  return st;
}

struct comlearn_msg_subscription {
  lcm_subscription_t *lcm_sub;
  comlearn_msg_sub_config_t cfg;
  void *msg; /* scratch message of cfg.type, zeroed between deliveries */
};

static void on_raw(const lcm_recv_buf_t *rbuf, const char *channel, void *user) {
  comlearn_msg_subscription_t *sub = user;
  comlearn_msg_status_t st =
      comlearn_msg_decode(sub->cfg.type, rbuf->data, rbuf->data_size, sub->msg, sub->cfg.stats);
  if (st == COMLEARN_MSG_OK) {
    sub->cfg.on_message(rbuf, channel, sub->msg, sub->cfg.user);
    sub->cfg.type->decode_cleanup(sub->msg);
  } else if (sub->cfg.on_reject != NULL) {
    sub->cfg.on_reject(rbuf, channel, st, sub->cfg.user);
  }
}

comlearn_msg_status_t comlearn_msg_subscribe(lcm_t *lcm, const char *channel,
                                             const comlearn_msg_sub_config_t *cfg,
                                             comlearn_msg_subscription_t **out) {
  if (out != NULL) *out = NULL;
  if (lcm == NULL || channel == NULL || channel[0] == '\0' || cfg == NULL || cfg->type == NULL ||
      cfg->on_message == NULL || out == NULL)
    return COMLEARN_MSG_E_ARG;
  int size = cfg->type->struct_size();
  if (size <= 0) return COMLEARN_MSG_E_UNSUPPORTED;
  comlearn_msg_subscription_t *sub = calloc(1, sizeof *sub);
  if (sub == NULL) return COMLEARN_MSG_E_NOMEM;
  sub->cfg = *cfg;
  sub->msg = calloc(1, (size_t)size);
  if (sub->msg == NULL) {
    free(sub);
    return COMLEARN_MSG_E_NOMEM;
  }
  comlearn_msg_status_t st = schema_supported(cfg->type, sub->msg);
  if (st != COMLEARN_MSG_OK) {
    free(sub->msg);
    free(sub);
    return st;
  }
  sub->lcm_sub = lcm_subscribe(lcm, channel, on_raw, sub);
  if (sub->lcm_sub == NULL) {
    free(sub->msg);
    free(sub);
    return COMLEARN_MSG_E_LCM;
  }
  *out = sub;
  return COMLEARN_MSG_OK;
}

comlearn_msg_status_t comlearn_msg_subscription_set_queue_capacity(comlearn_msg_subscription_t *sub,
                                                                   int capacity) {
  if (sub == NULL || capacity < 0) return COMLEARN_MSG_E_ARG;
  return lcm_subscription_set_queue_capacity(sub->lcm_sub, capacity) == 0 ? COMLEARN_MSG_OK
                                                                          : COMLEARN_MSG_E_LCM;
}

comlearn_msg_status_t comlearn_msg_unsubscribe(lcm_t *lcm, comlearn_msg_subscription_t *sub) {
  if (sub == NULL) return COMLEARN_MSG_OK;
  if (lcm == NULL) return COMLEARN_MSG_E_ARG;
  int rc = lcm_unsubscribe(lcm, sub->lcm_sub);
  free(sub->msg);
  free(sub);
  return rc == 0 ? COMLEARN_MSG_OK : COMLEARN_MSG_E_LCM;
}
