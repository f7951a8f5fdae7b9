/*
 * leak.c - a test FMU that leaks memory: y = u, and while u > 0 every fmi2DoStep allocates
 * mb_per_step MB, writes to every byte (so the pages are really resident) and never frees it.
 *
 * Value references: 0 u (input), 1 mb_per_step (parameter, 8), 2 y (output).
 */
#define MODEL_GUID "{5e0d9b2c-6a7f-4d18-b3c4-8f9e0a1b2c02}"
#define N_REALS 3

#include "fmi2cs.h"

enum { VR_U = 0, VR_MB_PER_STEP = 1, VR_Y = 2 };

/* Where the leaked blocks go: a volatile global, so the allocations cannot be optimised out. */
static void *volatile leaked_block;

static void model_defaults(Instance *c) {
    c->r[VR_U] = 0.0;
    c->r[VR_MB_PER_STEP] = 8.0;
    c->r[VR_Y] = 0.0;
}

static int model_settable(fmi2ValueReference vr) { return vr == VR_U || vr == VR_MB_PER_STEP; }

static void model_outputs(Instance *c) { c->r[VR_Y] = c->r[VR_U]; }

static fmi2Status model_do_step(Instance *c, fmi2Real h) {
    (void)h;
    if (c->r[VR_U] > 0.0 && c->r[VR_MB_PER_STEP] > 0.0) {
        size_t size = (size_t)(c->r[VR_MB_PER_STEP] * 1024.0 * 1024.0);
        void *block = malloc(size);
        if (block == NULL) {
            LOG_ERROR(c, "out of memory after leaking on purpose");
            return fmi2Fatal;
        }
        memset(block, 0xA5, size); /* not 0: malloc + memset(0) may become calloc */
        leaked_block = block;
    }
    model_outputs(c);
    return fmi2OK;
}
