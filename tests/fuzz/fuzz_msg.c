/* fuzz_msg.c - libFuzzer harness: every comlearn message type's decoder (comlearn_msg_decode) on
 * arbitrary bytes. A buffer either decodes (then its strings are released) or is refused; nothing
 * may crash, leak or read out of bounds. docs/security.md, "Fuzzing". */
#include <stddef.h>
#include <stdint.h>

#include "comlearn/comlearn_com_estimate_t.h"
#include "comlearn/comlearn_com_trial_t.h"
#include "comlearn/comlearn_object_state_t.h"
#include "comlearn/comlearn_sim_control_t.h"
#include "comlearn/comlearn_yumi_command_t.h"
#include "comlearn/comlearn_yumi_status_t.h"
#include "comlearn/msg.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  const lcm_type_info_t *types[] = {
      comlearn_yumi_command_t_get_type_info(), comlearn_yumi_status_t_get_type_info(),
      comlearn_object_state_t_get_type_info(), comlearn_sim_control_t_get_type_info(),
      comlearn_com_trial_t_get_type_info(),    comlearn_com_estimate_t_get_type_info()};
  _Alignas(16) unsigned char msg[8192];
  comlearn_msg_stats_t stats = {0};
  for (size_t i = 0; i < sizeof types / sizeof types[0]; ++i) {
    if ((size_t)types[i]->struct_size() > sizeof msg) continue;
    if (comlearn_msg_decode(types[i], data, size, msg, &stats) == COMLEARN_MSG_OK)
      types[i]->decode_cleanup(msg);
  }
  return 0;
}
