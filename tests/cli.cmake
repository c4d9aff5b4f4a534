comlearn_add_check(check_cli SOURCES check_cli.c)
target_compile_definitions(check_cli PRIVATE COMLEARN_BIN="$<TARGET_FILE:comlearn>")
add_dependencies(check_cli comlearn)
