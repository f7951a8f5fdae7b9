/*
 * chain_mass.c - one mass of a chain of masses, each tied to its left and right neighbour
 * by a spring and a damper; instances of this FMU connected in a row make the chain.
 * The neighbours' positions and velocities are inputs (held over a communication step):
 *     x' = v,  m v' = kl (xl - x) + dl (vl - v) + kr (xr - x) + dr (vr - v)
 * An end of the chain leaves its inputs unconnected: at their start value 0 they are a
 * wall. Positions are displacements from rest, integrated with RK4 substeps fine enough
 * that the coupling dominates a co-simulation's error.
 *
 * Value references: 0 x, 1 v (outputs; their start values may be set), 2 xl, 3 vl, 4 xr,
 * 5 vr (inputs), 6 m, 7 kl, 8 dl, 9 kr, 10 dr (parameters).
 */
#define MODEL_GUID "{3e9b7d41-2c5a-4f68-8b1d-6a7c8e9f0b01}"
#define N_REALS 11

#include "fmi2cs.h"

enum {
    VR_X = 0, VR_V = 1, VR_XL = 2, VR_VL = 3, VR_XR = 4, VR_VR = 5,
    VR_M = 6, VR_KL = 7, VR_DL = 8, VR_KR = 9, VR_DR = 10
};
#define SUBSTEPS 16

static void model_defaults(Instance *c) {
    int i;
    for (i = 0; i < N_REALS; i++) c->r[i] = 0.0;
    c->r[VR_M] = 1.0;
    c->r[VR_KL] = 1.0;
    c->r[VR_KR] = 1.0;
}

static int model_settable(fmi2ValueReference vr) { return vr <= VR_DR; }

static void model_outputs(Instance *c) { (void)c; }

static double accel(const Instance *c, double x, double v) {
    const double *r = c->r;
    double f = r[VR_KL] * (r[VR_XL] - x) + r[VR_DL] * (r[VR_VL] - v) + r[VR_KR] * (r[VR_XR] - x) +
               r[VR_DR] * (r[VR_VR] - v);
    return f / r[VR_M];
}

static fmi2Status model_do_step(Instance *c, fmi2Real h) {
    double x = c->r[VR_X], v = c->r[VR_V], dt = h / SUBSTEPS;
    int i;
    if (!(c->r[VR_M] > 0.0)) {
        LOG_ERROR(c, "the mass m must be positive, not %g", c->r[VR_M]);
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
