/*
 * incubator_kalman.c - the INTO-CPS Incubator's Kalman filter: it estimates the box's air
 * temperature T and the heater's temperature T_heater (which nobody measures) from the
 * measured air temperature and the heater's on/off command, with the plant's own model
 * (incubator_plant.c):
 *     x = [T, T_heater],  x' = A x + b(u),  y = T
 * A step from t to t + h first corrects the estimate with the measurement y(t) (gain
 * K = P H' / (H P H' + R)), then predicts it to t + h with u(t): the mean with the same RK4
 * substeps as the plant, the covariance P = F P F' + Q h with F = I + A h + (A h)^2 / 2.
 * The outputs are the predicted x(t + h). The covariance starts at P0 I on the first step.
 *
 * Value references: 0 T_est, 1 T_heater_est (outputs; their start values are the initial
 * estimate), 2 T_measured, 3 heater_on, 4 T_room (inputs), 5 C_air, 6 G_box, 7 C_heater,
 * 8 G_heater, 9 V_heater, 10 I_heater (the model's parameters), 11 Q_T, 12 Q_heater
 * (process noise, per second), 13 R (measurement noise), 14 P0 (parameters); 15-17 the
 * covariance P00, P01, P11 and 18 whether it was started (internal, not in the model
 * description).
 */
#define MODEL_GUID "{8a1f3c20-5b6d-4e7f-9a0b-1c2d3e4f5a03}"
#define N_REALS 19

#include "fmi2cs.h"

enum {
    VR_T = 0, VR_TH = 1, VR_Y = 2, VR_ON = 3, VR_ROOM = 4,
    VR_C_AIR = 5, VR_G_BOX = 6, VR_C_HEATER = 7, VR_G_HEATER = 8, VR_V = 9, VR_I = 10,
    VR_Q_T = 11, VR_Q_H = 12, VR_R = 13, VR_P0 = 14,
    P00 = 15, P01 = 16, P11 = 17, STARTED = 18
};
#define SUBSTEPS 8

static void model_defaults(Instance *c) {
    c->r[VR_T] = 21.0;
    c->r[VR_TH] = 21.0;
    c->r[VR_Y] = 21.0;
    c->r[VR_ON] = 0.0;
    c->r[VR_ROOM] = 21.0;
    c->r[VR_C_AIR] = 145.69;
    c->r[VR_G_BOX] = 0.79;
    c->r[VR_C_HEATER] = 243.45;
    c->r[VR_G_HEATER] = 0.87;
    c->r[VR_V] = 12.15;
    c->r[VR_I] = 1.53;
    c->r[VR_Q_T] = 1e-4;
    c->r[VR_Q_H] = 1e-3;
    c->r[VR_R] = 1e-2;
    c->r[VR_P0] = 100.0;
    c->r[P00] = c->r[P01] = c->r[P11] = 0.0;
    c->r[STARTED] = 0.0;
}

static int model_settable(fmi2ValueReference vr) { return vr <= VR_P0; }

static void model_outputs(Instance *c) { (void)c; }

static void derivatives(const Instance *c, double t, double th, double *dt, double *dth) {
    double to_air = c->r[VR_G_HEATER] * (th - t);
    double power = c->r[VR_ON] > 0.5 ? c->r[VR_V] * c->r[VR_I] : 0.0;
    *dt = (to_air - c->r[VR_G_BOX] * (t - c->r[VR_ROOM])) / c->r[VR_C_AIR];
    *dth = (power - to_air) / c->r[VR_C_HEATER];
}

static void correct(Instance *c) {
    double s = c->r[P00] + c->r[VR_R];
    double k0 = c->r[P00] / s, k1 = c->r[P01] / s, innovation = c->r[VR_Y] - c->r[VR_T];
    c->r[VR_T] += k0 * innovation;
    c->r[VR_TH] += k1 * innovation;
    c->r[P11] -= k1 * c->r[P01];
    c->r[P01] -= k0 * c->r[P01];
    c->r[P00] -= k0 * c->r[P00];
}

static void predict_mean(Instance *c, double h) {
    double t = c->r[VR_T], th = c->r[VR_TH], dt = h / SUBSTEPS;
    double k1, l1, k2, l2, k3, l3, k4, l4;
    int i;
    for (i = 0; i < SUBSTEPS; i++) {
        derivatives(c, t, th, &k1, &l1);
        derivatives(c, t + 0.5 * dt * k1, th + 0.5 * dt * l1, &k2, &l2);
        derivatives(c, t + 0.5 * dt * k2, th + 0.5 * dt * l2, &k3, &l3);
        derivatives(c, t + dt * k3, th + dt * l3, &k4, &l4);
        t += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
        th += dt / 6.0 * (l1 + 2.0 * l2 + 2.0 * l3 + l4);
    }
    c->r[VR_T] = t;
    c->r[VR_TH] = th;
}

static void predict_covariance(Instance *c, double h) {
    double gh = c->r[VR_G_HEATER];
    /* A h, then F = I + A h + (A h)^2 / 2 */
    double a00 = -(gh + c->r[VR_G_BOX]) / c->r[VR_C_AIR] * h, a01 = gh / c->r[VR_C_AIR] * h;
    double a10 = gh / c->r[VR_C_HEATER] * h, a11 = -gh / c->r[VR_C_HEATER] * h;
    double f00 = 1.0 + a00 + 0.5 * (a00 * a00 + a01 * a10);
    double f01 = a01 + 0.5 * (a00 * a01 + a01 * a11);
    double f10 = a10 + 0.5 * (a10 * a00 + a11 * a10);
    double f11 = 1.0 + a11 + 0.5 * (a10 * a01 + a11 * a11);
    double p00 = c->r[P00], p01 = c->r[P01], p11 = c->r[P11];
    /* F P */
    double m00 = f00 * p00 + f01 * p01, m01 = f00 * p01 + f01 * p11;
    double m10 = f10 * p00 + f11 * p01, m11 = f10 * p01 + f11 * p11;
    /* (F P) F' + Q h */
    c->r[P00] = m00 * f00 + m01 * f01 + c->r[VR_Q_T] * h;
    c->r[P01] = m00 * f10 + m01 * f11;
    c->r[P11] = m10 * f10 + m11 * f11 + c->r[VR_Q_H] * h;
}

static fmi2Status model_do_step(Instance *c, fmi2Real h) {
    if (!(c->r[VR_C_AIR] > 0.0) || !(c->r[VR_C_HEATER] > 0.0) || !(c->r[VR_R] > 0.0)) {
        LOG_ERROR(c, "C_air, C_heater and R must be positive, not %g, %g and %g",
                  c->r[VR_C_AIR], c->r[VR_C_HEATER], c->r[VR_R]);
        return fmi2Error;
    }
    if (c->r[STARTED] == 0.0) {
        c->r[P00] = c->r[P11] = c->r[VR_P0];
        c->r[P01] = 0.0;
        c->r[STARTED] = 1.0;
    }
    correct(c);
    predict_mean(c, h);
    predict_covariance(c, h);
    return fmi2OK;
}
