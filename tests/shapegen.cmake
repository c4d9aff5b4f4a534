# Adversarial test objects (tools/shapegen.h, comlearn-shapegen): the acceptance rule, closed-form
# volumes and CoMs, each family's defining feature, the files and the command line.
comlearn_add_check(check_shapegen SOURCES check_shapegen.c
  LIBS comlearn_shapegen comlearn_model_sim comlearn_math TIMEOUT 600)
target_compile_definitions(check_shapegen PRIVATE
  COMLEARN_SHAPEGEN="$<TARGET_FILE:comlearn-shapegen>")
add_dependencies(check_shapegen comlearn-shapegen)
