/*
 * msd_spring.c - the second half of the two-mass spring-damper split into two FMUs (the
 * INTO-CPS example's msd2): mass m2 tied to the wall by spring c2 and damper d2, and to the
 * first mass (its position x1 and velocity v1 as inputs) by the coupling spring cc and damper dc (the INTO-CPS example's names).
 * Its output fk is the coupling force on the first mass, a direct function of the inputs:
 *     fk = cc (x2 - x1) + dc (v2 - v1)
 *     x2' = v2,  v2' = (-fk - c2 x2 - d2 v2) / m2
 * x1 and v1 are held constant over a communication step (RK4 substeps, as msd_mass).
 *
 * Value references: 0 x2, 1 v2 (outputs; their start values may be set), 2 fk (output),
 * 3 x1, 4 v1 (inputs), 5 m2, 6 c2, 7 d2, 8 cc, 9 dc (parameters).
 */
#define MODEL_GUID "{5d0c2a51-7f3e-4b8a-9e21-3c4d5e6f7a02}"
#define N_REALS 10

#define MODEL_FMU_STATE /* canGetAndSetFMUstate: the var-step master rolls back */
#include "fmi2cs.h"

enum {
    VR_X = 0, VR_V = 1, VR_FK = 2, VR_X1 = 3, VR_V1 = 4,
    VR_M = 5, VR_SPRING = 6, VR_DAMP = 7, VR_CC = 8, VR_DC = 9
};
#define SUBSTEPS 16

static void model_defaults(Instance *c) {
    c->r[VR_X] = 0.0;
    c->r[VR_V] = 0.0;
    c->r[VR_FK] = 0.0;
    c->r[VR_X1] = 0.0;
    c->r[VR_V1] = 0.0;
    c->r[VR_M] = 1.0;
    c->r[VR_SPRING] = 1.0;
    c->r[VR_DAMP] = 0.0;
    c->r[VR_CC] = 1.0;
    c->r[VR_DC] = 0.0;
}

static int model_settable(fmi2ValueReference vr) { return vr != VR_FK && vr <= VR_DC; }

static double force(const Instance *c, double x, double v) {
    return c->r[VR_CC] * (x - c->r[VR_X1]) + c->r[VR_DC] * (v - c->r[VR_V1]);
}

static void model_outputs(Instance *c) { c->r[VR_FK] = force(c, c->r[VR_X], c->r[VR_V]); }

static double accel(const Instance *c, double x, double v) {
    return (-force(c, x, v) - c->r[VR_SPRING] * x - c->r[VR_DAMP] * v) / c->r[VR_M];
}

static fmi2Status model_do_step(Instance *c, fmi2Real h) {
    double x = c->r[VR_X], v = c->r[VR_V], dt = h / SUBSTEPS;
    int i;
    if (!(c->r[VR_M] > 0.0)) {
        LOG_ERROR(c, "the mass m2 must be positive, not %g", c->r[VR_M]);
        return fmi2Error;
    }
    for (i = 0; i < SUBSTEPS; i++) {
        double k1x = v, k1v = accel(c, x, v);
        double k2x = v + 0.5 * dt * k1v, k2v = accel(c, x + 0.5 * dt * k1x, k2x);
        double k3x = v + 0.5 * dt * k2v, k3v = accel(c, x + 0.5 * dt * k2x, k3x);
        double k4x = v + dt * k3v, k4v = accel(c, x + dt * k3x, k4x);
        x += dt / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
        v += dt / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
    }
    c->r[VR_X] = x;
    c->r[VR_V] = v;
    model_outputs(c);
    return fmi2OK;
}
