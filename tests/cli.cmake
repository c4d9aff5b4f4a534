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
    bench_estimate bench_stack bench_coverage placements_dump bench_hull bench_outcome)
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
