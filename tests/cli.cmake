comlearn_add_check(check_cli SOURCES check_cli.c LIBS comlearn_msg)
target_compile_definitions(check_cli PRIVATE COMLEARN_BIN="$<TARGET_FILE:comlearn>")
add_dependencies(check_cli comlearn)
# comlearn_cli (apps/common): the programs' JSON writer and logger, as units.
comlearn_add_check(check_cli_common SOURCES check_cli_common.c LIBS comlearn_cli TIMEOUT 30)
# The command-line surface of every program and script (--version, --help without side effects,
# unknown options and missing values named): tests/cli_surface.sh.
# bench/ is configured after tests/, always with it (generator expressions resolve later).
set(comlearn_cli_programs comlearn comlearn-sim comlearn-rockgen comlearn-shapegen
    comlearn-rocks-svg comlearn-reach-svg bench_balance bench_regimes bench_qlearn bench_ik
    bench_estimate bench_stack bench_coverage placements_dump bench_hull bench_outcome bench_pivot)
set(comlearn_cli_program_files)
foreach(t IN LISTS comlearn_cli_programs)
  list(APPEND comlearn_cli_program_files $<TARGET_FILE:${t}>)
endforeach()
add_test(NAME cli_surface
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/cli_surface.sh ${PROJECT_VERSION}
                 ${PROJECT_SOURCE_DIR} ${comlearn_cli_program_files})
set_tests_properties(cli_surface PROPERTIES TIMEOUT 300)
# readme_commands: README.md's "Using it" block, read at test time and run line by line (made
# small and private where a line is slow or a daemon), each line's output checked; a line
# without a rule fails (tests/readme_commands.sh).
add_test(NAME readme_commands
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/readme_commands.sh ${PROJECT_SOURCE_DIR}
                 ${PROJECT_BINARY_DIR})
set_tests_properties(readme_commands PROPERTIES TIMEOUT 180)
# gui_wrappers: scripts/lcm-spy.sh and scripts/lcm-logplayer-gui.sh (tests/gui_wrappers.sh).
# Their checks with fake prerequisites always run; those with this machine's java (--check's
# command: main class, class path with this build's jar, URL) need a java with AWT, lcm.jar,
# jchart2d.jar and the jar, which only 'scripts/setup.sh --gui' installs: without them the
# script exits 77 and CTest reports the test skipped.
if(TARGET comlearn_lcmtypes_jar)
  get_target_property(comlearn_gui_types_jar comlearn_lcmtypes_jar JAR_FILE)
else()
  set(comlearn_gui_types_jar "")
endif()
add_test(NAME gui_wrappers
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/gui_wrappers.sh ${PROJECT_SOURCE_DIR}
                 "${comlearn_gui_types_jar}")
set_tests_properties(gui_wrappers PROPERTIES TIMEOUT 120 SKIP_RETURN_CODE 77)
