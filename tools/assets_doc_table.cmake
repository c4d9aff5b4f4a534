# The table in docs/assets.md between the markers below is printed by `comlearn-rockgen --table`.
#   cmake -DROCKGEN=path/to/comlearn-rockgen -DASSETS=assets -DDOC=docs/assets.md
#         -DMODE=update|check -P tools/assets_doc_table.cmake
# update: replace the block with the tool's output; check: fail when they differ.
set(begin_marker "<!-- rockgen table: begin -->")
set(end_marker "<!-- rockgen table: end -->")

execute_process(COMMAND ${ROCKGEN} --table --assets-dir ${ASSETS}
  OUTPUT_VARIABLE table RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "comlearn-rockgen --table failed (${rc})")
endif()

file(READ ${DOC} doc)
string(FIND "${doc}" "${begin_marker}" b)
string(FIND "${doc}" "${end_marker}" e)
if(b EQUAL -1 OR e EQUAL -1 OR e LESS b)
  message(FATAL_ERROR "${DOC}: markers '${begin_marker}' ... '${end_marker}' not found")
endif()
string(LENGTH "${begin_marker}\n" blen)
math(EXPR start "${b} + ${blen}")
math(EXPR len "${e} - ${start}")
string(SUBSTRING "${doc}" ${start} ${len} current)

if(MODE STREQUAL "update")
  string(SUBSTRING "${doc}" 0 ${start} head)
  string(SUBSTRING "${doc}" ${e} -1 tail)
  file(WRITE ${DOC} "${head}${table}${tail}")
elseif(NOT current STREQUAL table)
  message(FATAL_ERROR "${DOC}: the table differs from `comlearn-rockgen --table`; "
                      "run `cmake --build <build> --target comlearn_assets_docs`")
endif()
