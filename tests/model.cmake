# lib/model: one Check runner for every suite, plus a symbol check of the estimator/simulator
# boundary.
comlearn_add_check(check_model
  SOURCES check_model.c model_mesh_tests.c model_massprop_tests.c model_hull_tests.c
          model_urdf_tests.c model_outcome_tests.c
  LIBS comlearn_model_sim comlearn_math)
# model_hull_tests.c tests the hull's exact predicate (lib/model/src/orient.h) directly.
target_include_directories(check_model PRIVATE ${PROJECT_SOURCE_DIR}/lib/model/src)

# comlearn_model (what the estimator links) must hold no code that reads <inertial>: no symbol
# whose demangled name mentions "inertial", defined or referenced. The same scan must find the
# inertial reader in comlearn_model_sim, which proves the scan works; and the two archives must
# not define the same strong symbol (urdf.cpp is compiled into both).
add_test(NAME model_estimator_lib_has_no_inertial
  COMMAND ${CMAKE_COMMAND}
          -DNM=${CMAKE_NM}
          -DESTIMATOR_LIB=$<TARGET_FILE:comlearn_model>
          -DSIM_LIB=$<TARGET_FILE:comlearn_model_sim>
          -P ${CMAKE_CURRENT_SOURCE_DIR}/model_symbols.cmake)
set_tests_properties(model_estimator_lib_has_no_inertial PROPERTIES TIMEOUT 60)

# The outcome model (comlearn/model_outcome.h) allocates nothing with a work area: malloc, calloc
# and realloc wrapped and counted while it runs.
comlearn_add_check(check_model_noalloc SOURCES check_model_noalloc.c LIBS comlearn_model comlearn_math)
target_link_options(check_model_noalloc PRIVATE
  -Wl,--wrap=malloc -Wl,--wrap=calloc -Wl,--wrap=realloc)
