# The bundled assets: their requirements (check_assets) and that the generator reproduces them
# byte for byte (assets_reproducible). check_urdf on each, and the ROS package: urdf_tools.cmake.
comlearn_add_check(check_assets SOURCES check_assets.c LIBS comlearn_rockgen comlearn_model_sim comlearn_math)

add_test(NAME assets_reproducible
  COMMAND ${CMAKE_COMMAND}
          -DROCKGEN=$<TARGET_FILE:comlearn-rockgen>
          -DSVG=$<TARGET_FILE:comlearn-rocks-svg>
          -DASSETS=${COMLEARN_ASSETS_DIR}
          -DDOCS=${CMAKE_SOURCE_DIR}/docs
          -DTABLE_SCRIPT=${CMAKE_SOURCE_DIR}/tools/assets_doc_table.cmake
          -DOUT=${CMAKE_CURRENT_BINARY_DIR}/assets_regen
          -P ${CMAKE_CURRENT_SOURCE_DIR}/assets_reproducible.cmake)
set_tests_properties(assets_reproducible PROPERTIES TIMEOUT 120)

# Random rocks (rockgen_spec_random, comlearn-rockgen --random) and the stack picture
# (apps/comlearn/stack_svg.c, target comlearn_stack_svg).
comlearn_add_check(check_rockgen_random
  SOURCES check_rockgen_random.c
  LIBS comlearn_stack_svg comlearn_rockgen comlearn_balance comlearn_model_sim comlearn_math TIMEOUT 300)
target_compile_definitions(check_rockgen_random PRIVATE
  COMLEARN_ROCKGEN="$<TARGET_FILE:comlearn-rockgen>")
add_dependencies(check_rockgen_random comlearn-rockgen)
