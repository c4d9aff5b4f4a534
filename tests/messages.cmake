# Messages (lcmtypes/): the Check suite, and the cross-check that the Java classes lcm-spy uses
# decode what the C bindings encode.
comlearn_add_check(check_messages
  SOURCES check_messages.c
  LIBS comlearn_msg comlearn_math
  TIMEOUT 120)
# The types lcmtypes/ builds: check_messages and DecodeCheck fail when a type has no fixture.
get_target_property(comlearn_lcm_types comlearn_lcmtypes COMLEARN_LCM_TYPES)
list(JOIN comlearn_lcm_types "," comlearn_lcm_types_csv)
target_compile_definitions(check_messages PRIVATE
  COMLEARN_LCM_TYPE_NAMES="${comlearn_lcm_types_csv}")

# tests/java/DecodeCheck.java, compiled at build time against lcm.jar and the types' jar: only
# when lcmtypes/ builds the jar (a JDK and lcm.jar were found).
if(NOT TARGET comlearn_lcmtypes_jar)
  message(STATUS "messages_java_decode not registered: no jar of the types (see lcmtypes' STATUS "
    "line above; 'bash scripts/setup.sh --gui' installs a JDK and liblcm-java)")
  return()
endif()
get_target_property(comlearn_lcmtypes_jar_file comlearn_lcmtypes_jar JAR_FILE)
set(decode_check_src ${CMAKE_CURRENT_SOURCE_DIR}/java/DecodeCheck.java)
set(decode_check_dir ${CMAKE_CURRENT_BINARY_DIR}/java-classes)
set(decode_check_class ${decode_check_dir}/DecodeCheck.class)
add_custom_command(
  OUTPUT ${decode_check_class}
  COMMAND ${CMAKE_COMMAND} -E make_directory ${decode_check_dir}
  COMMAND ${Java_JAVAC_EXECUTABLE} -encoding UTF-8 -Xlint:all -Werror
          -cp ${LCM_JAVA_JAR}:${comlearn_lcmtypes_jar_file}
          -d ${decode_check_dir} ${decode_check_src}
  DEPENDS ${decode_check_src} ${comlearn_lcmtypes_jar_file} comlearn_lcmtypes_jar
  COMMENT "javac tests/java/DecodeCheck.java"
  VERBATIM)
add_custom_target(check_messages_java ALL DEPENDS ${decode_check_class})

# check_messages writes each type's C encoding and its fields; DecodeCheck decodes the encoding
# with the Java classes (found by fingerprint, as lcm-spy finds them) and compares every field.
set(decode_check_cp ${decode_check_dir}:${comlearn_lcmtypes_jar_file}:${LCM_JAVA_JAR})
if(JCHART2D_JAR)
  # lcm-spy's own class path; without it the class scan reports lcm.spy's chart classes.
  string(APPEND decode_check_cp ":${JCHART2D_JAR}")
endif()
set(msg_fixture_dir ${CMAKE_CURRENT_BINARY_DIR}/messages-java-fixtures)
file(MAKE_DIRECTORY ${msg_fixture_dir})
add_test(NAME messages_java_fixtures
  COMMAND check_messages --write-fixtures ${msg_fixture_dir})
add_test(NAME messages_java_decode
  COMMAND ${Java_JAVA_EXECUTABLE} -ea
          -cp ${decode_check_cp}
          DecodeCheck ${msg_fixture_dir}
          ${comlearn_lcm_types})
set_tests_properties(messages_java_fixtures PROPERTIES
  TIMEOUT 60 FIXTURES_SETUP messages_java)
set_tests_properties(messages_java_decode PROPERTIES
  TIMEOUT 120 FIXTURES_REQUIRED messages_java)
