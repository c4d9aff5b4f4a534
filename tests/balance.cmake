# Physics is slow under the sanitizers (-O0): the timeout leaves room for that build.
comlearn_add_check(check_balance
  SOURCES check_balance.c balance_trial_tests.c balance_accuracy_tests.c balance_regime_tests.c
          balance_stable_tests.c balance_stack_tests.c
  LIBS comlearn_balance comlearn_model_sim comlearn_math PkgConfig::ODE
  TIMEOUT 900)
# balance_trial_tests.c also checks internal pieces (contact filtering and reduction).
target_include_directories(check_balance PRIVATE ${PROJECT_SOURCE_DIR}/lib/balance/src)
