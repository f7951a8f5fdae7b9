/*
 * status.c - a test FMU that reports errors through the FMI status: y = u, but fmi2DoStep
 * returns fmi2Error (and logs "negative input u=<value> is not allowed" in the category
 * "logStatusError") when u < 0, and fmi2Fatal when u is NaN. An instance whose name starts
 * with "refuse" is not made: fmi2Instantiate says why only at the info level (fmi2OK, logged
 * only with logging on, as a Python FMU that cannot import a module may) and returns NULL.
 *
 * Value references: 0 u (input), 1 y (output).
 */
#include <math.h>
#include <string.h>

#define MODEL_GUID "{0f3b7c6d-2e1a-4b9c-8d7e-6a5b4c3d2e03}"
#define N_REALS 2
#define MODEL_REFUSE_INSTANCE

#include "fmi2cs.h"

enum { VR_U = 0, VR_Y = 1 };

static void model_defaults(Instance *c) {
    c->r[VR_U] = 0.0;
    c->r[VR_Y] = 0.0;
}

static int model_settable(fmi2ValueReference vr) { return vr == VR_U; }

static void model_outputs(Instance *c) { c->r[VR_Y] = c->r[VR_U]; }

static fmi2Status model_do_step(Instance *c, fmi2Real h) {
    double u = c->r[VR_U];
    (void)h;
    if (isnan(u)) {
        log_message(c, fmi2Fatal, "logStatusFatal", "input u is NaN");
        return fmi2Fatal;
    }
    if (u < 0.0) {
        log_message(c, fmi2Error, "logStatusError", "negative input u=%g is not allowed", u);
        return fmi2Error;
    }
    model_outputs(c);
    return fmi2OK;
}

static int model_refuse(Instance *probe) {
    if (strncmp(probe->name, "refuse", 6) != 0) return 0;
    log_message(probe, fmi2OK, "logAll", "cannot import module 'twinlink_missing_module'");
    return 1;
}
