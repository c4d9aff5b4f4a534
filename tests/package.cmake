# Packaging: a packager's configure, the shared libraries' exports, the install (docs/install.md,
# cmake/ComlearnLibrary.cmake).
# build_options: a packager's configure: BUILD_TESTING=OFF needs no `check`, no JDK skips the jar
# with a message, -Werror only with COMLEARN_WERROR (ON in the presets) (tests/build_options.cmake).
add_test(NAME build_options
         COMMAND ${CMAKE_COMMAND} -DSOURCE_DIR=${PROJECT_SOURCE_DIR}
                 -DWORK_DIR=${CMAKE_CURRENT_BINARY_DIR}/build-options
                 -DPKG_CONFIG=${PKG_CONFIG_EXECUTABLE}
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/build_options.cmake)
set_tests_properties(build_options PROPERTIES TIMEOUT 300)

# package_symbols_NAME: the shared library of each installed library exports its public prefix
# only, and a sealed static archive defines exactly those globals (tests/shared_symbols.cmake).
get_property(comlearn_libraries GLOBAL PROPERTY COMLEARN_LIBRARIES)
foreach(name IN LISTS comlearn_libraries)
  get_target_property(prefix comlearn_${name}_shared COMLEARN_PREFIX)
  add_test(NAME package_symbols_${name}
           COMMAND ${CMAKE_COMMAND} -DNM=${CMAKE_NM} -DLIB=$<TARGET_FILE:comlearn_${name}_shared>
                   -DARCHIVE=$<TARGET_FILE:comlearn_${name}> -DPREFIX=${prefix}
                   "-DSEALED=$<TARGET_PROPERTY:comlearn_${name},COMLEARN_SEALED>"
                   -P ${CMAKE_CURRENT_SOURCE_DIR}/shared_symbols.cmake)
  set_tests_properties(package_symbols_${name} PROPERTIES TIMEOUT 60)
endforeach()

# package_install: `cmake --install` of this build into a prefix under the build folder, then
# examples/ against it with find_package and with pkg-config (tests/install.cmake).
add_test(NAME package_install
         COMMAND ${CMAKE_COMMAND} -DBUILD_DIR=${PROJECT_BINARY_DIR}
                 -DSOURCE_DIR=${PROJECT_SOURCE_DIR}
                 -DWORK_DIR=${CMAKE_CURRENT_BINARY_DIR}/package-install
                 -DLIBDIR=${CMAKE_INSTALL_LIBDIR}
                 -DCC=${CMAKE_C_COMPILER} -DCXX=${CMAKE_CXX_COMPILER}
                 -DGENERATOR=${CMAKE_GENERATOR} -DPKG_CONFIG=${PKG_CONFIG_EXECUTABLE}
                 "-DLCM_URL=udpm://239.255.76.67:7690?ttl=0"
                 -DPYTHON=${Python3_EXECUTABLE} -DPYTHON_DIR=${COMLEARN_PYTHON_DIR}
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/install.cmake)
set_tests_properties(package_install PROPERTIES TIMEOUT 300)
