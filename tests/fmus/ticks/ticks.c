/*
 * ticks.c - a test FMU (FMI 2.0 Co-Simulation) with a time event every `period` seconds:
 * ticks = floor(t / period). A step that would pass the next tick stops on it, returning
 * fmi2Discard (not terminated) with fmi2LastSuccessfulTime the tick, as an FMU that cannot
 * step over an event does; a master goes on from there. It can save and restore its state
 * (canGetAndSetFMUstate), so a var-step master can bring the others back to the tick too.
 *
 * Value references: 0 ticks (output), 1 period (parameter).
 */
#include <math.h>

#define MODEL_GUID "{8c2e4f61-3a5b-4d7c-9e0f-1a2b3c4d5e6f}"
#define N_REALS 2
#define MODEL_FMU_STATE

#include "fmi2cs.h"

#define EPS 1e-9

enum { VR_TICKS = 0, VR_PERIOD = 1 };

static void model_defaults(Instance *c) {
    c->r[VR_TICKS] = 0.0;
    c->r[VR_PERIOD] = 1.0;
}

static int model_settable(fmi2ValueReference vr) { return vr == VR_PERIOD; }

static void model_outputs(Instance *c) {
    c->r[VR_TICKS] = floor(c->time / c->r[VR_PERIOD] + EPS);
}

static fmi2Status model_do_step(Instance *c, fmi2Real h) {
    double period = c->r[VR_PERIOD], tick;
    if (!(period > 0.0)) {
        LOG_ERROR(c, "the period must be positive, not %g", period);
        return fmi2Error;
    }
    tick = (floor(c->time / period + EPS) + 1.0) * period;
    if (c->time + h <= tick + EPS) return fmi2OK; /* fmi2DoStep sets the time */
    c->time = tick;
    log_message(c, fmi2OK, "logEvents", "a tick at t = %g s: the step stops there", tick);
    return fmi2Discard;
}
