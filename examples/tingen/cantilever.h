/*
 * cantilever.h - the physics of the "Tingen" rig, shared by the FMI 2.0 and FMI 3.0 FMUs.
 *
 * A vertical steel cantilever (NTNU thesis, table 3.1: L = 0.300 m, I = 2.1 mm^4, E = 210000
 * N/mm^2) with a tip mass, loaded by a horizontal force F at the tip, reduced to its first
 * bending mode: a single-degree-of-freedom oscillator of the tip deflection w,
 *
 *     m_eff * w'' + c * w' + k * w = F
 *
 *     k     = 3 E I / L^3                                  static tip stiffness
 *     m_eff = tip_mass + 0.2357 * beam_mass_per_length * L  Rayleigh's effective mass
 *     c     = 2 * zeta * sqrt(k * m_eff)                    viscous damping, ratio zeta
 *
 * Outputs: the tip angle theta = 3 w / (2 L) (so in equilibrium theta = F L^2 / (2 E I), the
 * thesis's eq. 4.1 inverted), the bending stress at the root sigma = M c_fiber / I with the
 * root moment M = k w L, and the tip deflection w itself.
 *
 * Everything here is header-only (static inline functions), so each FMU compiles it into its own
 * binary. Plain C99, no allocation, no global state.
 */
#ifndef TINGEN_CANTILEVER_H
#define TINGEN_CANTILEVER_H

#include <math.h>
#include <stddef.h>

/* Rayleigh's factor: the share of a uniform cantilever's mass that moves with the tip. */
#define CANTILEVER_RAYLEIGH_FACTOR 0.2357

/* Value references, the same in the FMI 2.0 and FMI 3.0 model descriptions (FMI 3.0 adds
 * VR_TIME = 0 for its independent variable). */
enum {
    VR_F = 1,
    VR_THETA = 2,
    VR_SIGMA = 3,
    VR_W = 4,
    VR_V = 5,
    VR_DER_W = 6,
    VR_DER_V = 7,
    VR_L = 10,
    VR_I = 11,
    VR_E = 12,
    VR_TIP_MASS = 13,
    VR_BEAM_MASS_PER_LENGTH = 14,
    VR_ZETA = 15,
    VR_C_FIBER = 16
};

typedef struct {
    double L;                    /* free length [m] */
    double I;                    /* area moment of inertia about the bending axis [m^4] */
    double E;                    /* Young's modulus [Pa] */
    double tip_mass;             /* mass at the tip [kg] */
    double beam_mass_per_length; /* mass of the beam per metre [kg/m] */
    double zeta;                 /* damping ratio [1] */
    double c_fiber;              /* distance of the outer fibre from the neutral axis [m] */
} CantileverParams;

typedef struct {
    double w; /* tip deflection [m] */
    double v; /* tip velocity [m/s] */
} CantileverState;

/* The thesis's rig. tip_mass = 0: the thesis's input force is the whole tip load computed from
 * the measured angle, tip mass included, so the demo leaves it at 0. 0.196 kg/m is a
 * 25 mm x 1 mm steel strip (7850 kg/m^3). */
static inline void cantilever_default_params(CantileverParams *p) {
    p->L = 0.300;
    p->I = 2.1e-12;
    p->E = 210e9;
    p->tip_mass = 0.0;
    p->beam_mass_per_length = 0.196;
    p->zeta = 0.02;
    p->c_fiber = 0.0005;
}

static inline double cantilever_stiffness(const CantileverParams *p) {
    return 3.0 * p->E * p->I / (p->L * p->L * p->L);
}

static inline double cantilever_effective_mass(const CantileverParams *p) {
    return p->tip_mass + CANTILEVER_RAYLEIGH_FACTOR * p->beam_mass_per_length * p->L;
}

static inline double cantilever_damping(const CantileverParams *p) {
    return 2.0 * p->zeta * sqrt(cantilever_stiffness(p) * cantilever_effective_mass(p));
}

/* NULL when the parameters describe a physical beam, otherwise what is wrong with them. */
static inline const char *cantilever_check(const CantileverParams *p) {
    if (!(p->L > 0.0) || !isfinite(p->L)) return "L must be a positive length";
    if (!(p->I > 0.0) || !isfinite(p->I)) return "I must be positive";
    if (!(p->E > 0.0) || !isfinite(p->E)) return "E must be positive";
    if (!(p->tip_mass >= 0.0) || !isfinite(p->tip_mass)) return "tip_mass must not be negative";
    if (!(p->beam_mass_per_length >= 0.0) || !isfinite(p->beam_mass_per_length))
        return "beam_mass_per_length must not be negative";
    if (!(cantilever_effective_mass(p) > 0.0))
        return "the effective mass tip_mass + 0.2357 * beam_mass_per_length * L must be positive";
    if (!(p->zeta >= 0.0) || !isfinite(p->zeta)) return "zeta must not be negative";
    if (!(p->c_fiber >= 0.0) || !isfinite(p->c_fiber)) return "c_fiber must not be negative";
    return NULL;
}

