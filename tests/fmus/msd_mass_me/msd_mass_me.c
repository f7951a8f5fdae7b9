/*
 * msd_mass_me.c - msd_mass (tests/fmus/msd_mass) as an FMI 2.0 Model Exchange FMU: the same
 * mass m1 on spring c1 and damper d1 pushed by the coupling force fk, but the importer's
 * solver integrates
 *     x1' = v1,  v1' = (fk - c1 x1 - d1 v1) / m1
 * No events. The FMU state (fmi2GetFMUstate / fmi2SetFMUstate) is supported, so an importer
 * can roll a step back. Every other fmi2 function FMPy loads is here; Co-Simulation ones
 * refuse with fmi2Error.
 *
 * Value references: 0 x1, 1 v1 (outputs and states), 2 fk (input), 3 m1, 4 c1, 5 d1
 * (parameters), 6 der(x1), 7 der(v1).
 */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

#define MODEL_GUID "{5d0c2a51-7f3e-4b8a-9e21-3c4d5e6f7a03}"
#define N_REALS 8
enum { VR_X = 0, VR_V = 1, VR_FK = 2, VR_M = 3, VR_SPRING = 4, VR_DAMP = 5, VR_DX = 6, VR_DV = 7 };

typedef struct {
    char *name;
    fmi2CallbackFunctions cb;
    fmi2Real time;
    fmi2Real r[N_REALS];
} Instance;

typedef struct {
    fmi2Real time;
    fmi2Real r[N_REALS];
} State;

static void log_error(const Instance *c, const char *fmt, const char *arg) {
    char text[256];
    if (c == NULL || c->cb.logger == NULL) return;
    snprintf(text, sizeof text, fmt, arg);
    c->cb.logger(c->cb.componentEnvironment, c->name, fmi2Error, "logStatusError", "%s", text);
}

static fmi2Status refuse(fmi2Component c, const char *function) {
    log_error((Instance *)c, "%s is not supported by this FMU.", function);
    return fmi2Error;
}

static void derivatives(Instance *c) {
    double *r = c->r;
    r[VR_DX] = r[VR_V];
    r[VR_DV] = (r[VR_FK] - r[VR_SPRING] * r[VR_X] - r[VR_DAMP] * r[VR_V]) / r[VR_M];
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n, const fmi2String k[]) {
    (void)on, (void)n, (void)k;
    return c == NULL ? fmi2Error : fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String name, fmi2Type type, fmi2String guid, fmi2String res,
                              const fmi2CallbackFunctions *f, fmi2Boolean visible,
                              fmi2Boolean loggingOn) {
    Instance *c;
    (void)res, (void)visible, (void)loggingOn;
    if (f == NULL || name == NULL || type != fmi2ModelExchange) return NULL;
    if (guid == NULL || strcmp(guid, MODEL_GUID) != 0) return NULL;
    c = (Instance *)calloc(1, sizeof(Instance));
    if (c == NULL) return NULL;
    c->name = (char *)malloc(strlen(name) + 1);
    if (c->name == NULL) {
        free(c);
        return NULL;
    }
    strcpy(c->name, name);
    c->cb = *f;
    c->r[VR_X] = 1.0;
    c->r[VR_M] = 1.0;
    c->r[VR_SPRING] = 1.0;
    return c;
}

void fmi2FreeInstance(fmi2Component c) {
    if (c == NULL) return;
    free(((Instance *)c)->name);
    free(c);
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean td, fmi2Real tol, fmi2Real t0,
                               fmi2Boolean sd, fmi2Real t1) {
    (void)td, (void)tol, (void)sd, (void)t1;
    if (c == NULL) return fmi2Error;
    ((Instance *)c)->time = t0;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) { return c ? fmi2OK : fmi2Error; }

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    Instance *inst = (Instance *)c;
    if (inst == NULL) return fmi2Error;
    if (!(inst->r[VR_M] > 0.0)) {
        log_error(inst, "the mass m1 must be positive%s", "");
        return fmi2Error;
    }
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component c) { return c ? fmi2OK : fmi2Error; }
fmi2Status fmi2Reset(fmi2Component c) { return refuse(c, "fmi2Reset"); }

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    Instance *inst = (Instance *)c;
    size_t i;
    if (inst == NULL) return fmi2Error;
    derivatives(inst);
    for (i = 0; i < n; i++) {
        if (vr[i] >= N_REALS) return refuse(c, "fmi2GetReal of an unknown value reference");
        v[i] = inst->r[vr[i]];
    }
    return fmi2OK;
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                       const fmi2Real v[]) {
    Instance *inst = (Instance *)c;
    size_t i;
    if (inst == NULL) return fmi2Error;
    for (i = 0; i < n; i++) {
        if (vr[i] > VR_DAMP) return refuse(c, "fmi2SetReal of this value reference");
        inst->r[vr[i]] = v[i];
    }
    return fmi2OK;
}

