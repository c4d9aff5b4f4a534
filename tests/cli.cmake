comlearn_add_check(check_cli SOURCES check_cli.c LIBS comlearn_msg)
target_compile_definitions(check_cli PRIVATE COMLEARN_BIN="$<TARGET_FILE:comlearn>")
add_dependencies(check_cli comlearn)
# comlearn_cli (apps/common): the programs' JSON writer and logger, as units.
comlearn_add_check(check_cli_common SOURCES check_cli_common.c LIBS comlearn_cli TIMEOUT 30)
