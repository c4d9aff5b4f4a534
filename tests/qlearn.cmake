# lib/qlearn: one Check runner for every suite, plus the proofs of embedded style.
comlearn_add_check(check_qlearn
  SOURCES check_qlearn.c qlearn_learner_tests.c qlearn_paper_tests.c qlearn_search_tests.c
          qlearn_solve_tests.c
  LIBS comlearn_qlearn comlearn_math)

# No allocator in the archive: nm finds no malloc, calloc, realloc or free (referenced or
# defined). The same script must find malloc in a control archive that calls it (first test) and
# must fail when pointed at that archive as the library (second test, WILL_FAIL): the scan can
# fail.
add_library(alloc_scan_control STATIC alloc_scan_control.c)
comlearn_strict(alloc_scan_control)
add_test(NAME qlearn_lib_has_no_allocator
  COMMAND ${CMAKE_COMMAND} -DNM=${CMAKE_NM}
          -DLIB=$<TARGET_FILE:comlearn_qlearn>
          -DCONTROL=$<TARGET_FILE:alloc_scan_control>
          -P ${CMAKE_CURRENT_SOURCE_DIR}/qlearn_alloc_symbols.cmake)
add_test(NAME qlearn_alloc_scan_can_fail
  COMMAND ${CMAKE_COMMAND} -DNM=${CMAKE_NM}
          -DLIB=$<TARGET_FILE:alloc_scan_control>
          -P ${CMAKE_CURRENT_SOURCE_DIR}/qlearn_alloc_symbols.cmake)
set_tests_properties(qlearn_lib_has_no_allocator qlearn_alloc_scan_can_fail
  PROPERTIES TIMEOUT 60)
set_tests_properties(qlearn_alloc_scan_can_fail PROPERTIES WILL_FAIL TRUE)

# A whole estimate (four policies x three components, then a 3-D solve) allocates nothing: the
# allocator is wrapped (--wrap) and counted; also prints the state sizes, 16 KiB enforced.
add_executable(qlearn_noalloc qlearn_noalloc.c)
comlearn_strict(qlearn_noalloc)
target_link_libraries(qlearn_noalloc PRIVATE comlearn_qlearn m)
target_link_options(qlearn_noalloc PRIVATE
  "LINKER:--wrap=malloc,--wrap=calloc,--wrap=realloc,--wrap=free")
add_test(NAME qlearn_noalloc COMMAND qlearn_noalloc)
set_tests_properties(qlearn_noalloc PROPERTIES TIMEOUT 120)
