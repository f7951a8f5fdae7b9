/*
 * tingen.c - the "Tingen" cantilever rig as an FMI 2.0 FMU (Model Exchange and Co-Simulation
 * in one binary).
 *
 * Physics
 * -------
 * A vertical steel cantilever ("Tingen", NTNU thesis table 3.1: length L = 0.300 m, area
 * moment of inertia I = 2.1 mm^4 = 2.1e-12 m^4, E = 210000 N/mm^2 = 210e9 Pa) with a tip mass,
 * loaded by a horizontal force F at the tip. Modelled by its first bending mode as a
 * single-degree-of-freedom oscillator of the tip deflection w:
 *
 *     m_eff * w'' + c * w' + k * w = F
 *     k     = 3 E I / L^3
 *     m_eff = tip_mass + 0.2357 * beam_mass_per_length * L   (Rayleigh's effective mass)
 *     c     = 2 * zeta * sqrt(k * m_eff)
 *
 * Outputs
 *     theta = 3 w / (2 L)            tip angle [rad]; static: theta = F L^2 / (2 E I), the
 *                                    thesis's equation 4.1 inverted
 *     sigma = k w L c_fiber / I      bending stress at the root [Pa] (root moment M = k w L,
 *                                    c_fiber = distance of the outer fibre = half the thickness)
 *     w                              tip deflection [m]
 *
 * Parameters: L, I, E, tip_mass (default 0 kg: the thesis's input force is the whole tip load
 * computed from the measured angle, tip mass included, so the demo leaves it at 0),
 * beam_mass_per_length (0.196 kg/m: a 25 mm x 1 mm steel strip), zeta (0.02), c_fiber (0.5 mm).
 *
 * Co-Simulation: fmi2DoStep solves the oscillator in closed form for F held constant over the
 * step (cantilever_step in cantilever.h), so the result does not depend on the step size.
 * Model Exchange: two continuous states (w, v = w'), no event indicators.
 *
 * Value references (the same in the FMI 3.0 build, which adds time = 0):
 *     1 F, 2 theta, 3 sigma, 4 w, 5 v, 6 der(w), 7 der(v),
 *     10 L, 11 I, 12 E, 13 tip_mass, 14 beam_mass_per_length, 15 zeta, 16 c_fiber
 *
 * cantilever.h is a symbolic link to ../cantilever.h, so the physics lives in one place and
 * the FMU's sources/ folder still holds everything needed to rebuild it.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

#include "cantilever.h"

#define MODEL_GUID "{6f1c2b7e-3d4a-4e59-8b20-71a9c4d5e8f3}"
#define N_STATES 2
#define NOMINAL_W 0.01
#define NOMINAL_V 0.1

typedef enum {
    MODE_INSTANTIATED = 1 << 0,
    MODE_INITIALIZATION = 1 << 1,
    MODE_STEP = 1 << 2,       /* Co-Simulation: step complete */
    MODE_EVENT = 1 << 3,      /* Model Exchange */
    MODE_CONTINUOUS = 1 << 4, /* Model Exchange */
    MODE_TERMINATED = 1 << 5
} Mode;

#define MODES_ANY                                                                     \
    (MODE_INSTANTIATED | MODE_INITIALIZATION | MODE_STEP | MODE_EVENT | MODE_CONTINUOUS \
     | MODE_TERMINATED)

/* The log categories of modelDescription.xml, in the same order. */
typedef enum {
    LOG_EVENTS,
    LOG_STATUS_WARNING,
    LOG_STATUS_DISCARD,
    LOG_STATUS_ERROR,
    LOG_STATUS_FATAL,
    N_CATEGORIES
} Category;

static const char *const CATEGORY_NAMES[N_CATEGORIES] = {
    "logEvents", "logStatusWarning", "logStatusDiscard", "logStatusError", "logStatusFatal"};

typedef struct {
    fmi2Type type;
    char *name;
    fmi2CallbackFunctions cb;
    fmi2Boolean logging_on;
    int category_on[N_CATEGORIES];
    Mode mode;
    double time;
    CantileverParams p;
    double F;
    CantileverState x;
} Instance;

