/*
 * maxstep.c - a test FMU (FMI 2.0 Co-Simulation) with a time event every `period` seconds,
 * that tells a master where it is through INTO-CPS's fmi2GetMaxStepsize (the time left to
 * the next tick) instead of refusing a step over it. ticks = floor(t / period); `missed`
 * counts the steps that went over a tick without ending on it.
 *
 * Value references: 0 ticks (output), 1 missed (output), 2 period (parameter).
 */
#include <math.h>

#define MODEL_GUID "{5b0f3d2a-7c41-4e8b-a9d6-2f1e0c3b4a59}"
#define N_REALS 3
#define MODEL_FMU_STATE

#include "fmi2cs.h"

#define EPS 1e-9

enum { VR_TICKS = 0, VR_MISSED = 1, VR_PERIOD = 2 };

static void model_defaults(Instance *c) {
    c->r[VR_TICKS] = 0.0;
    c->r[VR_MISSED] = 0.0;
    c->r[VR_PERIOD] = 1.0;
}

static int model_settable(fmi2ValueReference vr) { return vr == VR_PERIOD; }

static void model_outputs(Instance *c) {
    c->r[VR_TICKS] = floor(c->time / c->r[VR_PERIOD] + EPS);
}

static double next_tick(const Instance *c) {
    return (floor(c->time / c->r[VR_PERIOD] + EPS) + 1.0) * c->r[VR_PERIOD];
}

static fmi2Status model_do_step(Instance *c, fmi2Real h) {
    if (!(c->r[VR_PERIOD] > 0.0)) {
        LOG_ERROR(c, "the period must be positive, not %g", c->r[VR_PERIOD]);
        return fmi2Error;
    }
    if (c->time + h > next_tick(c) + EPS) c->r[VR_MISSED] += 1.0;
    return fmi2OK; /* fmi2DoStep sets the time */
}

/* INTO-CPS's extension of FMI 2 (Maestro's fmumaxstepsize constraint asks it). */
FMI2_Export fmi2Status fmi2GetMaxStepsize(fmi2Component c, fmi2Real *size) {
    Instance *inst = (Instance *)c;
    if (inst == NULL || size == NULL) return fmi2Error;
    *size = next_tick(inst) - inst->time;
    return fmi2OK;
}
