# tests/urdf_tools.cmake's checks.
#   cmake -DMODE=check_urdf -DCHECK_URDF=path -DURDF=file -P this
#   cmake -DMODE=package -DASSETS=dir -DVERSION=x.y.z -DURDFS=a.urdf,b.urdf -P this
cmake_minimum_required(VERSION 3.20)

if(MODE STREQUAL "check_urdf")
  if(NOT EXISTS "${CHECK_URDF}")
    message(FATAL_ERROR "check_urdf not found: install liburdfdom-tools (scripts/setup.sh)")
  endif()
  execute_process(COMMAND ${CHECK_URDF} ${URDF} RESULT_VARIABLE rc OUTPUT_VARIABLE out
                  ERROR_VARIABLE err)
  if(NOT rc EQUAL 0 OR NOT out MATCHES "Successfully Parsed XML" OR NOT err STREQUAL "")
    message(FATAL_ERROR "check_urdf ${URDF}: exit ${rc}\nstdout:\n${out}\nstderr:\n${err}")
  endif()
  message(STATUS "check_urdf ${URDF}: clean")
  return()
endif()

if(NOT MODE STREQUAL "package")
  message(FATAL_ERROR "MODE must be check_urdf or package, not '${MODE}'")
endif()

# assets/package.xml: format 3, <name>comlearn</name>, the project's version, and no dependency
# (nothing in comlearn needs ROS).
file(READ ${ASSETS}/package.xml xml)
string(REGEX REPLACE "<!--([^-]|-[^-])*-->" "" xml_nc "${xml}")
foreach(want "<package format=\"3\">" "<name>comlearn</name>" "<version>${VERSION}</version>"
             "<description>" "<maintainer email=\"" "<license>")
  string(FIND "${xml_nc}" "${want}" at)
  if(at EQUAL -1)
    message(FATAL_ERROR "${ASSETS}/package.xml: no ${want}")
  endif()
endforeach()
if(xml_nc MATCHES "<(depend|build_depend|buildtool_depend|exec_depend|build_export_depend)[ >]")
  message(FATAL_ERROR "${ASSETS}/package.xml declares a dependency: ${CMAKE_MATCH_0}")
endif()

# Every mesh of a bundled URDF is package://comlearn/REST, REST a file under the package root.
string(REPLACE "," ";" urdfs "${URDFS}")
set(meshes 0)
foreach(rel IN LISTS urdfs)
  file(READ ${ASSETS}/${rel} text)
  string(REGEX MATCHALL "filename=\"[^\"]*\"" names "${text}")
  foreach(attr IN LISTS names)
    string(REGEX REPLACE "^filename=\"(.*)\"$" "\\1" uri "${attr}")
    if(NOT uri MATCHES "^package://comlearn/(.+)$")
      message(FATAL_ERROR "${rel}: mesh '${uri}' is not package://comlearn/...")
    endif()
    set(rest ${CMAKE_MATCH_1})
    if(rest MATCHES "(^|/)\\.\\.(/|$)" OR NOT EXISTS ${ASSETS}/${rest}
       OR IS_DIRECTORY ${ASSETS}/${rest})
      message(FATAL_ERROR "${rel}: mesh '${uri}' is no file under ${ASSETS}")
    endif()
    math(EXPR meshes "${meshes} + 1")
  endforeach()
endforeach()
if(meshes LESS 12)
  message(FATAL_ERROR "only ${meshes} package:// meshes in ${URDFS} (the six rocks name two each)")
endif()
message(STATUS "package.xml comlearn ${VERSION}; ${meshes} package://comlearn meshes resolve")
