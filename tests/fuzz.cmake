# Fuzz harnesses (tests/fuzz, docs/security.md "Fuzzing"). In every build the seed corpora
# (tests/fuzz/corpus/<harness>) run through each harness as a CTest, fuzz_corpus_<harness>, with
# fuzz_replay.c in place of libFuzzer. With COMLEARN_FUZZ (the fuzz preset, clang) each harness is
# also a libFuzzer binary, fuzz_<harness>, that scripts/fuzz.sh runs for a bounded time.
set(fuzz_msg_libs comlearn_msg comlearn_lcmtypes)
set(fuzz_mesh_libs comlearn_model)
set(fuzz_urdf_libs comlearn_model_sim comlearn_model)
foreach(h msg mesh urdf)
  add_executable(fuzz_replay_${h} fuzz/fuzz_${h}.c fuzz/fuzz_replay.c)
  comlearn_strict(fuzz_replay_${h})
  target_link_libraries(fuzz_replay_${h} PRIVATE ${fuzz_${h}_libs})
  add_test(NAME fuzz_corpus_${h}
           COMMAND fuzz_replay_${h} ${CMAKE_CURRENT_SOURCE_DIR}/fuzz/corpus/${h})
  set_tests_properties(fuzz_corpus_${h} PROPERTIES TIMEOUT 120)
  if(COMLEARN_FUZZ)
    add_executable(fuzz_${h} fuzz/fuzz_${h}.c)
    target_link_libraries(fuzz_${h} PRIVATE ${fuzz_${h}_libs})
    target_link_options(fuzz_${h} PRIVATE -fsanitize=fuzzer)
  endif()
endforeach()
