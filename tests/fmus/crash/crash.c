/*
 * crash.c - a test FMU that really crashes: y = 2 u, but fmi2DoStep with u > threshold writes
 * through a NULL pointer, so the process dies with SIGSEGV. Both the pointer and what it points
 * to are volatile: the compiler cannot know the pointer is NULL (so no trap instruction, which
 * would be SIGILL) and cannot drop the write (with only the pointer volatile, gcc -O2 does).
 *
 * Value references: 0 u (input), 1 threshold (parameter, 100), 2 y (output).
 */
#define MODEL_GUID "{c7a1e2d0-0b5e-4f3a-9c61-1d2e3f4a5b01}"
#define N_REALS 3

#include "fmi2cs.h"

enum { VR_U = 0, VR_THRESHOLD = 1, VR_Y = 2 };

static void model_defaults(Instance *c) {
    c->r[VR_U] = 0.0;
    c->r[VR_THRESHOLD] = 100.0;
    c->r[VR_Y] = 0.0;
}

static int model_settable(fmi2ValueReference vr) { return vr == VR_U || vr == VR_THRESHOLD; }

static void model_outputs(Instance *c) { c->r[VR_Y] = 2.0 * c->r[VR_U]; }

static fmi2Status model_do_step(Instance *c, fmi2Real h) {
    (void)h;
    if (c->r[VR_U] > c->r[VR_THRESHOLD]) {
        volatile int *volatile nowhere = NULL;
        *nowhere = 42; /* SIGSEGV */
    }
    model_outputs(c);
    return fmi2OK;
}
