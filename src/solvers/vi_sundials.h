/*
 * vi_sundials.h - the SUNDIALS headers the solver (src/solvers/vi_solver.c) and its tests use, for every
 * SUNDIALS the build takes (CMakeLists.txt): 6.4 or 7.x, with CVODE or, where only it is installed,
 * CVODES. CVODES holds CVODE's whole API (the same CVode* functions, under cvodes/); the build
 * defines VI_SUNDIALS_CVODES when it links CVODES.
 *
 * What differs between the versions, as names here:
 *   VI_SUN_COMM, VI_SUN_COMM_NULL  the communicator SUNContext_Create takes: void * and NULL in 6.x,
 *                                  SUNComm and SUN_COMM_NULL since 7.0
 *   VI_SUNDIALS_7                  1 from 7.0: errors reach the context's handler stack
 *                                  (SUNContext_PushErrHandler), warnings its logger (SUNLogger);
 *                                  6.x calls the integrator's handler (CVodeSetErrHandlerFn) for both
 *   VI_SUNLOGGER_CALLBACKS         1 from 7.8, whose logger passes its messages to functions
 *                                  (SUNLogger_SetQueueAndFlushMsgFns); the loggers of 7.0 to 7.7 can
 *                                  only write to files (by default CVODE's warnings to stdout)
 */
#ifndef VI_SUNDIALS_H
#define VI_SUNDIALS_H

#if defined(VI_SUNDIALS_CVODES)
#include <cvodes/cvodes.h>
#else
#include <cvode/cvode.h>
#endif
#include <nvector/nvector_serial.h>
#include <sundials/sundials_context.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#if SUNDIALS_VERSION_MAJOR >= 7
#define VI_SUNDIALS_7 1
#define VI_SUN_COMM SUNComm
#define VI_SUN_COMM_NULL SUN_COMM_NULL
#include <sundials/sundials_logger.h>
#else
#define VI_SUNDIALS_7 0
#define VI_SUN_COMM void *
#define VI_SUN_COMM_NULL NULL
#endif
#if SUNDIALS_VERSION_MAJOR > 7 || (SUNDIALS_VERSION_MAJOR == 7 && SUNDIALS_VERSION_MINOR >= 8)
#define VI_SUNLOGGER_CALLBACKS 1
#else
#define VI_SUNLOGGER_CALLBACKS 0
#endif

#endif
