# The tree passes its .clang-format: every C / C++ source and header of the project (not the
# LCM-generated code, which lives in the build tree). clang-format comes from Debian
# (scripts/setup.sh installs it); configuring the tests without it is an error, not a skip.
find_program(CLANG_FORMAT NAMES clang-format clang-format-14)
if(NOT CLANG_FORMAT)
  message(FATAL_ERROR "clang-format not found: install Debian package clang-format "
                      "(scripts/setup.sh does), or configure with -DBUILD_TESTING=OFF")
endif()
add_test(NAME source_format
         COMMAND ${CMAKE_COMMAND} -DCLANG_FORMAT=${CLANG_FORMAT} -DROOT=${PROJECT_SOURCE_DIR}
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/format_check.cmake)
# The check can fail: a badly formatted fixture is refused.
add_test(NAME source_format_control
         COMMAND ${CMAKE_COMMAND} -DCLANG_FORMAT=${CLANG_FORMAT} -DROOT=${PROJECT_SOURCE_DIR}
                 -DFILES=${CMAKE_CURRENT_SOURCE_DIR}/data/format_bad.c
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/format_check.cmake)
set_tests_properties(source_format_control PROPERTIES
  PASS_REGULAR_EXPRESSION "not formatted \\(run: clang-format -i FILE\\):[ \n]*tests/data/format_bad\\.c")
