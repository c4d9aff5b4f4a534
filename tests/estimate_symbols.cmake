# cmake -DNM=nm -DLIB=libcomlearn_estimate.a -P this
# lib/estimate is geometry and learning only: every symbol its archive needs from elsewhere is
# its own (estimate_*: one member calling another), lib/model's (model_*), lib/qlearn's
# (qlearn_*), the C library's or libm's from the short list
# below, or the compiler's and sanitizers' own (__*, and _GLOBAL_OFFSET_TABLE_, which the linker
# defines: position-independent code for the shared library references it). So it calls no
# physics engine (ODE's d*, lib/balance's balance_*), no LCM, no file or stream I/O (fopen,
# printf, ...).
cmake_minimum_required(VERSION 3.20)
include(${CMAKE_CURRENT_LIST_DIR}/nm_lines.cmake)
nm_lines(lines ${LIB} -u)
set(libc acos asin atan atan2 ceil cos erfc exp fabs floor fmax fmin hypot log pow sin sincos sqrt tan
    free malloc calloc memcmp memcpy memmove memset qsort snprintf strcmp strlen strncmp)
set(bad "")
set(count 0)
foreach(line IN LISTS lines)
  if(NOT line MATCHES "^ *U +([^ ]+)")
    continue() # member headers ("x.o:") and blank lines
  endif()
  set(sym "${CMAKE_MATCH_1}")
  math(EXPR count "${count} + 1")
  if(sym MATCHES "^(estimate_|model_|qlearn_|__)" OR sym STREQUAL "_GLOBAL_OFFSET_TABLE_")
    continue()
  endif()
  list(FIND libc "${sym}" at)
  if(at LESS 0)
    list(APPEND bad "${sym}")
  endif()
endforeach()
if(count EQUAL 0)
  message(FATAL_ERROR "${LIB} needs no symbol at all: wrong archive?")
endif()
if(bad)
  message(FATAL_ERROR "${LIB} calls outside lib/model, lib/qlearn and the allowed C library: ${bad}")
endif()
message(STATUS "${LIB}: ${count} undefined symbols, all lib/model, lib/qlearn or libc/libm")
