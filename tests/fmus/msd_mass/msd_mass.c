/*
 * msd_mass.c - the first half of the two-mass spring-damper split into two FMUs (the INTO-CPS
 * mass-spring-damper example's msd1): mass m1 tied to the wall by spring c1 and damper d1 (the INTO-CPS example's names),
 * pushed by the coupling force fk that the other FMU (msd_spring) computes:
 *     x1' = v1,  v1' = (fk - c1 x1 - d1 v1) / m1
 * fk is held constant over a communication step, which is integrated with RK4 substeps fine
 * enough that the coupling, not this integrator, dominates a co-simulation's error.
 *
 * Value references: 0 x1, 1 v1 (outputs; their start values may be set), 2 fk (input),
 * 3 m1, 4 c1, 5 d1 (parameters).
 */
#define MODEL_GUID "{5d0c2a51-7f3e-4b8a-9e21-3c4d5e6f7a01}"
#define N_REALS 6

#define MODEL_FMU_STATE /* canGetAndSetFMUstate: the var-step master rolls back */
#include "fmi2cs.h"

enum { VR_X = 0, VR_V = 1, VR_FK = 2, VR_M = 3, VR_SPRING = 4, VR_DAMP = 5 };
#define SUBSTEPS 16

static void model_defaults(Instance *c) {
    c->r[VR_X] = 1.0;
    c->r[VR_V] = 0.0;
    c->r[VR_FK] = 0.0;
    c->r[VR_M] = 1.0;
    c->r[VR_SPRING] = 1.0;
    c->r[VR_DAMP] = 0.0;
}

static int model_settable(fmi2ValueReference vr) { return vr <= VR_DAMP; }

static void model_outputs(Instance *c) { (void)c; }

static double accel(const Instance *c, double x, double v) {
    return (c->r[VR_FK] - c->r[VR_SPRING] * x - c->r[VR_DAMP] * v) / c->r[VR_M];
}

static fmi2Status model_do_step(Instance *c, fmi2Real h) {
    double x = c->r[VR_X], v = c->r[VR_V], dt = h / SUBSTEPS;
    int i;
    if (!(c->r[VR_M] > 0.0)) {
        LOG_ERROR(c, "the mass m1 must be positive, not %g", c->r[VR_M]);
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
    return fmi2OK;
}