/* ---------------------------------------------------------------------------------------- */
/* Helpers                                                                                  */
/* ---------------------------------------------------------------------------------------- */

/* Errors and fatal errors are always reported; everything else only with logging on and the
 * category enabled. The message is formatted here and its '%' doubled, because the logger
 * treats the message as a printf format of its own. */
static void log_message(const Instance *c, fmi2Status status, Category category, const char *fmt,
                        ...) {
    char text[512];
    char escaped[1024];
    size_t i, j;
    va_list args;

    if (c == NULL || c->cb.logger == NULL) return;
    if (status < fmi2Error && !(c->logging_on && c->category_on[category])) return;

    va_start(args, fmt);
    vsnprintf(text, sizeof text, fmt, args);
    va_end(args);

    for (i = 0, j = 0; text[i] != '\0' && j + 2 < sizeof escaped; i++) {
        if (text[i] == '%') escaped[j++] = '%';
        escaped[j++] = text[i];
    }
    escaped[j] = '\0';

    c->cb.logger(c->cb.componentEnvironment, c->name != NULL ? c->name : "tingen", status,
                 CATEGORY_NAMES[category], escaped);
}

#define LOG_ERROR(c, ...) log_message((c), fmi2Error, LOG_STATUS_ERROR, __VA_ARGS__)
#define LOG_DISCARD(c, ...) log_message((c), fmi2Discard, LOG_STATUS_DISCARD, __VA_ARGS__)

static const char *mode_name(Mode mode) {
    switch (mode) {
        case MODE_INSTANTIATED: return "Instantiated";
        case MODE_INITIALIZATION: return "Initialization Mode";
        case MODE_STEP: return "Step Mode";
        case MODE_EVENT: return "Event Mode";
        case MODE_CONTINUOUS: return "Continuous-Time Mode";
        case MODE_TERMINATED: return "Terminated";
    }
    return "unknown mode";
}

/* Whether a function may be called now; logs why not. `type` < 0 means either interface. */
static int allowed(Instance *c, const char *function, int type, int modes) {
    if (c == NULL) return 0;
    if (type >= 0 && (int)c->type != type) {
        LOG_ERROR(c, "%s is only available in %s.", function,
                  type == fmi2CoSimulation ? "Co-Simulation" : "Model Exchange");
        return 0;
    }
    if (!(c->mode & modes)) {
        LOG_ERROR(c, "%s must not be called in %s.", function, mode_name(c->mode));
        return 0;
    }
    return 1;
}

static fmi2Status unsupported(fmi2Component c, const char *function) {
    LOG_ERROR((Instance *)c, "%s is not supported by this FMU.", function);
    return fmi2Error;
}

static void set_defaults(Instance *c) {
    cantilever_default_params(&c->p);
    c->F = 0.0;
    c->x.w = 0.0;
    c->x.v = 0.0;
    c->time = 0.0;
}

static fmi2Status get_value(Instance *c, fmi2ValueReference vr, fmi2Real *value) {
    if (cantilever_get(&c->p, c->F, &c->x, vr, value)) return fmi2OK;
    LOG_ERROR(c, "fmi2GetReal: unknown value reference %u.", vr);
    return fmi2Error;
}

/* A structural (fixed) parameter: settable before and during initialization only. */
static fmi2Status set_fixed(Instance *c, const char *name, double *target, double value,
                            int strictly_positive) {
    if (!(c->mode & (MODE_INSTANTIATED | MODE_INITIALIZATION))) {
        LOG_ERROR(c, "fmi2SetReal: %s is a fixed parameter and cannot be set in %s.", name,
                  mode_name(c->mode));
        return fmi2Error;
    }
    if (!isfinite(value) || (strictly_positive ? !(value > 0.0) : !(value >= 0.0))) {
        LOG_ERROR(c, "fmi2SetReal: %s = %g is not allowed, it must be %s.", name, value,
                  strictly_positive ? "positive" : "zero or positive");
        return fmi2Error;
    }
    *target = value;
    return fmi2OK;
}

