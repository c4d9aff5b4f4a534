# check_estimate: the estimator with the direct backend, and `comlearn estimate` as a user runs it.
comlearn_add_check(check_estimate SOURCES check_estimate.c
  LIBS comlearn_estimate_direct comlearn_estimate comlearn_balance comlearn_shapegen
       comlearn_rockgen comlearn_model_sim
  TIMEOUT 600)
target_compile_definitions(check_estimate PRIVATE COMLEARN_BIN="$<TARGET_FILE:comlearn>")
target_include_directories(check_estimate PRIVATE ${PROJECT_SOURCE_DIR}/lib/estimate/src) # pivot.h
add_dependencies(check_estimate comlearn)
# All six rocks and 48 generated objects in both presets: the suite takes ~6 s in the default
# build, ~40 s under asan (-O0).
add_test(NAME estimate_no_inertial_symbols
         COMMAND ${CMAKE_COMMAND} -DNM=${CMAKE_NM} -DLIB=$<TARGET_FILE:comlearn_estimate>
                 -DANCHOR=estimate_next
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/no_inertial_symbols.cmake)
# Every bundled rock's estimate, bit for bit, against tests/data/estimate_golden.txt (written
# before the estimator moved into lib/estimate).
comlearn_add_check(check_estimate_golden SOURCES check_estimate_golden.c
  LIBS comlearn_estimate_direct comlearn_estimate comlearn_model_sim TIMEOUT 900)
add_test(NAME estimate_calls_no_physics
         COMMAND ${CMAKE_COMMAND} -DNM=${CMAKE_NM} -DLIB=$<TARGET_FILE:comlearn_estimate>
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/estimate_symbols.cmake)
# lib/estimate's own loop: next / observe, refused replies, caller memory, final failures.
comlearn_add_check(check_estimate_api SOURCES check_estimate_api.c
  LIBS comlearn_estimate_direct comlearn_estimate comlearn_model_sim)
# No allocation per trial: malloc / calloc / realloc of the project's archives counted (--wrap)
# while estimate_next / estimate_observe run.
comlearn_add_check(check_estimate_noalloc SOURCES check_estimate_noalloc.c
  LIBS comlearn_estimate_direct comlearn_estimate comlearn_model_sim)
target_link_options(check_estimate_noalloc PRIVATE
  -Wl,--wrap=malloc -Wl,--wrap=calloc -Wl,--wrap=realloc)
# `comlearn estimate --svg`: the picture parsed through the projection it publishes, against the
# --json estimate (direct and over LCM), a component not found as a band, bad paths; and
# estimate_svg_write on hand-made results (apps/comlearn/estimate_svg.c compiled in).
comlearn_add_check(check_estimate_svg
  SOURCES check_estimate_svg.c ${PROJECT_SOURCE_DIR}/apps/comlearn/estimate_svg.c
  LIBS comlearn_estimate_drive comlearn_estimate comlearn_model comlearn_cli TIMEOUT 300)
target_include_directories(check_estimate_svg PRIVATE ${PROJECT_SOURCE_DIR}/apps/comlearn)
target_compile_definitions(check_estimate_svg PRIVATE COMLEARN_BIN="$<TARGET_FILE:comlearn>"
                           COMLEARN_SHAPEGEN_BIN="$<TARGET_FILE:comlearn-shapegen>")
add_dependencies(check_estimate_svg comlearn comlearn-shapegen comlearn-sim)
