# check_replay: record a real `comlearn estimate --spawn-sim` run with lcm-logger (a udpm URL of
# its own per test), replay it with lcm-logplayer into `comlearn watch --once --json`, and check
# that the replayed trial outcomes and final estimate equal the live ones; then recompute the
# estimate from the log's COM_TRIAL records (docs/replay.md). Needs lcm-logger / lcm-logplayer
# (Debian liblcm-bin) on PATH.
comlearn_add_check(check_replay SOURCES check_replay.c
  LIBS comlearn_estimate_drive comlearn_msg comlearn_placement comlearn_model_sim comlearn_model
  TIMEOUT 300)
target_compile_definitions(check_replay PRIVATE COMLEARN_BIN="$<TARGET_FILE:comlearn>")
add_dependencies(check_replay comlearn comlearn-sim)
