# `comlearn stack`: planner, simulation, CLI (tests/check_stack.c).
comlearn_add_check(check_stack SOURCES check_stack.c
  LIBS comlearn_stack_sim comlearn_stack comlearn_balance comlearn_model_sim comlearn_model
       comlearn_math
  TIMEOUT 600)
target_compile_definitions(check_stack PRIVATE COMLEARN_BIN="$<TARGET_FILE:comlearn>"
  COMLEARN_ROCKGEN="$<TARGET_FILE:comlearn-rockgen>")
# The rocks stand the full 5 s in the normal build; the sanitizer build (-O0, ~10x slower
# contacts) simulates 1 s of it to keep the suite within its budget.
if(COMLEARN_SANITIZE)
  target_compile_definitions(check_stack PRIVATE STACK_TEST_ROCK_SECONDS="1")
endif()
add_dependencies(check_stack comlearn comlearn-rockgen)
# The planner side (planner and rehearsal) must not reference the URDF inertial, like the
# estimator: no symbol naming "inertial" in the comlearn_stack archive.
add_test(NAME stack_no_inertial_symbols
         COMMAND ${CMAKE_COMMAND} -DNM=${CMAKE_NM} -DLIB=$<TARGET_FILE:comlearn_stack>
                 -DANCHOR=stack_plan
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/no_inertial_symbols.cmake)
# The control: the simulator side reads the inertial, so the same check must fail on it.
add_test(NAME no_inertial_symbols_control
         COMMAND ${CMAKE_COMMAND} -DNM=${CMAKE_NM} -DLIB=$<TARGET_FILE:comlearn_stack_sim>
                 -DANCHOR=stack_simulate
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/no_inertial_symbols.cmake)
set_tests_properties(no_inertial_symbols_control PROPERTIES WILL_FAIL TRUE)