static fmi2Status set_value(Instance *c, fmi2ValueReference vr, fmi2Real value) {
    switch (vr) {
        case VR_F:
            if (!(c->mode & (MODES_ANY & ~MODE_TERMINATED))) break;
            if (!isfinite(value)) {
                LOG_ERROR(c, "fmi2SetReal: the force F must be finite, got %g.", value);
                return fmi2Error;
            }
            c->F = value;
            return fmi2OK;
        case VR_W:
        case VR_V:
            if (!(c->mode & (MODE_INSTANTIATED | MODE_INITIALIZATION))) break;
            if (!isfinite(value)) {
                LOG_ERROR(c, "fmi2SetReal: the start value of %s must be finite.",
                          vr == VR_W ? "w" : "v");
                return fmi2Error;
            }
            if (vr == VR_W) c->x.w = value;
            else c->x.v = value;
            return fmi2OK;
        case VR_ZETA:
            if (!(c->mode & (MODE_INSTANTIATED | MODE_INITIALIZATION | MODE_STEP | MODE_EVENT)))
                break;
            if (!isfinite(value) || !(value >= 0.0)) {
                LOG_ERROR(c, "fmi2SetReal: zeta = %g is not allowed, it must be zero or positive.",
                          value);
                return fmi2Error;
            }
            c->p.zeta = value;
            return fmi2OK;
        case VR_L: return set_fixed(c, "L", &c->p.L, value, 1);
        case VR_I: return set_fixed(c, "I", &c->p.I, value, 1);
        case VR_E: return set_fixed(c, "E", &c->p.E, value, 1);
        case VR_TIP_MASS: return set_fixed(c, "tip_mass", &c->p.tip_mass, value, 0);
        case VR_BEAM_MASS_PER_LENGTH:
            return set_fixed(c, "beam_mass_per_length", &c->p.beam_mass_per_length, value, 0);
        case VR_C_FIBER: return set_fixed(c, "c_fiber", &c->p.c_fiber, value, 0);
        case VR_THETA:
        case VR_SIGMA:
        case VR_DER_W:
        case VR_DER_V:
            LOG_ERROR(c, "fmi2SetReal: value reference %u is a calculated variable and cannot be "
                      "set.", vr);
            return fmi2Error;
        default:
            LOG_ERROR(c, "fmi2SetReal: unknown value reference %u.", vr);
            return fmi2Error;
    }
    LOG_ERROR(c, "fmi2SetReal: value reference %u cannot be set in %s.", vr, mode_name(c->mode));
    return fmi2Error;
}

/* For Integer, Boolean and String: this model has no such variables. */
static fmi2Status no_variables(fmi2Component c, const char *function, const fmi2ValueReference vr[],
                               size_t nvr) {
    Instance *inst = (Instance *)c;
    if (inst == NULL) return fmi2Error;
    if (nvr == 0) return fmi2OK;
    LOG_ERROR(inst, "%s: unknown value reference %u (this model has no such variables).",
              function, vr != NULL ? vr[0] : 0u);
    return fmi2Error;
}

