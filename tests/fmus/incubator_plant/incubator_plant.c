/*
 * incubator_plant.c - the heated box of the INTO-CPS Incubator (its "four parameter model"):
 * the air in the box and the heater are two lumped thermal masses; the heater, when on,
 * takes V I watts, warms the air through G_heater, and the air loses heat to the room
 * through G_box:
 *     C_air    T'        = G_heater (T_heater - T) - G_box (T - T_room)
 *     C_heater T_heater' = V I heater_on - G_heater (T_heater - T)
 * heater_on (0 or 1; the test FMUs have Real variables only) and T_room are held over a
 * communication step, integrated with RK4 substeps. The parameters are the Incubator's
 * fitted ones (C_air 145.69 J/K, G_box 0.79 W/K, C_heater 243.45 J/K, G_heater 0.87 W/K,
 * 12.15 V, 1.53 A).
 *
 * Value references: 0 T, 1 T_heater (outputs; their start values may be set),
 * 2 heater_on, 3 T_room (inputs), 4 C_air, 5 G_box, 6 C_heater, 7 G_heater, 8 V_heater,
 * 9 I_heater (parameters).
 */
#define MODEL_GUID "{8a1f3c20-5b6d-4e7f-9a0b-1c2d3e4f5a01}"
#define N_REALS 10

#include "fmi2cs.h"

enum {
    VR_T = 0, VR_TH = 1, VR_ON = 2, VR_ROOM = 3,
    VR_C_AIR = 4, VR_G_BOX = 5, VR_C_HEATER = 6, VR_G_HEATER = 7, VR_V = 8, VR_I = 9
};
#define SUBSTEPS 8

static void model_defaults(Instance *c) {
    c->r[VR_T] = 21.0;
    c->r[VR_TH] = 21.0;
    c->r[VR_ON] = 0.0;
    c->r[VR_ROOM] = 21.0;
    c->r[VR_C_AIR] = 145.69;
    c->r[VR_G_BOX] = 0.79;
    c->r[VR_C_HEATER] = 243.45;
    c->r[VR_G_HEATER] = 0.87;
    c->r[VR_V] = 12.15;
    c->r[VR_I] = 1.53;
}

static int model_settable(fmi2ValueReference vr) { return vr <= VR_I; }

static void model_outputs(Instance *c) { (void)c; }

static void derivatives(const Instance *c, double t, double th, double *dt, double *dth) {
    double to_air = c->r[VR_G_HEATER] * (th - t);
    double power = c->r[VR_ON] > 0.5 ? c->r[VR_V] * c->r[VR_I] : 0.0;
    *dt = (to_air - c->r[VR_G_BOX] * (t - c->r[VR_ROOM])) / c->r[VR_C_AIR];
    *dth = (power - to_air) / c->r[VR_C_HEATER];
}

static fmi2Status model_do_step(Instance *c, fmi2Real h) {
    double t = c->r[VR_T], th = c->r[VR_TH], dt = h / SUBSTEPS;
    double k1, l1, k2, l2, k3, l3, k4, l4;
    int i;
    if (!(c->r[VR_C_AIR] > 0.0) || !(c->r[VR_C_HEATER] > 0.0)) {
        LOG_ERROR(c, "the heat capacities must be positive, not %g and %g", c->r[VR_C_AIR],
                  c->r[VR_C_HEATER]);
        return fmi2Error;
    }
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
    return fmi2OK;
}
