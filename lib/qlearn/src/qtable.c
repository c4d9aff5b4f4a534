/* Fixed-capacity Q-table (comlearn/qlearn_qtable.h). */
#include <math.h>
#include <string.h>

#include "comlearn/qlearn_qtable.h"

_Static_assert(QLEARN_QTABLE_MAX_STATES >= QLEARN_MAX_TRIALS, "one state per trial must fit");
_Static_assert(QLEARN_QTABLE_ACTIONS == 2, "the paper's actions are +1 and -1");

qlearn_status_t qlearn_qtable_init(qlearn_qtable_t *table) {
  if (table == NULL) return QLEARN_E_ARG;
  memset(table, 0, sizeof *table);
  return QLEARN_OK;
}

/* Index of state, or -1. */
static int find(const qlearn_qtable_t *table, int64_t state) {
  for (uint32_t i = 0; i < table->n && i < QLEARN_QTABLE_MAX_STATES; i++) {
    if (table->state[i] == state) return (int)i;
  }
  return -1;
}

qlearn_status_t qlearn_qtable_set(qlearn_qtable_t *table, int64_t state, const double *q) {
  if (table == NULL || q == NULL) return QLEARN_E_ARG;
  for (int a = 0; a < QLEARN_QTABLE_ACTIONS; a++) {
    if (!isfinite(q[a])) return QLEARN_E_NONFINITE;
  }
  int i = find(table, state);
  if (i < 0) {
    if (table->n >= QLEARN_QTABLE_MAX_STATES) return QLEARN_E_CAPACITY;
    i = (int)table->n++;
    table->state[i] = state;
  }
  for (int a = 0; a < QLEARN_QTABLE_ACTIONS; a++) table->q[i][a] = q[a];
  return QLEARN_OK;
}

int qlearn_qtable_get(const qlearn_qtable_t *table, int64_t state, double *q) {
  if (table == NULL || q == NULL) return -1;
  const int i = find(table, state);
  for (int a = 0; a < QLEARN_QTABLE_ACTIONS; a++) {
    q[a] = (i < 0) ? QLEARN_QTABLE_Q_UNSEEN : table->q[i][a];
  }
  return i < 0 ? 0 : 1;
}