/* ---------------------------------------------------------------------------------------- */
/* Common functions                                                                         */
/* ---------------------------------------------------------------------------------------- */

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    Instance *inst = (Instance *)c;
    size_t i;
    int k;

    if (inst == NULL) return fmi2Error;
    inst->logging_on = loggingOn;
    for (k = 0; k < N_CATEGORIES; k++) inst->category_on[k] = nCategories == 0;
    for (i = 0; i < nCategories; i++) {
        int found = 0;
        for (k = 0; k < N_CATEGORIES; k++) {
            if (categories[i] != NULL && strcmp(categories[i], CATEGORY_NAMES[k]) == 0) {
                inst->category_on[k] = 1;
                found = 1;
            }
        }
        if (!found) {
            LOG_ERROR(inst, "fmi2SetDebugLogging: unknown log category \"%s\".",
                      categories[i] != NULL ? categories[i] : "(null)");
            return fmi2Error;
        }
    }
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation,
                              const fmi2CallbackFunctions *functions, fmi2Boolean visible,
                              fmi2Boolean loggingOn) {
    Instance probe; /* only for logging until the real instance exists */
    Instance *c;
    size_t len;
    int k;

    (void)fmuResourceLocation;
    (void)visible;

    if (functions == NULL) return NULL;
    memset(&probe, 0, sizeof probe);
    probe.cb = *functions;
    probe.name = (char *)(instanceName != NULL ? instanceName : "tingen");

    if (instanceName == NULL || instanceName[0] == '\0') {
        LOG_ERROR(&probe, "fmi2Instantiate: missing instance name.");
        return NULL;
    }
    if (fmuGUID == NULL || strcmp(fmuGUID, MODEL_GUID) != 0) {
        LOG_ERROR(&probe, "fmi2Instantiate: wrong GUID %s, expected %s.",
                  fmuGUID != NULL ? fmuGUID : "(null)", MODEL_GUID);
        return NULL;
    }
    if (fmuType != fmi2ModelExchange && fmuType != fmi2CoSimulation) {
        LOG_ERROR(&probe, "fmi2Instantiate: unknown FMU type %d.", (int)fmuType);
        return NULL;
    }

    c = functions->allocateMemory != NULL
            ? (Instance *)functions->allocateMemory(1, sizeof(Instance))
            : (Instance *)calloc(1, sizeof(Instance));
    if (c == NULL) {
        LOG_ERROR(&probe, "fmi2Instantiate: out of memory.");
        return NULL;
    }
    memset(c, 0, sizeof *c);
    c->cb = *functions;
    len = strlen(instanceName) + 1;
    c->name = functions->allocateMemory != NULL ? (char *)functions->allocateMemory(len, 1)
                                                : (char *)calloc(len, 1);
    if (c->name == NULL) {
        LOG_ERROR(&probe, "fmi2Instantiate: out of memory.");
        if (functions->freeMemory != NULL) functions->freeMemory(c);
        else free(c);
        return NULL;
    }
    memcpy(c->name, instanceName, len);
    c->type = fmuType;
    c->logging_on = loggingOn;
    for (k = 0; k < N_CATEGORIES; k++) c->category_on[k] = 1;
    c->mode = MODE_INSTANTIATED;
    set_defaults(c);
    return c;
}

