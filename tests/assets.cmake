# The bundled assets: their requirements (check_assets), URDF syntax (check_urdf from
# liburdfdom-tools), and that the generator reproduces them byte for byte (assets_reproducible).
comlearn_add_check(check_assets SOURCES check_assets.c LIBS comlearn_rockgen comlearn_model_sim comlearn_math)

set(comlearn_asset_urdfs
  rocks/rock_1_even rocks/rock_1_uneven
  rocks/rock_2_even rocks/rock_2_uneven
  rocks/rock_3_even rocks/rock_3_uneven
  base/base)

find_program(COMLEARN_CHECK_URDF check_urdf)
foreach(urdf ${comlearn_asset_urdfs})
  get_filename_component(stem ${urdf} NAME)
  if(COMLEARN_CHECK_URDF)
    add_test(NAME check_urdf_${stem}
             COMMAND ${COMLEARN_CHECK_URDF} ${COMLEARN_ASSETS_DIR}/${urdf}.urdf)
  else()
    # Missing tool: fail loudly rather than skip (scripts/setup.sh installs liburdfdom-tools).
    add_test(NAME check_urdf_${stem}
             COMMAND ${CMAKE_COMMAND} -E echo "check_urdf not found: install liburdfdom-tools")
    set_tests_properties(check_urdf_${stem} PROPERTIES WILL_FAIL TRUE)
  endif()
  set_tests_properties(check_urdf_${stem} PROPERTIES TIMEOUT 30)
endforeach()

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
