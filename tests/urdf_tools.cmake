# The bundled URDFs as ROS tools see them (docs/assets.md, "ROS package"):
#   check_urdf_<name>    urdfdom's check_urdf (Debian liburdfdom-tools) on every bundled URDF,
#                        clean: exit 0, "Successfully Parsed XML", nothing on stderr;
#   assets_ros_package   assets/package.xml is the ROS package comlearn (format 3) at the
#                        project's version with no dependency, and every mesh a bundled URDF names
#                        is package://comlearn/REST with assets/REST an existing file.
# Both through tests/urdf_tools_run.cmake.
set(comlearn_bundled_urdfs
  rocks/rock_1_even rocks/rock_1_uneven
  rocks/rock_2_even rocks/rock_2_uneven
  rocks/rock_3_even rocks/rock_3_uneven
  base/base yumi/yumi)

# Missing tool: each test fails saying so (scripts/setup.sh installs liburdfdom-tools).
find_program(COMLEARN_CHECK_URDF check_urdf)
foreach(urdf ${comlearn_bundled_urdfs})
  get_filename_component(stem ${urdf} NAME)
  add_test(NAME check_urdf_${stem}
           COMMAND ${CMAKE_COMMAND} -DMODE=check_urdf -DCHECK_URDF=${COMLEARN_CHECK_URDF}
                   -DURDF=${COMLEARN_ASSETS_DIR}/${urdf}.urdf
                   -P ${CMAKE_CURRENT_SOURCE_DIR}/urdf_tools_run.cmake)
  set_tests_properties(check_urdf_${stem} PROPERTIES TIMEOUT 30)
endforeach()

list(TRANSFORM comlearn_bundled_urdfs APPEND .urdf OUTPUT_VARIABLE comlearn_bundled_urdf_files)
string(REPLACE ";" "," comlearn_bundled_urdf_files "${comlearn_bundled_urdf_files}")
add_test(NAME assets_ros_package
         COMMAND ${CMAKE_COMMAND} -DMODE=package -DASSETS=${COMLEARN_ASSETS_DIR}
                 -DVERSION=${PROJECT_VERSION} -DURDFS=${comlearn_bundled_urdf_files}
                 -P ${CMAKE_CURRENT_SOURCE_DIR}/urdf_tools_run.cmake)
set_tests_properties(assets_ros_package PROPERTIES TIMEOUT 30)