void fmi2FreeInstance(fmi2Component c) {
    Instance *inst = (Instance *)c;
    fmi2CallbackFreeMemory release;

    if (inst == NULL) return;
    release = inst->cb.freeMemory;
    if (release != NULL) {
        release(inst->name);
        release(inst);
    } else {
        free(inst->name);
        free(inst);
    }
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined,
                               fmi2Real stopTime) {
    Instance *inst = (Instance *)c;
    (void)toleranceDefined;
    (void)tolerance;
    (void)stopTimeDefined;
    (void)stopTime;
    if (!allowed(inst, "fmi2SetupExperiment", -1, MODE_INSTANTIATED)) return fmi2Error;
    inst->time = startTime;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    Instance *inst = (Instance *)c;
    if (!allowed(inst, "fmi2EnterInitializationMode", -1, MODE_INSTANTIATED)) return fmi2Error;
    inst->mode = MODE_INITIALIZATION;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    Instance *inst = (Instance *)c;
    const char *problem;
    if (!allowed(inst, "fmi2ExitInitializationMode", -1, MODE_INITIALIZATION)) return fmi2Error;
    problem = cantilever_check(&inst->p);
    if (problem != NULL) {
        LOG_ERROR(inst, "fmi2ExitInitializationMode: %s.", problem);
        return fmi2Error;
    }
    inst->mode = inst->type == fmi2CoSimulation ? MODE_STEP : MODE_EVENT;
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component c) {
    Instance *inst = (Instance *)c;
    if (!allowed(inst, "fmi2Terminate", -1,
                 MODE_INITIALIZATION | MODE_STEP | MODE_EVENT | MODE_CONTINUOUS))
        return fmi2Error;
    inst->mode = MODE_TERMINATED;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component c) {
    Instance *inst = (Instance *)c;
    if (inst == NULL) return fmi2Error;
    set_defaults(inst);
    inst->mode = MODE_INSTANTIATED;
    return fmi2OK;
}

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       fmi2Real value[]) {
    Instance *inst = (Instance *)c;
    size_t i;
    if (inst == NULL) return fmi2Error;
    if (nvr > 0 && (vr == NULL || value == NULL)) {
        LOG_ERROR(inst, "fmi2GetReal: NULL argument.");
        return fmi2Error;
    }
    for (i = 0; i < nvr; i++) {
        if (get_value(inst, vr[i], &value[i]) != fmi2OK) return fmi2Error;
    }
    return fmi2OK;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          fmi2Integer value[]) {
    (void)value;
    return no_variables(c, "fmi2GetInteger", vr, nvr);
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          fmi2Boolean value[]) {
    (void)value;
    return no_variables(c, "fmi2GetBoolean", vr, nvr);
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         fmi2String value[]) {
    (void)value;
    return no_variables(c, "fmi2GetString", vr, nvr);
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                       const fmi2Real value[]) {
    Instance *inst = (Instance *)c;
    size_t i;
    if (inst == NULL) return fmi2Error;
    if (nvr > 0 && (vr == NULL || value == NULL)) {
        LOG_ERROR(inst, "fmi2SetReal: NULL argument.");
        return fmi2Error;
    }
    for (i = 0; i < nvr; i++) {
        if (set_value(inst, vr[i], value[i]) != fmi2OK) return fmi2Error;
    }
    return fmi2OK;
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          const fmi2Integer value[]) {
    (void)value;
    return no_variables(c, "fmi2SetInteger", vr, nvr);
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          const fmi2Boolean value[]) {
    (void)value;
    return no_variables(c, "fmi2SetBoolean", vr, nvr);
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         const fmi2String value[]) {
    (void)value;
    return no_variables(c, "fmi2SetString", vr, nvr);
}

/* FMU state, serialization and directional derivatives: not supported (modelDescription.xml
 * says canGetAndSetFMUstate="false", providesDirectionalDerivative="false"). */

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *FMUstate) {
    (void)FMUstate;
    return unsupported(c, "fmi2GetFMUstate");
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate FMUstate) {
    (void)FMUstate;
    return unsupported(c, "fmi2SetFMUstate");
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *FMUstate) {
    (void)FMUstate;
    return unsupported(c, "fmi2FreeFMUstate");
}

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate FMUstate, size_t *size) {
    (void)FMUstate;
    (void)size;
    return unsupported(c, "fmi2SerializedFMUstateSize");
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate FMUstate, fmi2Byte serializedState[],
                                 size_t size) {
    (void)FMUstate;
    (void)serializedState;
    (void)size;
    return unsupported(c, "fmi2SerializeFMUstate");
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte serializedState[], size_t size,
                                   fmi2FMUstate *FMUstate) {
    (void)serializedState;
    (void)size;
    (void)FMUstate;
    return unsupported(c, "fmi2DeSerializeFMUstate");
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown_ref[],
                                        size_t nUnknown, const fmi2ValueReference vKnown_ref[],
                                        size_t nKnown, const fmi2Real dvKnown[],
                                        fmi2Real dvUnknown[]) {
    (void)vUnknown_ref;
    (void)nUnknown;
    (void)vKnown_ref;
    (void)nKnown;
    (void)dvKnown;
    (void)dvUnknown;
    return unsupported(c, "fmi2GetDirectionalDerivative");
}

/* ---------------------------------------------------------------------------------------- */
/* Model Exchange                                                                           */
/* ---------------------------------------------------------------------------------------- */

