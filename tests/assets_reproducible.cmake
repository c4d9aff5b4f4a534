# Regenerate the assets, the picture and the docs table into a scratch folder and require them to
# equal the committed files byte for byte (the generator uses only IEEE-exact arithmetic and sqrt,
# so the normal and the sanitizer build write the same bytes).
#   cmake -DROCKGEN=... -DSVG=... -DASSETS=... -DDOCS=... -DTABLE_SCRIPT=... -DOUT=... -P this
set(expected
  base/base.urdf package.xml
  rocks/meshes/rock_1.stl rocks/meshes/rock_2.stl rocks/meshes/rock_3.stl
  rocks/rock_1_even.urdf rocks/rock_1_uneven.urdf
  rocks/rock_2_even.urdf rocks/rock_2_uneven.urdf
  rocks/rock_3_even.urdf rocks/rock_3_uneven.urdf)

file(REMOVE_RECURSE ${OUT})
execute_process(COMMAND ${ROCKGEN} --out-dir ${OUT} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "comlearn-rockgen --out-dir ${OUT} failed (${rc})")
endif()

# The generator writes exactly the expected files, and the committed folders hold nothing else.
file(GLOB_RECURSE generated RELATIVE ${OUT} ${OUT}/*)
file(GLOB_RECURSE committed RELATIVE ${ASSETS} ${ASSETS}/rocks/* ${ASSETS}/base/*
     ${ASSETS}/package.xml)
list(SORT generated)
list(SORT committed)
if(NOT generated STREQUAL expected)
  message(FATAL_ERROR "generated files: ${generated}\nexpected: ${expected}")
endif()
if(NOT committed STREQUAL expected)
  message(FATAL_ERROR "committed files: ${committed}\nexpected: ${expected}")
endif()

set(differ "")
foreach(f ${expected})
  execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT}/${f} ${ASSETS}/${f}
                  RESULT_VARIABLE d)
  if(NOT d EQUAL 0)
    list(APPEND differ ${f})
  endif()
endforeach()

execute_process(COMMAND ${SVG} --assets-dir ${ASSETS} --out ${OUT}/rocks.svg RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "comlearn-rocks-svg failed (${rc})")
endif()
execute_process(COMMAND ${CMAKE_COMMAND} -E compare_files ${OUT}/rocks.svg ${DOCS}/img/rocks.svg
                RESULT_VARIABLE d)
if(NOT d EQUAL 0)
  list(APPEND differ docs/img/rocks.svg)
endif()
if(differ)
  message(FATAL_ERROR "differ from a fresh generation: ${differ}\n"
                      "regenerate: cmake --build <build> --target comlearn_assets comlearn_assets_docs")
endif()

execute_process(COMMAND ${CMAKE_COMMAND} -DROCKGEN=${ROCKGEN} -DASSETS=${ASSETS}
                        -DDOC=${DOCS}/assets.md -DMODE=check -P ${TABLE_SCRIPT}
                RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "docs/assets.md: table out of date")
endif()
message(STATUS "assets, picture and table reproduced byte for byte")
