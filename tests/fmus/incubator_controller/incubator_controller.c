/*
 * incubator_controller.c - the INTO-CPS Incubator's bang-bang controller with hysteresis:
 * the heater goes on when the box's temperature T falls below T_low and off when it rises
 * above T_high; inside the band [T_low, T_high] it stays as it was. The controller samples
 * T at each communication point: a step decides from the input held over it, and the
 * decision is the output at the step's end.
 *
 * Value references: 0 heater_on (output, 0 or 1; the test FMUs have Real variables only),
 * 1 T (input), 2 T_low, 3 T_high (parameters).
 */
#define MODEL_GUID "{8a1f3c20-5b6d-4e7f-9a0b-1c2d3e4f5a02}"
#define N_REALS 4

#include "fmi2cs.h"

enum { VR_ON = 0, VR_T = 1, VR_LOW = 2, VR_HIGH = 3 };

static void model_defaults(Instance *c) {
    c->r[VR_ON] = 0.0;
    c->r[VR_T] = 21.0;
    c->r[VR_LOW] = 34.0;
    c->r[VR_HIGH] = 36.0;
}

static int model_settable(fmi2ValueReference vr) { return vr != VR_ON && vr <= VR_HIGH; }

static void model_outputs(Instance *c) { (void)c; }

static fmi2Status model_do_step(Instance *c, fmi2Real h) {
    (void)h;
    if (!(c->r[VR_LOW] < c->r[VR_HIGH])) {
        LOG_ERROR(c, "the band is empty: T_low %g is not below T_high %g", c->r[VR_LOW],
                  c->r[VR_HIGH]);
        return fmi2Error;
    }
    if (c->r[VR_T] < c->r[VR_LOW])
        c->r[VR_ON] = 1.0;
    else if (c->r[VR_T] > c->r[VR_HIGH])
        c->r[VR_ON] = 0.0;
    return fmi2OK;
}
