# include()d by the symbol checks (model_symbols, qlearn_alloc_symbols, shared_symbols,
# estimate_symbols): nm_lines(OUT FILE [NM ARGS...]) sets OUT to the lines `${NM} ARGS FILE`
# prints, as a CMake list (";" in a line becomes ","), and stops the script when nm fails.
function(nm_lines out file)
  execute_process(COMMAND ${NM} ${ARGN} ${file}
                  OUTPUT_VARIABLE text ERROR_VARIABLE errtext RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "${NM} ${ARGN} ${file} failed (${rc}): ${errtext}")
  endif()
  string(REPLACE ";" "," text "${text}")
  string(REPLACE "\n" ";" text "${text}")
  set(${out} "${text}" PARENT_SCOPE)
endfunction()