fmi2Status fmi2EnterEventMode(fmi2Component c) {
    Instance *inst = (Instance *)c;
    if (!allowed(inst, "fmi2EnterEventMode", fmi2ModelExchange, MODE_EVENT | MODE_CONTINUOUS))
        return fmi2Error;
    inst->mode = MODE_EVENT;
    return fmi2OK;
}

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *eventInfo) {
    Instance *inst = (Instance *)c;
    if (!allowed(inst, "fmi2NewDiscreteStates", fmi2ModelExchange, MODE_EVENT)) return fmi2Error;
    if (eventInfo == NULL) {
        LOG_ERROR(inst, "fmi2NewDiscreteStates: NULL argument.");
        return fmi2Error;
    }
    eventInfo->newDiscreteStatesNeeded = fmi2False;
    eventInfo->terminateSimulation = fmi2False;
    eventInfo->nominalsOfContinuousStatesChanged = fmi2False;
    eventInfo->valuesOfContinuousStatesChanged = fmi2False;
    eventInfo->nextEventTimeDefined = fmi2False;
    eventInfo->nextEventTime = 0.0;
    return fmi2OK;
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) {
    Instance *inst = (Instance *)c;
    if (!allowed(inst, "fmi2EnterContinuousTimeMode", fmi2ModelExchange, MODE_EVENT))
        return fmi2Error;
    inst->mode = MODE_CONTINUOUS;
    return fmi2OK;
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c,
                                       fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode,
                                       fmi2Boolean *terminateSimulation) {
    Instance *inst = (Instance *)c;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!allowed(inst, "fmi2CompletedIntegratorStep", fmi2ModelExchange, MODE_CONTINUOUS))
        return fmi2Error;
    if (enterEventMode != NULL) *enterEventMode = fmi2False;
    if (terminateSimulation != NULL) *terminateSimulation = fmi2False;
    return fmi2OK;
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time) {
    Instance *inst = (Instance *)c;
    if (!allowed(inst, "fmi2SetTime", fmi2ModelExchange, MODE_EVENT | MODE_CONTINUOUS))
        return fmi2Error;
    inst->time = time;
    return fmi2OK;
}

static int check_nx(Instance *inst, const char *function, const void *array, size_t nx) {
    if (nx != N_STATES || array == NULL) {
        LOG_ERROR(inst, "%s: expected an array of %d continuous states, got %lu.", function,
                  N_STATES, (unsigned long)nx);
        return 0;
    }
    return 1;
}

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    Instance *inst = (Instance *)c;
    if (!allowed(inst, "fmi2SetContinuousStates", fmi2ModelExchange, MODE_CONTINUOUS))
        return fmi2Error;
    if (!check_nx(inst, "fmi2SetContinuousStates", x, nx)) return fmi2Error;
    inst->x.w = x[0];
    inst->x.v = x[1];
    return fmi2OK;
}

#define ME_QUERY_MODES (MODE_INITIALIZATION | MODE_EVENT | MODE_CONTINUOUS | MODE_TERMINATED)

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx) {
    Instance *inst = (Instance *)c;
    if (!allowed(inst, "fmi2GetDerivatives", fmi2ModelExchange, ME_QUERY_MODES)) return fmi2Error;
    if (!check_nx(inst, "fmi2GetDerivatives", derivatives, nx)) return fmi2Error;
    derivatives[0] = inst->x.v;
    derivatives[1] = cantilever_acceleration(&inst->p, inst->F, inst->x.w, inst->x.v);
    return fmi2OK;
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni) {
    Instance *inst = (Instance *)c;
    (void)eventIndicators;
    if (!allowed(inst, "fmi2GetEventIndicators", fmi2ModelExchange, ME_QUERY_MODES))
        return fmi2Error;
    if (ni != 0) {
        LOG_ERROR(inst, "fmi2GetEventIndicators: this model has no event indicators, got %lu.",
                  (unsigned long)ni);
        return fmi2Error;
    }
    return fmi2OK;
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    Instance *inst = (Instance *)c;
    if (!allowed(inst, "fmi2GetContinuousStates", fmi2ModelExchange, ME_QUERY_MODES))
        return fmi2Error;
    if (!check_nx(inst, "fmi2GetContinuousStates", x, nx)) return fmi2Error;
    x[0] = inst->x.w;
    x[1] = inst->x.v;
    return fmi2OK;
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx) {
    Instance *inst = (Instance *)c;
    if (!allowed(inst, "fmi2GetNominalsOfContinuousStates", fmi2ModelExchange,
                 MODE_INSTANTIATED | ME_QUERY_MODES))
        return fmi2Error;
    if (!check_nx(inst, "fmi2GetNominalsOfContinuousStates", x_nominal, nx)) return fmi2Error;
    x_nominal[0] = NOMINAL_W;
    x_nominal[1] = NOMINAL_V;
    return fmi2OK;
}

