# cmake -DSOURCE_DIR=... -DWORK_DIR=... -DPKG_CONFIG=pkg-config -P this
# The build options a packager meets (docs/install.md), by configuring the source tree afresh:
#   1. -DBUILD_TESTING=OFF -DCMAKE_DISABLE_FIND_PACKAGE_Java=ON with a pkg-config that refuses
#      the module `check`: the configure succeeds, says why the jar is skipped, configures no
#      tests/ or bench/ and defines no comlearn_lcmtypes_jar; warnings are not errors
#      (COMLEARN_WERROR OFF: no -Werror in compile_commands.json);
#   2. the same tree with -DCOMLEARN_WERROR=ON: -Werror in compile_commands.json;
#   3. every configure preset of CMakePresets.json sets COMLEARN_WERROR ON (CI runs the presets).
cmake_minimum_required(VERSION 3.20)
foreach(var SOURCE_DIR WORK_DIR PKG_CONFIG)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "build_options.cmake: ${var} is not set")
  endif()
endforeach()

function(configure)
  execute_process(COMMAND ${CMAKE_COMMAND} -S ${SOURCE_DIR} -B ${bin} ${ARGN}
                  RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "configure ${ARGN} failed (${rc}):\n${out}\n${err}")
  endif()
  set(configure_out "${out}" PARENT_SCOPE)
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
set(bin ${WORK_DIR}/build)
set(wrapper ${WORK_DIR}/pkg-config-without-check)
file(WRITE ${wrapper} "#!/bin/sh
# pkg-config as if Debian's package `check` were not installed
for a in \"$@\"; do
  case \"$a\" in check|check[\\ \\<\\>=]*) echo \"no module check (${wrapper})\" >&2; exit 1 ;; esac
done
exec '${PKG_CONFIG}' \"$@\"
")
file(CHMOD ${wrapper} PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE)

# 1.
configure(-DCMAKE_BUILD_TYPE=Release -DBUILD_TESTING=OFF -DCMAKE_DISABLE_FIND_PACKAGE_Java=ON
          -DPKG_CONFIG_EXECUTABLE=${wrapper})
if(NOT configure_out MATCHES "comlearn_lcmtypes_jar \\(the message types for lcm-spy\\) and the Java decode test skipped")
  message(FATAL_ERROR "no STATUS message on the skipped jar:\n${configure_out}")
endif()
foreach(dir tests bench)
  if(EXISTS ${bin}/${dir})
    message(FATAL_ERROR "BUILD_TESTING=OFF configured ${dir}/")
  endif()
endforeach()
file(READ ${bin}/lcmtypes/Makefile makefile)
if(makefile MATCHES "comlearn_lcmtypes_jar")
  message(FATAL_ERROR "comlearn_lcmtypes_jar defined without Java")
endif()
file(READ ${bin}/CMakeCache.txt cache)
if(NOT cache MATCHES "\nCOMLEARN_WERROR:BOOL=OFF\n")
  message(FATAL_ERROR "COMLEARN_WERROR is not OFF by default")
endif()
file(READ ${bin}/compile_commands.json commands)
if(commands MATCHES "-Werror")
  message(FATAL_ERROR "-Werror without COMLEARN_WERROR")
endif()
if(NOT commands MATCHES "-Wconversion")
  message(FATAL_ERROR "no strict warnings in compile_commands.json")
endif()

# 2.
configure(-DCOMLEARN_WERROR=ON)
file(READ ${bin}/compile_commands.json commands)
if(NOT commands MATCHES "-Werror")
  message(FATAL_ERROR "COMLEARN_WERROR=ON gives no -Werror")
endif()

# 3.
file(READ ${SOURCE_DIR}/CMakePresets.json presets)
string(JSON n LENGTH "${presets}" configurePresets)
math(EXPR last "${n} - 1")
foreach(i RANGE ${last})
  string(JSON name GET "${presets}" configurePresets ${i} name)
  string(JSON werror ERROR_VARIABLE missing GET "${presets}" configurePresets ${i} cacheVariables
         COMLEARN_WERROR)
  if(NOT werror STREQUAL "ON")
    message(FATAL_ERROR "configure preset ${name} does not set COMLEARN_WERROR ON")
  endif()
endforeach()
message(STATUS "BUILD_TESTING=OFF without check, Java off, COMLEARN_WERROR OFF by default and ON "
               "in ${n} presets")
