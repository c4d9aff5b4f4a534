# check_experiments: the noisy direct backend (comlearn-sim's seeding, held pose reported), PBA's
# noise model in the estimator, and `comlearn experiments` (JSON, table, SVG, exit codes).
# ~25 s under asan (-O0): two rocks x two policies x (noiseless + one seed) through the program.
comlearn_add_check(check_experiments SOURCES check_experiments.c
  LIBS comlearn_estimate_direct comlearn_estimate comlearn_balance comlearn_model_sim
  TIMEOUT 900)
target_compile_definitions(check_experiments PRIVATE COMLEARN_BIN="$<TARGET_FILE:comlearn>")
add_dependencies(check_experiments comlearn comlearn-sim)
