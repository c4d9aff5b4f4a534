# Packaging: what a packager's configure gets.
# build_options: a packager's configure: BUILD_TESTING=OFF needs no `check`, no JDK skips the jar
# with a message, -Werror only with COMLEARN_WERROR (ON in the presets) (tests/build_options.cmake).
add_test(NAME build_options
         COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${PROJECT_SOURCE_DIR}
                 -DWORK_DIR=${CMAKE_CURRENT_BINARY_DIR}/build-options
                 -DPKG_CONFIG=${PKG_CONFIG_EXECUTABLE}
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/build_options.cmake)
set_tests_properties(build_options PROPERTIES TIMEOUT 300)
