# check_sim: integration tests of comlearn-sim. Each test starts the real daemon binary as a child
# process on an LCM URL of its own (udpm, port from the pid) and talks to it over LCM.
comlearn_add_check(check_sim SOURCES check_sim.c
  LIBS comlearn_msg comlearn_placement comlearn_model comlearn_math TIMEOUT 120)
target_compile_definitions(check_sim PRIVATE COMLEARN_SIM_EXE="$<TARGET_FILE:comlearn-sim>")
add_dependencies(check_sim comlearn-sim)
