# cmake -DBUILD_DIR=... -DSOURCE_DIR=... -DWORK_DIR=... -DLIBDIR=lib -DCC=cc -DCXX=c++
#       -DGENERATOR=... -DLCM_URL=udpm://... -DPKG_CONFIG=pkg-config -P this
# What an installed comlearn gives a user (docs/install.md), from a fresh `cmake --install` of
# BUILD_DIR into WORK_DIR/prefix:
#   1. the files: headers, static and shared libraries with SONAME links, CMake package,
#      pkg-config files, programs, assets; no internal library; the package files do not name
#      the source tree;
#   2. the installed programs find their data under the prefix: `comlearn inspect` resolves the
#      installed rocks' package://comlearn meshes in share/comlearn (a copy elsewhere through
#      ROS_PACKAGE_PATH only); comlearn-sim's and comlearn-rockgen's --help name
#      PREFIX/share/comlearn, and the installed `comlearn estimate
#      --spawn-sim` (COMLEARN_SIM unset) starts the installed comlearn-sim and plans with the
#      installed YuMi URDF, finding all three components of a bundled rock;
#   3. examples/ configured, built and run against the prefix with find_package(comlearn), once
#      on the shared and once on the static libraries (comlearn_VERSION and comlearn_DATA_DIR
#      set); mesh_info and estimate_balance print known numbers for rock_1_even (the shared
#      estimate_balance loads libcomlearn_qlearn.so through libcomlearn_estimate.so's RUNPATH);
#   4. the pkg-config route: cc examples/mesh_info.c $(pkg-config --cflags --libs comlearn-model)
#      with PKG_CONFIG_PATH into the prefix, same numbers;
#   5. with -DPYTHON=python3 -DPYTHON_DIR=dir: the Python package comlearn imported from
#      PREFIX/PYTHON_DIR (not from the build tree), a yumi_status_t round trip and comlearn.udpm.
cmake_minimum_required(VERSION 3.20)
foreach(var BUILD_DIR SOURCE_DIR WORK_DIR LIBDIR CC CXX GENERATOR LCM_URL PKG_CONFIG)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "install.cmake: ${var} is not set")
  endif()
endforeach()

function(run)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT rc EQUAL 0)
    string(REPLACE ";" " " cmd "${ARGN}")
    message(FATAL_ERROR "failed (${rc}): ${cmd}\n${out}\n${err}")
  endif()
  set(run_out "${out}" PARENT_SCOPE)
endfunction()

function(expect_match text regex what)
  if(NOT text MATCHES "${regex}")
    message(FATAL_ERROR "${what}: expected to match '${regex}', got:\n${text}")
  endif()
endfunction()

file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})
file(REAL_PATH ${WORK_DIR} WORK_DIR)
set(prefix ${WORK_DIR}/prefix)
run(${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})

# 1. Files.
set(libs model model_sim balance qlearn placement estimate stack stack_sim lcmtypes msg)
set(expected
  include/comlearn/model.h include/comlearn/model_inertial.h include/comlearn/balance.h
  include/comlearn/model_support.h include/comlearn/model_outcome.h include/comlearn/qlearn.h
  include/comlearn/placement_plan.h
  include/comlearn/estimate.h include/comlearn/stack.h include/comlearn/math3d.h
  include/comlearn/msg.h ${LIBDIR}/pkgconfig/comlearn-math.pc
  include/comlearn/comlearn_yumi_command_t.h
  ${LIBDIR}/cmake/comlearn/comlearnConfig.cmake
  ${LIBDIR}/cmake/comlearn/comlearnConfigVersion.cmake
  ${LIBDIR}/cmake/comlearn/comlearnTargets.cmake
  bin/comlearn bin/comlearn-sim bin/comlearn-rockgen bin/comlearn-shapegen
  share/comlearn/rocks/rock_1_even.urdf share/comlearn/rocks/meshes/rock_1.stl
  share/comlearn/base/base.urdf share/comlearn/yumi/yumi.urdf share/comlearn/package.xml
  share/ament_index/resource_index/packages/comlearn)