#define NO_VARIABLES(fn, T)                                                                    \
    fmi2Status fn(fmi2Component c, const fmi2ValueReference vr[], size_t n, T v[]) {          \
        (void)vr, (void)v;                                                                     \
        return n == 0 ? fmi2OK : refuse(c, #fn " (this model has only Real variables)");     \
    }
NO_VARIABLES(fmi2GetInteger, fmi2Integer)
NO_VARIABLES(fmi2GetBoolean, fmi2Boolean)
NO_VARIABLES(fmi2GetString, fmi2String)
NO_VARIABLES(fmi2SetInteger, const fmi2Integer)
NO_VARIABLES(fmi2SetBoolean, const fmi2Boolean)
NO_VARIABLES(fmi2SetString, const fmi2String)

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s) {
    Instance *inst = (Instance *)c;
    State *state;
    if (inst == NULL || s == NULL) return fmi2Error;
    state = *s != NULL ? (State *)*s : (State *)malloc(sizeof(State));
    if (state == NULL) return fmi2Error;
    state->time = inst->time;
    memcpy(state->r, inst->r, sizeof state->r);
    *s = state;
    return fmi2OK;
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s) {
    Instance *inst = (Instance *)c;
    const State *state = (const State *)s;
    if (inst == NULL || state == NULL) return fmi2Error;
    inst->time = state->time;
    memcpy(inst->r, state->r, sizeof inst->r);
    return fmi2OK;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s) {
    if (c == NULL || s == NULL) return fmi2Error;
    free(*s);
    *s = NULL;
    return fmi2OK;
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *size) {
    (void)s, (void)size;
    return refuse(c, "fmi2SerializedFMUstateSize");
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte b[], size_t n) {
    (void)s, (void)b, (void)n;
    return refuse(c, "fmi2SerializeFMUstate");
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte b[], size_t n,
                                   fmi2FMUstate *s) {
    (void)b, (void)n, (void)s;
    return refuse(c, "fmi2DeSerializeFMUstate");
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference u[],
                                        size_t nu, const fmi2ValueReference k[], size_t nk,
                                        const fmi2Real dk[], fmi2Real du[]) {
    (void)u, (void)nu, (void)k, (void)nk, (void)dk, (void)du;
    return refuse(c, "fmi2GetDirectionalDerivative");
}

/* Model Exchange */

fmi2Status fmi2EnterEventMode(fmi2Component c) { return c ? fmi2OK : fmi2Error; }

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *e) {
    if (c == NULL || e == NULL) return fmi2Error;
    memset(e, 0, sizeof *e);
    return fmi2OK;
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) { return c ? fmi2OK : fmi2Error; }

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSet, fmi2Boolean *ev,
                                       fmi2Boolean *term) {
    (void)noSet;
    if (c == NULL) return fmi2Error;
    *ev = fmi2False;
    *term = fmi2False;
    return fmi2OK;
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t) {
    if (c == NULL) return fmi2Error;
    ((Instance *)c)->time = t;
    return fmi2OK;
}

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t n) {
    Instance *inst = (Instance *)c;
    if (inst == NULL || n != 2) return fmi2Error;
    inst->r[VR_X] = x[0];
    inst->r[VR_V] = x[1];
    return fmi2OK;
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t n) {
    Instance *inst = (Instance *)c;
    if (inst == NULL || n != 2) return fmi2Error;
    x[0] = inst->r[VR_X];
    x[1] = inst->r[VR_V];
    return fmi2OK;
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real dx[], size_t n) {
    Instance *inst = (Instance *)c;
    if (inst == NULL || n != 2) return fmi2Error;
    derivatives(inst);
    dx[0] = inst->r[VR_DX];
    dx[1] = inst->r[VR_DV];
    return fmi2OK;
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real z[], size_t n) {
    (void)z;
    return c != NULL && n == 0 ? fmi2OK : fmi2Error;
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x[], size_t n) {
    if (c == NULL || n != 2) return fmi2Error;
    x[0] = x[1] = 1.0;
    return fmi2OK;
}

/* Co-Simulation: not supported (Model Exchange only). */

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                       size_t n, const fmi2Integer o[], const fmi2Real v[]) {
    (void)vr, (void)n, (void)o, (void)v;
    return refuse(c, "fmi2SetRealInputDerivatives");
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[],
                                        size_t n, const fmi2Integer o[], fmi2Real v[]) {
    (void)vr, (void)n, (void)o, (void)v;
    return refuse(c, "fmi2GetRealOutputDerivatives");
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSet) {
    (void)t, (void)h, (void)noSet;
    return refuse(c, "fmi2DoStep");
}

fmi2Status fmi2CancelStep(fmi2Component c) { return refuse(c, "fmi2CancelStep"); }

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *v) {
    (void)s, (void)v;
    return refuse(c, "fmi2GetStatus");
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *v) {
    (void)s, (void)v;
    return refuse(c, "fmi2GetRealStatus");
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *v) {
    (void)s, (void)v;
    return refuse(c, "fmi2GetIntegerStatus");
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *v) {
    (void)s, (void)v;
    return refuse(c, "fmi2GetBooleanStatus");
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *v) {
    (void)s, (void)v;
    return refuse(c, "fmi2GetStringStatus");
}
