# comlearn's libraries and how they install: one call per library, one for the package.
#
# comlearn_add_library(NAME
#   SOURCES src...              compiled once, as position-independent objects
#   HEADERS h...                public headers: installed into include/comlearn, and the functions
#                               they declare (with PREFIX) are what the shared library exports
#   PREFIX p                    public prefix of every exported function ("model_")
#   [INCLUDE_DIR dir]           public include folder in the build tree (default: include)
#   [GENERATED]                 generated sources: SYSTEM include folder, no strict warnings
#   [PUBLIC libs...]            dependencies of the API (comlearn_* ones: the shared library
#                               links their shared twins)
#   [PRIVATE libs...]           dependencies of the implementation
#   [DEFINITIONS defs...]       private compile definitions
#   [INTERNAL_EXPORTS pats...]  also exported though not in HEADERS: internals that another
#                               comlearn shared library calls (version-script patterns)
#   [PC_REQUIRES mods...]       pkg-config Requires (besides the comlearn-* of PUBLIC)
#   [PC_REQUIRES_PRIVATE mods...] [PC_LIBS_PRIVATE flags...]
#   [DESCRIPTION text])
# makes
#   comlearn_NAME_objects  the OBJECT library (strict warnings unless GENERATED)
#   comlearn_NAME          STATIC, what the programs and tests in this tree link (comlearn::NAME_static)
#   comlearn_NAME_shared   SHARED libcomlearn_NAME.so.VERSION, SONAME libcomlearn_NAME.so.MAJOR,
#                          RUNPATH $ORIGIN when installed;
#                          a version script generated from HEADERS (cmake/version_script.cmake)
#                          keeps every other symbol local (comlearn::NAME)
# and installs both, the headers and comlearn-NAME.pc. Targets join the export set
# comlearnTargets that comlearn_install_package() writes. The installed static archive of a C
# library (no C++, not GENERATED, no INTERNAL_EXPORTS) is sealed (cmake/seal_archive.cmake): one
# relocatable object whose only global symbols are the shared library's exports; the in-tree
# archive, which tests of internals link, stays as compiled.
include_guard(GLOBAL)
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(COMLEARN_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/comlearn)
set(COMLEARN_INSTALL_PKGCONFIGDIR ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
set(COMLEARN_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/comlearn)
set_property(GLOBAL PROPERTY COMLEARN_LIBRARIES "")
set_property(GLOBAL PROPERTY COMLEARN_HEADER_LIBRARIES "")

# Consumers of an install built with sanitizers need the sanitizer runtime at link time.
set(comlearn_consumer_link_options "")
if(COMLEARN_SANITIZE)
  set(comlearn_consumer_link_options -fsanitize=address,undefined)
endif()

# The shared twin of each compiled comlearn_* dependency among the arguments; others
# (comlearn_math, the header-only one, and third-party targets) as given.
function(comlearn_shared_twins out)
  set(deps "")
  foreach(dep IN LISTS ARGN)
    if(TARGET ${dep}_shared)
      list(APPEND deps ${dep}_shared)
    else()
      list(APPEND deps ${dep})
    endif()
  endforeach()
  set(${out} "${deps}" PARENT_SCOPE)
endfunction()

function(comlearn_add_library name)
  cmake_parse_arguments(A "GENERATED" "PREFIX;INCLUDE_DIR;DESCRIPTION"
    "SOURCES;HEADERS;PUBLIC;PRIVATE;DEFINITIONS;INTERNAL_EXPORTS;PC_REQUIRES;PC_REQUIRES_PRIVATE;PC_LIBS_PRIVATE"
    ${ARGN})
  foreach(arg SOURCES HEADERS PREFIX)
    if(NOT A_${arg})
      message(FATAL_ERROR "comlearn_add_library(${name}): ${arg} is required")
    endif()
  endforeach()
  if(NOT A_INCLUDE_DIR)
    set(A_INCLUDE_DIR include)
  endif()
  get_filename_component(include_dir ${A_INCLUDE_DIR} ABSOLUTE)
  list(TRANSFORM A_HEADERS PREPEND ${CMAKE_CURRENT_SOURCE_DIR}/ REGEX "^[^/]")
  set(lib comlearn_${name})
  set(system "")
  if(A_GENERATED)
    set(system SYSTEM)
  endif()

  comlearn_shared_twins(public_shared ${A_PUBLIC})
  comlearn_shared_twins(private_shared ${A_PRIVATE})

  add_library(${lib}_objects OBJECT ${A_SOURCES} ${A_HEADERS})
  set_target_properties(${lib}_objects PROPERTIES POSITION_INDEPENDENT_CODE ON)
  target_include_directories(${lib}_objects ${system} PUBLIC ${include_dir})
  if(IS_DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/src)
    target_include_directories(${lib}_objects PRIVATE ${CMAKE_CURRENT_SOURCE_DIR}/src)
  endif()
  target_compile_definitions(${lib}_objects PRIVATE ${A_DEFINITIONS})
  target_link_libraries(${lib}_objects PRIVATE ${A_PUBLIC} ${A_PRIVATE})
  if(NOT A_GENERATED)
    comlearn_strict(${lib}_objects)
  endif()

  add_library(${lib} STATIC $<TARGET_OBJECTS:${lib}_objects>)
  add_library(${lib}_shared SHARED $<TARGET_OBJECTS:${lib}_objects>)
  foreach(t ${lib} ${lib}_shared)
    target_include_directories(${t} ${system} PUBLIC
      $<BUILD_INTERFACE:${include_dir}> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
    target_link_options(${t} INTERFACE $<INSTALL_INTERFACE:${comlearn_consumer_link_options}>)
  endforeach()
  target_link_libraries(${lib} PUBLIC ${A_PUBLIC} PRIVATE ${A_PRIVATE})
  target_link_libraries(${lib}_shared PUBLIC ${public_shared} PRIVATE ${private_shared})

  set(map ${CMAKE_CURRENT_BINARY_DIR}/${lib}.map)
  add_custom_command(
    OUTPUT ${map}
    COMMAND ${CMAKE_COMMAND} -DPREFIX=${A_PREFIX} -DOUT=${map} "-DHEADERS=${A_HEADERS}"
            "-DEXTRA=${A_INTERNAL_EXPORTS}"
            -P ${PROJECT_SOURCE_DIR}/cmake/version_script.cmake
    DEPENDS ${A_HEADERS} ${PROJECT_SOURCE_DIR}/cmake/version_script.cmake
    COMMENT "version script ${lib}.map (exports ${A_PREFIX}* of the public headers)"
    VERBATIM)
  add_custom_target(${lib}_map DEPENDS ${map})
  add_dependencies(${lib}_shared ${lib}_map)
  target_link_options(${lib}_shared PRIVATE -Wl,--version-script=${map} -Wl,--no-undefined)
  set_target_properties(${lib}_shared PROPERTIES
    OUTPUT_NAME ${lib} EXPORT_NAME ${name}
    VERSION ${PROJECT_VERSION} SOVERSION ${PROJECT_VERSION_MAJOR}
    LINK_DEPENDS ${map} COMLEARN_PREFIX ${A_PREFIX}
    # installed, each finds the comlearn libraries it needs beside itself, wherever the prefix is
    INSTALL_RPATH "$ORIGIN")
  set_target_properties(${lib} PROPERTIES EXPORT_NAME ${name}_static)
  set_property(GLOBAL APPEND PROPERTY COMLEARN_LIBRARIES ${name})

  install(TARGETS ${lib} ${lib}_shared EXPORT comlearnTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
    RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  set(has_cxx 0)
  foreach(src IN LISTS A_SOURCES)
    if(src MATCHES "\\.(cpp|cc|cxx)$")
      set(has_cxx 1)
    endif()
  endforeach()
  if(NOT A_GENERATED AND NOT A_INTERNAL_EXPORTS AND NOT has_cxx)
    set(sealed ${CMAKE_CURRENT_BINARY_DIR}/sealed/lib${lib}.a)
    add_custom_command(
      OUTPUT ${sealed}
      COMMAND ${CMAKE_COMMAND} -DMAP=${map} "-DOBJECTS=$<JOIN:$<TARGET_OBJECTS:${lib}_objects>,|>"
              -DOUT=${sealed} -DLD=${CMAKE_LINKER} -DOBJCOPY=${CMAKE_OBJCOPY} -DAR=${CMAKE_AR}
              -P ${PROJECT_SOURCE_DIR}/cmake/seal_archive.cmake
      DEPENDS ${map} $<TARGET_OBJECTS:${lib}_objects> ${PROJECT_SOURCE_DIR}/cmake/seal_archive.cmake
      COMMENT "sealed archive lib${lib}.a (only the ${A_PREFIX}* exports global)"
      VERBATIM)
    add_custom_target(${lib}_sealed ALL DEPENDS ${sealed})
    # the objects are another target's outputs: build that target first
    add_dependencies(${lib}_sealed ${lib}_objects ${lib}_map)
    set_target_properties(${lib} PROPERTIES COMLEARN_SEALED ${sealed})
    # after install(TARGETS): the sealed archive replaces the in-tree one in the prefix
    install(FILES ${sealed} DESTINATION ${CMAKE_INSTALL_LIBDIR})
  endif()
  install(FILES ${A_HEADERS} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/comlearn)

  comlearn_pc_modules(requires ${A_PUBLIC})
  comlearn_pc_modules(requires_private ${A_PRIVATE})
  set(libs "-L\${libdir}" "-l${lib}" ${comlearn_consumer_link_options})
  comlearn_write_pc(${name} "${A_DESCRIPTION}" "${libs}" "${requires};${A_PC_REQUIRES}"
                    "${requires_private};${A_PC_REQUIRES_PRIVATE}" "${A_PC_LIBS_PRIVATE}")
endfunction()

# comlearn_add_header_library(NAME HEADERS h... [PUBLIC libs...] [PC_LIBS flags...]
#                             [DESCRIPTION text])
# A header-only library (static inline code): the INTERFACE target comlearn_NAME with the public
# include folder include/, installed with its headers, exported as comlearn::NAME, and a
# comlearn-NAME.pc (Cflags, and PC_LIBS as Libs).
function(comlearn_add_header_library name)
  cmake_parse_arguments(A "" "DESCRIPTION" "HEADERS;PUBLIC;PC_LIBS" ${ARGN})
  if(NOT A_HEADERS)
    message(FATAL_ERROR "comlearn_add_header_library(${name}): HEADERS is required")
  endif()
  set(lib comlearn_${name})
  add_library(${lib} INTERFACE)
  target_include_directories(${lib} INTERFACE
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${lib} INTERFACE ${A_PUBLIC})
  set_target_properties(${lib} PROPERTIES EXPORT_NAME ${name})
  set_property(GLOBAL APPEND PROPERTY COMLEARN_HEADER_LIBRARIES ${name})
  install(TARGETS ${lib} EXPORT comlearnTargets)
  install(FILES ${A_HEADERS} DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/comlearn)
  comlearn_write_pc(${name} "${A_DESCRIPTION}" "${A_PC_LIBS}" "" "" "")
endfunction()

# The pkg-config modules of the comlearn_* libraries among the arguments: comlearn_model_sim is
# comlearn-model-sim. Others (third-party targets, m) have their PC_REQUIRES* spelled out.
function(comlearn_pc_modules out)
  set(modules "")
  foreach(dep IN LISTS ARGN)
    if(TARGET ${dep} AND dep MATCHES "^comlearn_(.+)$")
      string(REPLACE "_" "-" module "comlearn-${CMAKE_MATCH_1}")
      list(APPEND modules ${module})
    endif()
  endforeach()
  set(${out} "${modules}" PARENT_SCOPE)
endfunction()

# comlearn-NAME.pc, relocatable (the prefix from the .pc file's own folder), so `cmake --install
# --prefix` anywhere gives a working file; installed into lib/pkgconfig.
function(comlearn_write_pc name description libs requires requires_private libs_private)
  file(RELATIVE_PATH pc_to_prefix ${CMAKE_INSTALL_PREFIX}/${COMLEARN_INSTALL_PKGCONFIGDIR}
       ${CMAKE_INSTALL_PREFIX})
  string(REGEX REPLACE "/$" "" pc_to_prefix "${pc_to_prefix}")
  set(PC_PREFIX "\${pcfiledir}/${pc_to_prefix}")
  string(REPLACE "_" "-" PC_NAME "comlearn-${name}")
  set(PC_DESCRIPTION "${description}")
  foreach(field libs requires requires_private libs_private)
    list(REMOVE_ITEM ${field} "")
    string(TOUPPER "PC_${field}" var)
    list(JOIN ${field} " " ${var})
  endforeach()
  configure_file(${PROJECT_SOURCE_DIR}/cmake/comlearn-lib.pc.in
                 ${CMAKE_CURRENT_BINARY_DIR}/${PC_NAME}.pc @ONLY)
  install(FILES ${CMAKE_CURRENT_BINARY_DIR}/${PC_NAME}.pc
          DESTINATION ${COMLEARN_INSTALL_PKGCONFIGDIR})
endfunction()

# The CMake package: comlearnTargets.cmake (namespace comlearn::), comlearnConfig.cmake (finds the
# dependencies, then includes the targets; sets comlearn_DATA_DIR) and comlearnConfigVersion.cmake
# (SameMajorVersion).
function(comlearn_install_package)
  install(EXPORT comlearnTargets NAMESPACE comlearn:: DESTINATION ${COMLEARN_INSTALL_CMAKEDIR})
  get_property(COMLEARN_LIBRARIES GLOBAL PROPERTY COMLEARN_LIBRARIES)
  get_property(COMLEARN_HEADER_LIBRARIES GLOBAL PROPERTY COMLEARN_HEADER_LIBRARIES)
  configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/comlearnConfig.cmake.in
    ${PROJECT_BINARY_DIR}/comlearnConfig.cmake INSTALL_DESTINATION ${COMLEARN_INSTALL_CMAKEDIR}
    PATH_VARS COMLEARN_INSTALL_DATADIR)
  write_basic_package_version_file(${PROJECT_BINARY_DIR}/comlearnConfigVersion.cmake
    VERSION ${PROJECT_VERSION} COMPATIBILITY SameMajorVersion)
  install(FILES ${PROJECT_BINARY_DIR}/comlearnConfig.cmake
                ${PROJECT_BINARY_DIR}/comlearnConfigVersion.cmake
          DESTINATION ${COMLEARN_INSTALL_CMAKEDIR})
endfunction()
