# cmake -DNM=nm -DLIB=libcomlearn_estimate.a -DANCHOR=estimate_run -P this
# A library of the estimator's side (the estimator, the stack planner) must not reference the URDF
# inertial: no symbol (defined or undefined) naming "inertial" or the two-material mass routine
# of comlearn_model_sim. ANCHOR: a symbol the archive must hold (so that a wrong or empty archive
# does not pass).
cmake_minimum_required(VERSION 3.20)
execute_process(COMMAND ${NM} -C ${LIB} OUTPUT_VARIABLE text RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${NM} ${LIB} failed (${rc})")
endif()
string(TOLOWER "${text}" lower)
if(lower MATCHES "inertial" OR lower MATCHES "mass_halfspace")
  message(FATAL_ERROR "${LIB} references the inertial truth:\n${text}")
endif()
if(NOT lower MATCHES "${ANCHOR}")
  message(FATAL_ERROR "${ANCHOR} not found in ${LIB}: wrong archive?")
endif()
message(STATUS "${LIB} holds no inertial symbol")
