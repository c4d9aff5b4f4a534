# check_experiments: the noisy direct backend (comlearn-sim's seeding, held pose reported), PBA's
# noise model in the estimator, `comlearn experiments` (JSON, table, SVG, exit codes) and Fig. 2's
# trial axis on synthetic runs.
# ~25 s under asan (-O0): two rocks x two policies x (noiseless + one seed) through the program.
comlearn_add_check(check_experiments SOURCES check_experiments.c
  LIBS comlearn_estimate_direct comlearn_estimate comlearn_experiments_svg comlearn_balance comlearn_model_sim
  TIMEOUT 900)
target_compile_definitions(check_experiments PRIVATE COMLEARN_BIN="$<TARGET_FILE:comlearn>")
add_dependencies(check_experiments comlearn comlearn-sim)
