# cmake -DNM=nm -DLIB=libcomlearn_stack.a -P this
# The stack planner must not reference the URDF inertial: no symbol (defined or undefined) naming
# "inertial" or the two-material mass routine of comlearn_model_sim.
cmake_minimum_required(VERSION 3.20)
execute_process(COMMAND ${NM} -C ${LIB} OUTPUT_VARIABLE text RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "${NM} ${LIB} failed (${rc})")
endif()
string(TOLOWER "${text}" lower)
if(lower MATCHES "inertial" OR lower MATCHES "mass_halfspace")
  message(FATAL_ERROR "the stack planner library references the inertial truth:\n${text}")
endif()
if(NOT lower MATCHES "stack_plan")
  message(FATAL_ERROR "stack_plan not found in ${LIB}: wrong archive?")
endif()
message(STATUS "stack planner library holds no inertial symbol")
