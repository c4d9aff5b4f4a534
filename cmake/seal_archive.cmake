# cmake -DMAP=lib.map -DOBJECTS=a.o|b.o -DOUT=libx.a -DLD=ld -DOBJCOPY=objcopy -DAR=ar -P this
# The installed static archive of a C library: its objects linked into one relocatable object
# (ld -r), in which every global symbol but the exported ones (the "global:" names of its version
# script MAP, cmake/version_script.cmake) is made local (objcopy --keep-global-symbols), so the
# library's internals do not leak into a program that links the archive, as its shared library's
# do not. The in-tree archive (tests call internals) stays as compiled.
cmake_minimum_required(VERSION 3.20)
foreach(var MAP OBJECTS OUT LD OBJCOPY AR)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "seal_archive.cmake: ${var} is not set")
  endif()
endforeach()
file(READ ${MAP} map)
string(REGEX MATCH "global:(.*)local:" block "${map}")
string(REGEX MATCHALL "[A-Za-z_][A-Za-z0-9_]*" names "${CMAKE_MATCH_1}")
string(REPLACE "|" ";" OBJECTS "${OBJECTS}")
list(LENGTH names n)
if(n EQUAL 0)
  message(FATAL_ERROR "seal_archive.cmake: no exported name in ${MAP}")
endif()
get_filename_component(dir ${OUT} DIRECTORY)
get_filename_component(base ${OUT} NAME_WE)
file(MAKE_DIRECTORY ${dir})
set(keep ${dir}/${base}.keep)
set(obj ${dir}/${base}.o)
list(JOIN names "\n" text)
file(WRITE ${keep} "${text}\n")
file(REMOVE ${OUT} ${obj})
foreach(step "${LD};-r;-o;${obj};${OBJECTS}" "${OBJCOPY};--keep-global-symbols=${keep};${obj}"
        "${AR};rcs;${OUT};${obj}")
  execute_process(COMMAND ${step} RESULT_VARIABLE rc ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "seal_archive.cmake: ${step}: ${err}")
  endif()
endforeach()
