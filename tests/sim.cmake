# check_sim: integration tests of comlearn-sim. Each test starts the real daemon binary as a child
# process on an LCM URL of its own (udpm, port from the pid) and talks to it over LCM.
comlearn_add_check(check_sim SOURCES check_sim.c
  LIBS comlearn_msg comlearn_placement comlearn_model comlearn_math TIMEOUT 120)
target_compile_definitions(check_sim PRIVATE COMLEARN_SIM_EXE="$<TARGET_FILE:comlearn-sim>")
add_dependencies(check_sim comlearn-sim)

# lan_two_namespaces: scripts/lan-check.sh, many robots across "hosts": two network namespaces
# joined by a veth pair, a comlearn-sim in each on one ttl=1 URL, each side estimating on the
# other's robot (equal to --direct), and ttl=0 not crossing. Needs root for ip netns: skipped
# (exit 77) where namespaces cannot be made.
add_test(NAME lan_two_namespaces
  COMMAND bash ${PROJECT_SOURCE_DIR}/scripts/lan-check.sh ${PROJECT_BINARY_DIR})
set_tests_properties(lan_two_namespaces PROPERTIES SKIP_RETURN_CODE 77 TIMEOUT 120)