/* ---------------------------------------------------------------------------------------- */
/* Co-Simulation                                                                            */
/* ---------------------------------------------------------------------------------------- */

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[]) {
    (void)vr;
    (void)nvr;
    (void)order;
    (void)value;
    return unsupported(c, "fmi2SetRealInputDerivatives");
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[]) {
    (void)vr;
    (void)nvr;
    (void)order;
    (void)value;
    return unsupported(c, "fmi2GetRealOutputDerivatives");
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint,
                      fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint) {
    Instance *inst = (Instance *)c;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!allowed(inst, "fmi2DoStep", fmi2CoSimulation, MODE_STEP)) return fmi2Error;
    if (!isfinite(communicationStepSize) || communicationStepSize < 0.0) {
        LOG_ERROR(inst, "fmi2DoStep: the communication step size must be >= 0, got %g.",
                  communicationStepSize);
        return fmi2Error;
    }
    cantilever_step(&inst->p, inst->F, communicationStepSize, &inst->x);
    inst->time = currentCommunicationPoint + communicationStepSize;
    return fmi2OK;
}

fmi2Status fmi2CancelStep(fmi2Component c) {
    /* fmi2DoStep never returns fmi2Pending, so there is nothing to cancel. */
    return unsupported(c, "fmi2CancelStep");
}

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    Instance *inst = (Instance *)c;
    (void)value;
    if (!allowed(inst, "fmi2GetStatus", fmi2CoSimulation, MODES_ANY)) return fmi2Error;
    LOG_DISCARD(inst, "fmi2GetStatus: status kind %d is not available (fmi2DoStep never returns "
              "fmi2Pending).", (int)s);
    return fmi2Discard;
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    Instance *inst = (Instance *)c;
    if (!allowed(inst, "fmi2GetRealStatus", fmi2CoSimulation, MODES_ANY)) return fmi2Error;
    if (s == fmi2LastSuccessfulTime && value != NULL) {
        *value = inst->time;
        return fmi2OK;
    }
    LOG_DISCARD(inst, "fmi2GetRealStatus: status kind %d is not available.", (int)s);
    return fmi2Discard;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    Instance *inst = (Instance *)c;
    (void)value;
    if (!allowed(inst, "fmi2GetIntegerStatus", fmi2CoSimulation, MODES_ANY)) return fmi2Error;
    LOG_DISCARD(inst, "fmi2GetIntegerStatus: status kind %d is not available.", (int)s);
    return fmi2Discard;
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    Instance *inst = (Instance *)c;
    if (!allowed(inst, "fmi2GetBooleanStatus", fmi2CoSimulation, MODES_ANY)) return fmi2Error;
    if (s == fmi2Terminated && value != NULL) {
        *value = fmi2False; /* the model never asks to stop the simulation */
        return fmi2OK;
    }
    LOG_DISCARD(inst, "fmi2GetBooleanStatus: status kind %d is not available.", (int)s);
    return fmi2Discard;
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    Instance *inst = (Instance *)c;
    (void)value;
    if (!allowed(inst, "fmi2GetStringStatus", fmi2CoSimulation, MODES_ANY)) return fmi2Error;
    LOG_DISCARD(inst, "fmi2GetStringStatus: status kind %d is not available.", (int)s);
    return fmi2Discard;
}
