# Python (package comlearn, lcmtypes/CMakeLists.txt): the generated classes decode what the C
# bindings encode, the plain-Python udpm transport speaks LCM's wire format, and the example
# client examples/python/one_trial.py runs trials against the real comlearn-sim.
find_package(Python3 COMPONENTS Interpreter)
if(NOT Python3_FOUND)
  message(FATAL_ERROR "the Python tests need python3: apt-get install python3 "
                      "(scripts/setup.sh installs it)")
endif()
get_target_property(comlearn_python_path comlearn_lcmtypes_python PYTHON_PATH)
set(py_env "PYTHONPATH=${comlearn_python_path}" "PYTHONDONTWRITEBYTECODE=1")
set(py_tests ${CMAKE_CURRENT_SOURCE_DIR}/python)

set(py_fixture_dir ${CMAKE_CURRENT_BINARY_DIR}/messages-python-fixtures)
file(MAKE_DIRECTORY ${py_fixture_dir})
add_test(NAME messages_python_fixtures
  COMMAND check_messages --write-fixtures ${py_fixture_dir})
add_test(NAME python_decode
  COMMAND ${Python3_EXECUTABLE} ${py_tests}/decode_check.py ${py_fixture_dir} ${comlearn_lcm_types})
add_test(NAME python_udpm COMMAND ${Python3_EXECUTABLE} ${py_tests}/udpm_test.py)
add_test(NAME python_one_trial
  COMMAND ${Python3_EXECUTABLE} ${py_tests}/one_trial_test.py
          $<TARGET_FILE:comlearn-sim> $<TARGET_FILE:comlearn> ${COMLEARN_ASSETS_DIR})
set_tests_properties(messages_python_fixtures PROPERTIES
  TIMEOUT 60 FIXTURES_SETUP messages_python)
set_tests_properties(python_decode PROPERTIES
  TIMEOUT 60 FIXTURES_REQUIRED messages_python ENVIRONMENT "${py_env}")
set_tests_properties(python_udpm PROPERTIES TIMEOUT 60 ENVIRONMENT "${py_env}")
set_tests_properties(python_one_trial PROPERTIES TIMEOUT 120 ENVIRONMENT "${py_env}")
