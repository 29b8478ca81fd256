/*
 * vi_log.h - the log callback the engine and the solvers report through, and its categories (the
 * FMU's log categories: doc/model.md, "The event log"). Plain C, no solver, no FMI.
 */
#ifndef VI_LOG_H
#define VI_LOG_H

typedef void (*vi_log_fn)(void *env, int category, const char *fmt, ...);
enum { VI_LOG_EVENTS, VI_LOG_SOLVER, VI_LOG_WARNING, VI_LOG_ERROR };

#endif