foreach(lib IN LISTS libs)
  string(REPLACE "_" "-" pc ${lib})
  list(APPEND expected ${LIBDIR}/libcomlearn_${lib}.a ${LIBDIR}/libcomlearn_${lib}.so
       ${LIBDIR}/libcomlearn_${lib}.so.0 ${LIBDIR}/libcomlearn_${lib}.so.0.1.0
       ${LIBDIR}/pkgconfig/comlearn-${pc}.pc)
endforeach()
foreach(f IN LISTS expected)
  if(NOT EXISTS ${prefix}/${f})
    message(FATAL_ERROR "not installed: ${prefix}/${f}")
  endif()
endforeach()
foreach(internal comlearn_cli cli_log.h comlearn_estimate_ comlearn_stack_svg comlearn_rockgen
                 comlearn_shapegen model_internal.h)
  file(GLOB_RECURSE hits ${prefix}/*${internal}*)
  if(hits)
    message(FATAL_ERROR "internal file installed: ${hits}")
  endif()
endforeach()
file(GLOB package_files ${prefix}/${LIBDIR}/cmake/comlearn/* ${prefix}/${LIBDIR}/pkgconfig/*)
foreach(f IN LISTS package_files)
  file(READ ${f} text)
  string(FIND "${text}" "${SOURCE_DIR}" at)
  if(NOT at EQUAL -1)
    message(FATAL_ERROR "${f} names the source tree ${SOURCE_DIR}")
  endif()
endforeach()

# 2. The installed programs find their data under the prefix.
set(data ${prefix}/share/comlearn)
run(${prefix}/bin/comlearn-sim --help)
expect_match("${run_out}" "default: ${data}/yumi/yumi.urdf" "comlearn-sim --help")
run(${prefix}/bin/comlearn-rockgen --help)
expect_match("${run_out}" "default: ${data}\\)" "comlearn-rockgen --help")
# The installed rocks name package://comlearn/rocks/meshes/...: resolved from share/comlearn's
# package.xml (not the source tree's), and, for a copy outside the package, through
# ROS_PACKAGE_PATH=share/comlearn only.
unset(ENV{ROS_PACKAGE_PATH})
run(${prefix}/bin/comlearn inspect ${data}/rocks/rock_1_even.urdf --json)
expect_match("${run_out}" "\"mesh\": \"${data}/rocks/meshes/rock_1.stl\"" "installed package://")
file(READ ${data}/rocks/rock_1_even.urdf rock_text)
expect_match("${rock_text}" "filename=\"package://comlearn/rocks/meshes/rock_1.stl\"" "rock_1_even.urdf")
file(WRITE ${WORK_DIR}/ros_user/rock.urdf "${rock_text}")
execute_process(COMMAND ${prefix}/bin/comlearn inspect ${WORK_DIR}/ros_user/rock.urdf
                RESULT_VARIABLE rc OUTPUT_QUIET ERROR_VARIABLE err)
if(rc EQUAL 0 OR NOT err MATCHES "unknown package 'comlearn'")
  message(FATAL_ERROR "a copy outside the package without ROS_PACKAGE_PATH: exit ${rc}\n${err}")
endif()
set(ENV{ROS_PACKAGE_PATH} ${data})
run(${prefix}/bin/comlearn inspect ${WORK_DIR}/ros_user/rock.urdf --json)
expect_match("${run_out}" "\"mesh\": \"${data}/rocks/meshes/rock_1.stl\"" "ROS_PACKAGE_PATH")
unset(ENV{ROS_PACKAGE_PATH})

set(ENV{COMLEARN_SIM} "")
run(${prefix}/bin/comlearn estimate ${data}/rocks/rock_1_even.urdf --spawn-sim --lcm-url ${LCM_URL}
    --json -q)
expect_match("${run_out}" "\"backend\": \"lcm\"" "installed comlearn estimate --spawn-sim")
expect_match("${run_out}" "\"found\": \\[true, true, true\\]" "installed comlearn estimate --spawn-sim")

# 3. find_package(comlearn) from examples/, shared and static.
# rock_1_even: bounding box centred on the link origin (tools/rockgen), uniform-density CoM as
# `comlearn estimate` reports it (uniform_com_m).
set(mesh_info_expected [[
rock_1: 2000 triangles
bbox_min_m -0.038057 -0.029332 -0.022891
bbox_max_m 0.038057 0.029332 0.022891
com_m 0.002667 -0.000927 -0.002493
]])
# lib/estimate on lib/balance, as `comlearn estimate --direct` (the same 16 trials and CoM).
set(estimate_balance_expected [[
x +2.6653 mm +- 0.0778 (true +2.6665)
y -0.9976 mm +- 0.0778 (true -0.9269)
z -2.4433 mm +- 0.0550 (true -2.4933)
16 trials, done
]])
foreach(kind shared static)
  set(static OFF)
  if(kind STREQUAL "static")
    set(static ON)
  endif()
  set(bin ${WORK_DIR}/examples-${kind})
  run(${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples -B ${bin} -G ${GENERATOR}
      -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_C_COMPILER=${CC} -DCMAKE_CXX_COMPILER=${CXX}
      -DCOMLEARN_EXAMPLES_STATIC=${static})
  expect_match("${run_out}" "comlearn 0\\.1\\.0, assets in ${data}\n" "comlearn_DATA_DIR")
  run(${CMAKE_COMMAND} --build ${bin})
  foreach(example mesh_info estimate_balance)
    run(${bin}/${example} ${data}/rocks/rock_1_even.urdf)
    if(NOT run_out STREQUAL ${example}_expected)
      message(FATAL_ERROR "${example} (find_package, ${kind}) printed:\n${run_out}\n"
                          "expected:\n${${example}_expected}")
    endif()
  endforeach()
endforeach()
if(NOT EXISTS ${WORK_DIR}/examples-shared/mesh_info)
  message(FATAL_ERROR "no examples-shared/mesh_info")
endif()

# 4. pkg-config, as the first comment of examples/mesh_info.c says (plus an rpath to the prefix).
set(ENV{PKG_CONFIG_PATH} ${prefix}/${LIBDIR}/pkgconfig)
run(${PKG_CONFIG} --cflags --libs comlearn-model)
separate_arguments(pc_flags UNIX_COMMAND "${run_out}")
run(${CC} ${SOURCE_DIR}/examples/mesh_info.c ${pc_flags} -Wl,-rpath,${prefix}/${LIBDIR}
    -o ${WORK_DIR}/mesh_info_pkg_config)
run(${WORK_DIR}/mesh_info_pkg_config ${data}/rocks/rock_1_even.urdf)
if(NOT run_out STREQUAL mesh_info_expected)
  message(FATAL_ERROR "mesh_info (pkg-config) printed:\n${run_out}\nexpected:\n${mesh_info_expected}")
endif()
# 5. Python.
if(DEFINED PYTHON AND NOT PYTHON STREQUAL "")
  set(ENV{PYTHONPATH} ${prefix}/${PYTHON_DIR})
  # no ';' in the script: run() passes its arguments on as a CMake list
  run(${PYTHON} -c "import comlearn, comlearn.udpm as u
m = comlearn.yumi_status_t()
m.utime = 7
assert comlearn.yumi_status_t.decode(m.encode()).utime == 7
assert u.parse_url(u.DEFAULT_URL)[1] == 7667
print(comlearn.__file__)")
  expect_match("${run_out}" "^${prefix}/${PYTHON_DIR}/comlearn/__init__.py" "import comlearn")
endif()

message(STATUS "installed into ${prefix}; mesh_info (find_package shared and static, pkg-config):\n"
               "${run_out}")