/* w'' for the state (w, v) under the force F. */
static inline double cantilever_acceleration(const CantileverParams *p, double F, double w,
                                             double v) {
    return (F - cantilever_damping(p) * v - cantilever_stiffness(p) * w)
           / cantilever_effective_mass(p);
}

static inline double cantilever_theta(const CantileverParams *p, double w) {
    return 3.0 * w / (2.0 * p->L);
}

static inline double cantilever_sigma(const CantileverParams *p, double w) {
    double moment = cantilever_stiffness(p) * w * p->L;
    return moment * p->c_fiber / p->I;
}


/* The value of a model variable by its value reference; 0 when there is no such variable. */
static inline int cantilever_get(const CantileverParams *p, double F, const CantileverState *x,
                                 unsigned vr, double *value) {
    switch (vr) {
        case VR_F: *value = F; return 1;
        case VR_THETA: *value = cantilever_theta(p, x->w); return 1;
        case VR_SIGMA: *value = cantilever_sigma(p, x->w); return 1;
        case VR_W: *value = x->w; return 1;
        case VR_V: *value = x->v; return 1;
        case VR_DER_W: *value = x->v; return 1;
        case VR_DER_V: *value = cantilever_acceleration(p, F, x->w, x->v); return 1;
        case VR_L: *value = p->L; return 1;
        case VR_I: *value = p->I; return 1;
        case VR_E: *value = p->E; return 1;
        case VR_TIP_MASS: *value = p->tip_mass; return 1;
        case VR_BEAM_MASS_PER_LENGTH: *value = p->beam_mass_per_length; return 1;
        case VR_ZETA: *value = p->zeta; return 1;
        case VR_C_FIBER: *value = p->c_fiber; return 1;
        default: return 0;
    }
}

/*
 * Advance the state by h seconds with F held constant: the exact solution, not an integrator,
 * so the result does not depend on how a simulation is cut into steps.
 *
 * With x = w - F/k, omega_n = sqrt(k/m_eff) and s = zeta * omega_n the free response is
 *
 *     x(h) = C x0 + S (v0 + s x0)
 *     v(h) = C v0 - S (s v0 + omega_n^2 x0)
 *
 * where, with d = omega_n sqrt(|1 - zeta^2|),
 *     under-damped  (zeta < 1): C = e^(-s h) cos(d h),  S = e^(-s h) sin(d h) / d
 *     critically    (zeta = 1): C = e^(-s h),           S = e^(-s h) h
 *     over-damped   (zeta > 1): C = e^(-s h) cosh(d h), S = e^(-s h) sinh(d h) / d
 * (differentiate x to get v; s^2 +- d^2 = omega_n^2 makes the pairs consistent).
 */
static inline void cantilever_step(const CantileverParams *p, double F, double h,
                                   CantileverState *st) {
    const double k = cantilever_stiffness(p);
    const double m = cantilever_effective_mass(p);
    const double wn = sqrt(k / m);
    const double s = p->zeta * wn;
    const double w_eq = F / k;
    const double x0 = st->w - w_eq;
    const double v0 = st->v;
    double C, S;

    if (!(h > 0.0)) return;

    if (p->zeta < 1.0) {
        const double d = wn * sqrt((1.0 - p->zeta) * (1.0 + p->zeta));
        const double decay = exp(-s * h);
        C = decay * cos(d * h);
        S = d > 0.0 ? decay * sin(d * h) / d : decay * h;
    } else if (p->zeta == 1.0) {
        const double decay = exp(-s * h);
        C = decay;
        S = decay * h;
    } else {
        const double d = wn * sqrt((p->zeta - 1.0) * (p->zeta + 1.0));
        if (d * h < 20.0) {
            const double decay = exp(-s * h);
            C = decay * cosh(d * h);
            S = decay * sinh(d * h) / d;
        } else {
            /* Split cosh/sinh into exponentials so e^(d h) cannot overflow; s - d is computed
             * as omega_n^2 / (s + d) to avoid cancellation when zeta is large. */
            const double slow = exp(-(wn * wn / (s + d)) * h);
            const double fast = exp(-(s + d) * h);
            C = 0.5 * (slow + fast);
            S = 0.5 * (slow - fast) / d;
        }
    }

    st->w = w_eq + C * x0 + S * (v0 + s * x0);
    st->v = C * v0 - S * (s * v0 + wn * wn * x0);
}

#endif /* TINGEN_CANTILEVER_H */
