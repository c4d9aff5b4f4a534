/* estimate_balance.c - learn a rock's CoM with lib/estimate, running each trial on lib/balance.
 * Usage: estimate_balance ROCK.urdf. The estimator sees the mesh only; the trials use the URDF's
 * <inertial> (the truth), as a real robot's physics would. */
#include <stdio.h>

#include "comlearn/balance.h"
#include "comlearn/estimate.h"
#include "comlearn/model_inertial.h"

int main(int argc, char **argv) {
  model_object_t obj = {0};
  model_mass_t truth;
  model_error_t err = {{0}};
  if (argc != 2 || model_object_load(argv[1], NULL, &obj, &err) != MODEL_OK ||
      model_inertial_load(argv[1], NULL, &truth, &err) != MODEL_OK)
    return fprintf(stderr, "usage: estimate_balance ROCK.urdf (%s)\n", err.msg), 2;
  balance_config_t bc;
  balance_config_default(&bc);
  balance_world_t *world = NULL;
  balance_object_t *rock = NULL;
  estimate_config_t cfg;
  estimate_config_default(&cfg);
  estimate_t *est = NULL;
  if (balance_world_create(&bc, &world) != BALANCE_OK ||
      balance_object_create(world, &obj.mesh, &truth, &rock) != BALANCE_OK ||
      estimate_create(&obj.mesh, bc.base_size_m, &cfg, &est) != ESTIMATE_OK)
    return fprintf(stderr, "cannot set up\n"), 1;
  estimate_trial_request_t req;
  balance_trial_result_t r;
  while (estimate_next(est, &req) == ESTIMATE_OK &&
         balance_trial_run(world, rock, &req.release, NULL, &r) == BALANCE_OK) {
    const estimate_trial_reply_t reply = {(estimate_outcome_t)r.outcome, r.released, r.settled};
    estimate_observe(est, &reply);
  }
  const estimate_result_t *e = estimate_result(est);
  for (int k = 0; k < 3; ++k)
    printf("%c %+.4f mm +- %.4f (true %+.4f)\n", "xyz"[k], 1e3 * e -> com_m[k],
           1e3 * e -> halfwidth_m[k], 1e3 * truth.com_m[k]);
  printf("%zu trials, %s\n", e->trial_count, estimate_status_str(estimate_status(est)));
  const int ok = estimate_status(est) == ESTIMATE_DONE && e->found[0] && e->found[1] && e->found[2];
  estimate_destroy(est);
  balance_world_destroy(world);
  model_object_free(&obj);
  return ok ? 0 : 1;
}
