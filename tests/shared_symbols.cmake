# cmake -DNM=nm -DLIB=libcomlearn_model.so -DARCHIVE=libcomlearn_model.a -DPREFIX=model_
#       [-DSEALED=sealed/libcomlearn_model.a] -P this
# A shared library of comlearn exports its public API only (cmake/version_script.cmake): every
# defined dynamic symbol (demangled) starts with PREFIX, there is at least one, and each is also
# defined in the static library built from the same objects. Prints how many of the archive's
# global definitions the shared library keeps local. SEALED (the installed static archive of a C
# library, cmake/seal_archive.cmake): its global definitions are exactly the shared library's
# exports.
cmake_minimum_required(VERSION 3.20)
foreach(var NM LIB ARCHIVE PREFIX)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "shared_symbols.cmake: ${var} is not set")
  endif()
endforeach()

include(${CMAKE_CURRENT_LIST_DIR}/nm_lines.cmake)

# Names of the defined global symbols `nm ARGS file` lists, as a sorted CMake list.
function(defined_globals out file)
  nm_lines(lines ${file} ${ARGN})
  set(names "")
  foreach(line IN LISTS lines)
    # "address type name"; a global definition has an upper-case type (or u, i: unique, ifunc)
    if(line MATCHES "^[0-9a-fA-F]+ ([A-Zui]) (.+)$" AND NOT CMAKE_MATCH_1 STREQUAL "U")
      list(APPEND names "${CMAKE_MATCH_2}")
    endif()
  endforeach()
  list(REMOVE_DUPLICATES names)
  list(SORT names)
  set(${out} "${names}" PARENT_SCOPE)
endfunction()

defined_globals(exported ${LIB} -D -C --defined-only)
defined_globals(archived ${ARCHIVE} -g -C --defined-only)
if(NOT exported)
  message(FATAL_ERROR "${LIB} exports nothing")
endif()
set(bad "")
foreach(name IN LISTS exported)
  string(FIND "${name}" "${PREFIX}" at)
  if(NOT at EQUAL 0)
    list(APPEND bad "${name}")
  endif()
endforeach()
if(bad)
  list(JOIN bad "\n  " shown)
  message(FATAL_ERROR "${LIB} exports symbols without the prefix ${PREFIX}:\n  ${shown}")
endif()
set(hidden ${archived})
list(REMOVE_ITEM hidden ${exported})
set(stray ${exported})
list(REMOVE_ITEM stray ${archived})
if(stray)
  list(JOIN stray "\n  " shown)
  message(FATAL_ERROR "${LIB} exports symbols ${ARCHIVE} does not define:\n  ${shown}")
endif()
if(DEFINED SEALED AND NOT SEALED STREQUAL "")
  defined_globals(sealed ${SEALED} -g -C --defined-only)
  if(NOT sealed STREQUAL exported)
    list(JOIN sealed " " s1)
    list(JOIN exported " " s2)
    message(FATAL_ERROR "${SEALED} defines other globals than ${LIB} exports:\n  ${s1}\n  vs\n  ${s2}")
  endif()
  message(STATUS "${SEALED}: the same global definitions as ${LIB} exports")
endif()
list(LENGTH exported n_exported)
list(LENGTH hidden n_hidden)
message(STATUS "${LIB}: ${n_exported} exported (${PREFIX}*), ${n_hidden} global definitions of "
               "the archive kept local")
