/*
 * comlearn/qlearn_qtable.h - a fixed-capacity Q-table over integer states and 2 actions.
 *
 * States are integers (the paper policy uses the state's index on the grid of the resolution,
 * relative to the prior). The table holds up to QLEARN_QTABLE_MAX_STATES distinct states, each
 * with QLEARN_QTABLE_ACTIONS Q values; a state never set reads as QLEARN_QTABLE_Q_UNSEEN for
 * every action. Lookup is a bounded linear scan (at most QLEARN_QTABLE_MAX_STATES entries).
 *
 * Memory: no heap, no I/O, no globals; qlearn_qtable_t is caller-owned and may be copied with
 * memcpy. Thread safety: functions touch only their arguments.
 */
#ifndef COMLEARN_QLEARN_QTABLE_H
#define COMLEARN_QLEARN_QTABLE_H

#include <stdint.h>

#include "comlearn/qlearn_types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* One state is visited at most once per trial, so this many states always suffice. */
#define QLEARN_QTABLE_MAX_STATES QLEARN_MAX_TRIALS
#define QLEARN_QTABLE_ACTIONS 2
/* Q of a state never set (both actions equal: argmax ties). */
#define QLEARN_QTABLE_Q_UNSEEN 0.0

typedef struct {
  uint32_t n;                                                /* states stored */
  int64_t state[QLEARN_QTABLE_MAX_STATES];                   /* their keys */
  double q[QLEARN_QTABLE_MAX_STATES][QLEARN_QTABLE_ACTIONS]; /* their Q values */
} qlearn_qtable_t;

/* Empty the table. QLEARN_E_ARG for NULL. */
qlearn_status_t qlearn_qtable_init(qlearn_qtable_t *table);

/* Set Q(state, .) = q[QLEARN_QTABLE_ACTIONS] (overwrites an existing row). QLEARN_E_ARG for NULL,
 * QLEARN_E_NONFINITE for a non-finite q, QLEARN_E_CAPACITY when the state is new and the table is
 * full. On error the table is unchanged. */
qlearn_status_t qlearn_qtable_set(qlearn_qtable_t *table, int64_t state, const double *q);

/* Q(state, .) into q[QLEARN_QTABLE_ACTIONS]; returns 1 if the state was set, 0 if unseen (q then
 * holds QLEARN_QTABLE_Q_UNSEEN), -1 for NULL arguments. */
int qlearn_qtable_get(const qlearn_qtable_t *table, int64_t state, double *q);

#ifdef __cplusplus
}
#endif

#endif /* COMLEARN_QLEARN_QTABLE_H */
