# check_estimate_lcm: whole estimates over LCM against the real comlearn-sim (a udpm URL of its
# own per test), compared with the truth and with --direct trial by trial; and
# `comlearn estimate --spawn-sim` as a user runs it.
comlearn_add_check(check_estimate_lcm SOURCES check_estimate_lcm.c
  LIBS comlearn_estimate_lcm comlearn_estimate_direct comlearn_estimate comlearn_balance
       comlearn_shapegen comlearn_rockgen comlearn_model_sim comlearn_model
  TIMEOUT 300)
target_compile_definitions(check_estimate_lcm PRIVATE
  COMLEARN_SIM_EXE="$<TARGET_FILE:comlearn-sim>" COMLEARN_BIN="$<TARGET_FILE:comlearn>")
add_dependencies(check_estimate_lcm comlearn comlearn-sim)

# check_estimate_faults: the two-material box over LCM under faults (20 % drops both ways, the
# daemon SIGKILLed and restarted mid-estimate, garbage on the subscribed channels), each equal to
# --direct trial by trial (docs/estimate.md, "Faults").
find_package(Threads REQUIRED)
comlearn_add_check(check_estimate_faults SOURCES check_estimate_faults.c
  LIBS comlearn_estimate_lcm comlearn_estimate_direct comlearn_estimate comlearn_balance
       comlearn_model_sim comlearn_model Threads::Threads
  TIMEOUT 300)
target_compile_definitions(check_estimate_faults PRIVATE COMLEARN_SIM_EXE="$<TARGET_FILE:comlearn-sim>")
add_dependencies(check_estimate_faults comlearn-sim)
