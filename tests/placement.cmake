# lib/placement: one Check runner (kinematics and plans). urdfdom's check_urdf on the YuMi model is
# check_urdf_yumi (urdf_tools.cmake, with every bundled URDF).
comlearn_add_check(check_placement
  SOURCES check_placement.c placement_kin_tests.c placement_plan_tests.c
          placement_grasp_tests.c
  LIBS comlearn_placement
  TIMEOUT 300)

# plan.c at -O3 (what a Release build uses) with the strict warnings as errors: GCC 12 warned
# -Wstringop-overflow there, a false positive the code now avoids (rot_finite() in plan.c).
add_test(NAME placement_plan_o3_warnings
         COMMAND ${CMAKE_C_COMPILER} -std=c11 -O3
                 -Wall -Wextra -Wpedantic -Wshadow -Wconversion -Werror
                 -I${PROJECT_SOURCE_DIR}/lib/placement/include
                 -I${PROJECT_SOURCE_DIR}/lib/placement/src
                 -I${PROJECT_SOURCE_DIR}/lib/model/include
                 -I${PROJECT_SOURCE_DIR}/lib/math/include
                 -c ${PROJECT_SOURCE_DIR}/lib/placement/src/plan.c
                 -o ${CMAKE_CURRENT_BINARY_DIR}/plan_o3.o)
set_tests_properties(placement_plan_o3_warnings PROPERTIES TIMEOUT 120)
