/*
 * stair.c - a test FMU (FMI 2.0 Co-Simulation) that ends its simulation: counter = 1 + floor(t),
 * and the fmi2DoStep that reaches t = 9 s (counter 10) stops there, returning fmi2Discard with
 * fmi2Terminated true and fmi2LastSuccessfulTime 9. In the spirit of the Modelica
 * Reference-FMUs' Stair (see ../README.md).
 *
 * Value references: 0 counter (output).
 */
#include <math.h>

#define MODEL_GUID "{6a1d2c3e-9b8f-4e7d-a6c5-b4a3f2e1d0c9}"
#define N_REALS 1

#include "fmi2cs.h"

#define STOP_TIME 9.0
#define EPS 1e-9

enum { VR_COUNTER = 0 };

static void model_defaults(Instance *c) { c->r[VR_COUNTER] = 1.0; }

static int model_settable(fmi2ValueReference vr) {
    (void)vr;
    return 0;
}

static void model_outputs(Instance *c) { c->r[VR_COUNTER] = 1.0 + floor(c->time + EPS); }

static fmi2Status model_do_step(Instance *c, fmi2Real h) {
    if (c->terminated) {
        LOG_ERROR(c, "fmi2DoStep: the simulation has ended at t = %g s.", c->time);
        return fmi2Error;
    }
    if (c->time + h < STOP_TIME - EPS) return fmi2OK; /* fmi2DoStep sets the time */
    c->time = STOP_TIME;
    c->terminated = fmi2True;
    log_message(c, fmi2OK, "logEvents", "counter reached 10 at t = 9 s: terminating");
    return fmi2Discard;
}
