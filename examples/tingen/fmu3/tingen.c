/*
 * tingen.c - the "Tingen" cantilever rig as an FMI 3.0 FMU (Model Exchange and Co-Simulation
 * in one binary). The same model as ../fmu/tingen.c (FMI 2.0); the physics is shared in
 * cantilever.h (a symbolic link to ../cantilever.h).
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
 * Co-Simulation: fmi3DoStep solves the oscillator in closed form for F held constant over the
 * step, so the result does not depend on the step size. Model Exchange: two continuous states
 * (w, v = w'), no event indicators. No clocks, no FMU state, no directional derivatives.
 *
 * Value references:
 *     0 time, 1 F, 2 theta, 3 sigma, 4 w, 5 v, 6 der(w), 7 der(v),
 *     10 L, 11 I, 12 E, 13 tip_mass, 14 beam_mass_per_length, 15 zeta, 16 c_fiber
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"

#include "cantilever.h"

#define INSTANTIATION_TOKEN "{a3e5c7d9-1b2f-4c6e-8a0d-2f4b6d8e0a1c}"
#define N_STATES 2
#define NOMINAL_W 0.01
#define NOMINAL_V 0.1

enum { VR_TIME = 0 }; /* FMI 3.0 only: the independent variable */

typedef enum { TYPE_MODEL_EXCHANGE, TYPE_CO_SIMULATION } InterfaceType;

typedef enum {
    MODE_INSTANTIATED = 1 << 0,
    MODE_INITIALIZATION = 1 << 1,
    MODE_EVENT = 1 << 2,
    MODE_CONTINUOUS = 1 << 3, /* Model Exchange */
    MODE_STEP = 1 << 4,       /* Co-Simulation */
    MODE_TERMINATED = 1 << 5
} Mode;

#define MODES_ANY                                                                     \
    (MODE_INSTANTIATED | MODE_INITIALIZATION | MODE_EVENT | MODE_CONTINUOUS | MODE_STEP \
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
    InterfaceType type;
    char *name;
    fmi3InstanceEnvironment environment;
    fmi3LogMessageCallback log_message;
    fmi3Boolean logging_on;
    int category_on[N_CATEGORIES];
    fmi3Boolean event_mode_used;
    Mode mode;
    double time;
    CantileverParams p;
    double F;
    CantileverState x;
} Instance;

/* ---------------------------------------------------------------------------------------- */
/* Helpers                                                                                  */
/* ---------------------------------------------------------------------------------------- */

/* Errors are always reported; everything else only with logging on and the category on. */
static void log_message(const Instance *c, fmi3Status status, Category category, const char *fmt,
                        ...) {
    char text[512];
    va_list args;

    if (c == NULL || c->log_message == NULL) return;
    if (status < fmi3Error && !(c->logging_on && c->category_on[category])) return;

    va_start(args, fmt);
    vsnprintf(text, sizeof text, fmt, args);
    va_end(args);
    c->log_message(c->environment, status, CATEGORY_NAMES[category], text);
}

#define LOG_ERROR(c, ...) log_message((c), fmi3Error, LOG_STATUS_ERROR, __VA_ARGS__)

static const char *mode_name(Mode mode) {
    switch (mode) {
        case MODE_INSTANTIATED: return "Instantiated";
        case MODE_INITIALIZATION: return "Initialization Mode";
        case MODE_EVENT: return "Event Mode";
        case MODE_CONTINUOUS: return "Continuous-Time Mode";
        case MODE_STEP: return "Step Mode";
        case MODE_TERMINATED: return "Terminated";
    }
    return "unknown mode";
}

/* Whether a function may be called now; logs why not. `type` < 0 means either interface. */
static int allowed(Instance *c, const char *function, int type, int modes) {
    if (c == NULL) return 0;
    if (type >= 0 && (int)c->type != type) {
        LOG_ERROR(c, "%s is only available in %s.", function,
                  type == TYPE_CO_SIMULATION ? "Co-Simulation" : "Model Exchange");
        return 0;
    }
    if (!(c->mode & modes)) {
        LOG_ERROR(c, "%s must not be called in %s.", function, mode_name(c->mode));
        return 0;
    }
    return 1;
}

static fmi3Status unsupported(fmi3Instance instance, const char *function) {
    LOG_ERROR((Instance *)instance, "%s is not supported by this FMU.", function);
    return fmi3Error;
}

static void set_defaults(Instance *c) {
    cantilever_default_params(&c->p);
    c->F = 0.0;
    c->x.w = 0.0;
    c->x.v = 0.0;
    c->time = 0.0;
}

static fmi3Status get_value(Instance *c, fmi3ValueReference vr, fmi3Float64 *value) {
    if (vr == VR_TIME) {
        *value = c->time;
        return fmi3OK;
    }
    if (cantilever_get(&c->p, c->F, &c->x, vr, value)) return fmi3OK;
    LOG_ERROR(c, "fmi3GetFloat64: unknown value reference %u.", (unsigned)vr);
    return fmi3Error;
}

/* A structural (fixed) parameter: settable before and during initialization only. */
static fmi3Status set_fixed(Instance *c, const char *name, double *target, double value,
                            int strictly_positive) {
    if (!(c->mode & (MODE_INSTANTIATED | MODE_INITIALIZATION))) {
        LOG_ERROR(c, "fmi3SetFloat64: %s is a fixed parameter and cannot be set in %s.", name,
                  mode_name(c->mode));
        return fmi3Error;
    }
    if (!isfinite(value) || (strictly_positive ? !(value > 0.0) : !(value >= 0.0))) {
        LOG_ERROR(c, "fmi3SetFloat64: %s = %g is not allowed, it must be %s.", name, value,
                  strictly_positive ? "positive" : "zero or positive");
        return fmi3Error;
    }
    *target = value;
    return fmi3OK;
}

static fmi3Status set_value(Instance *c, fmi3ValueReference vr, fmi3Float64 value) {
    switch (vr) {
        case VR_F:
            if (!(c->mode & (MODES_ANY & ~MODE_TERMINATED))) break;
            if (!isfinite(value)) {
                LOG_ERROR(c, "fmi3SetFloat64: the force F must be finite, got %g.", value);
                return fmi3Error;
            }
            c->F = value;
            return fmi3OK;
        case VR_W:
        case VR_V:
            if (!(c->mode & (MODE_INSTANTIATED | MODE_INITIALIZATION))) break;
            if (!isfinite(value)) {
                LOG_ERROR(c, "fmi3SetFloat64: the start value of %s must be finite.",
                          vr == VR_W ? "w" : "v");
                return fmi3Error;
            }
            if (vr == VR_W) c->x.w = value;
            else c->x.v = value;
            return fmi3OK;
        case VR_ZETA:
            if (!(c->mode & (MODE_INSTANTIATED | MODE_INITIALIZATION | MODE_STEP | MODE_EVENT)))
                break;
            if (!isfinite(value) || !(value >= 0.0)) {
                LOG_ERROR(c, "fmi3SetFloat64: zeta = %g is not allowed, it must be zero or "
                          "positive.", value);
                return fmi3Error;
            }
            c->p.zeta = value;
            return fmi3OK;
        case VR_L: return set_fixed(c, "L", &c->p.L, value, 1);
        case VR_I: return set_fixed(c, "I", &c->p.I, value, 1);
        case VR_E: return set_fixed(c, "E", &c->p.E, value, 1);
        case VR_TIP_MASS: return set_fixed(c, "tip_mass", &c->p.tip_mass, value, 0);
        case VR_BEAM_MASS_PER_LENGTH:
            return set_fixed(c, "beam_mass_per_length", &c->p.beam_mass_per_length, value, 0);
        case VR_C_FIBER: return set_fixed(c, "c_fiber", &c->p.c_fiber, value, 0);
        case VR_TIME:
        case VR_THETA:
        case VR_SIGMA:
        case VR_DER_W:
        case VR_DER_V:
            LOG_ERROR(c, "fmi3SetFloat64: value reference %u is a calculated variable and cannot "
                      "be set.", (unsigned)vr);
            return fmi3Error;
        default:
            LOG_ERROR(c, "fmi3SetFloat64: unknown value reference %u.", (unsigned)vr);
            return fmi3Error;
    }
    LOG_ERROR(c, "fmi3SetFloat64: value reference %u cannot be set in %s.", (unsigned)vr,
              mode_name(c->mode));
    return fmi3Error;
}

static int check_sizes(Instance *c, const char *function, const fmi3ValueReference vr[],
                       size_t nvr, const void *values, size_t nValues) {
    if (nvr > 0 && (vr == NULL || values == NULL)) {
        LOG_ERROR(c, "%s: NULL argument.", function);
        return 0;
    }
    if (nValues != nvr) {
        LOG_ERROR(c, "%s: %lu values for %lu value references (this model has no arrays).",
                  function, (unsigned long)nValues, (unsigned long)nvr);
        return 0;
    }
    return 1;
}

/* For every type but Float64: this model has no such variables. */
static fmi3Status no_variables(fmi3Instance instance, const char *function,
                               const fmi3ValueReference vr[], size_t nvr) {
    Instance *c = (Instance *)instance;
    if (c == NULL) return fmi3Error;
    if (nvr == 0) return fmi3OK;
    LOG_ERROR(c, "%s: unknown value reference %u (this model has no such variables).", function,
              vr != NULL ? (unsigned)vr[0] : 0u);
    return fmi3Error;
}

static Instance *instantiate(InterfaceType type, fmi3String instanceName,
                             fmi3String instantiationToken, fmi3Boolean loggingOn,
                             fmi3InstanceEnvironment environment,
                             fmi3LogMessageCallback logMessage) {
    Instance probe; /* only for logging until the real instance exists */
    Instance *c;
    size_t len;
    int k;

    memset(&probe, 0, sizeof probe);
    probe.environment = environment;
    probe.log_message = logMessage;

    if (instanceName == NULL || instanceName[0] == '\0') {
        LOG_ERROR(&probe, "fmi3Instantiate: missing instance name.");
        return NULL;
    }
    if (instantiationToken == NULL || strcmp(instantiationToken, INSTANTIATION_TOKEN) != 0) {
        LOG_ERROR(&probe, "fmi3Instantiate: wrong instantiation token %s, expected %s.",
                  instantiationToken != NULL ? instantiationToken : "(null)",
                  INSTANTIATION_TOKEN);
        return NULL;
    }
    c = (Instance *)calloc(1, sizeof(Instance));
    len = strlen(instanceName) + 1;
    if (c != NULL) c->name = (char *)malloc(len);
    if (c == NULL || c->name == NULL) {
        LOG_ERROR(&probe, "fmi3Instantiate: out of memory.");
        free(c);
        return NULL;
    }
    memcpy(c->name, instanceName, len);
    c->type = type;
    c->environment = environment;
    c->log_message = logMessage;
    c->logging_on = loggingOn;
    for (k = 0; k < N_CATEGORIES; k++) c->category_on[k] = 1;
    c->mode = MODE_INSTANTIATED;
    set_defaults(c);
    return c;
}

/* ---------------------------------------------------------------------------------------- */
/* Common functions                                                                         */
/* ---------------------------------------------------------------------------------------- */

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[]) {
    Instance *c = (Instance *)instance;
    size_t i;
    int k;

    if (c == NULL) return fmi3Error;
    c->logging_on = loggingOn;
    for (k = 0; k < N_CATEGORIES; k++) c->category_on[k] = nCategories == 0;
    for (i = 0; i < nCategories; i++) {
        int found = 0;
        for (k = 0; k < N_CATEGORIES; k++) {
            if (categories[i] != NULL && strcmp(categories[i], CATEGORY_NAMES[k]) == 0) {
                c->category_on[k] = 1;
                found = 1;
            }
        }
        if (!found) {
            LOG_ERROR(c, "fmi3SetDebugLogging: unknown log category \"%s\".",
                      categories[i] != NULL ? categories[i] : "(null)");
            return fmi3Error;
        }
    }
    return fmi3OK;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible,
                                          fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage) {
    (void)resourcePath;
    (void)visible;
    return instantiate(TYPE_MODEL_EXCHANGE, instanceName, instantiationToken, loggingOn,
                       instanceEnvironment, logMessage);
}

fmi3Instance fmi3InstantiateCoSimulation(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3Boolean eventModeUsed,
    fmi3Boolean earlyReturnAllowed, const fmi3ValueReference requiredIntermediateVariables[],
    size_t nRequiredIntermediateVariables, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3IntermediateUpdateCallback intermediateUpdate) {
    Instance *c;
    (void)resourcePath;
    (void)visible;
    (void)earlyReturnAllowed; /* fmi3DoStep never returns early */
    (void)requiredIntermediateVariables;
    (void)nRequiredIntermediateVariables;
    (void)intermediateUpdate; /* no intermediate updates */
    c = instantiate(TYPE_CO_SIMULATION, instanceName, instantiationToken, loggingOn,
                    instanceEnvironment, logMessage);
    if (c != NULL) c->event_mode_used = eventModeUsed;
    return c;
}

fmi3Instance fmi3InstantiateScheduledExecution(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate,
    fmi3LockPreemptionCallback lockPreemption, fmi3UnlockPreemptionCallback unlockPreemption) {
    Instance probe;
    (void)instanceName;
    (void)instantiationToken;
    (void)resourcePath;
    (void)visible;
    (void)loggingOn;
    (void)clockUpdate;
    (void)lockPreemption;
    (void)unlockPreemption;
    memset(&probe, 0, sizeof probe);
    probe.environment = instanceEnvironment;
    probe.log_message = logMessage;
    LOG_ERROR(&probe, "fmi3InstantiateScheduledExecution: Scheduled Execution is not supported.");
    return NULL;
}

void fmi3FreeInstance(fmi3Instance instance) {
    Instance *c = (Instance *)instance;
    if (c == NULL) return;
    free(c->name);
    free(c);
}

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined,
                                       fmi3Float64 tolerance, fmi3Float64 startTime,
                                       fmi3Boolean stopTimeDefined, fmi3Float64 stopTime) {
    Instance *c = (Instance *)instance;
    (void)toleranceDefined;
    (void)tolerance;
    (void)stopTimeDefined;
    (void)stopTime;
    if (!allowed(c, "fmi3EnterInitializationMode", -1, MODE_INSTANTIATED)) return fmi3Error;
    c->time = startTime;
    c->mode = MODE_INITIALIZATION;
    return fmi3OK;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
    Instance *c = (Instance *)instance;
    const char *problem;
    if (!allowed(c, "fmi3ExitInitializationMode", -1, MODE_INITIALIZATION)) return fmi3Error;
    problem = cantilever_check(&c->p);
    if (problem != NULL) {
        LOG_ERROR(c, "fmi3ExitInitializationMode: %s.", problem);
        return fmi3Error;
    }
    if (c->type == TYPE_CO_SIMULATION && !c->event_mode_used) c->mode = MODE_STEP;
    else c->mode = MODE_EVENT;
    return fmi3OK;
}

fmi3Status fmi3EnterEventMode(fmi3Instance instance) {
    Instance *c = (Instance *)instance;
    if (!allowed(c, "fmi3EnterEventMode", -1, MODE_EVENT | MODE_CONTINUOUS | MODE_STEP))
        return fmi3Error;
    if (c->type == TYPE_CO_SIMULATION && !c->event_mode_used) {
        LOG_ERROR(c, "fmi3EnterEventMode: the instance was created with eventModeUsed = false.");
        return fmi3Error;
    }
    c->mode = MODE_EVENT;
    return fmi3OK;
}

fmi3Status fmi3Terminate(fmi3Instance instance) {
    Instance *c = (Instance *)instance;
    if (!allowed(c, "fmi3Terminate", -1,
                 MODE_INITIALIZATION | MODE_EVENT | MODE_CONTINUOUS | MODE_STEP))
        return fmi3Error;
    c->mode = MODE_TERMINATED;
    return fmi3OK;
}

fmi3Status fmi3Reset(fmi3Instance instance) {
    Instance *c = (Instance *)instance;
    if (c == NULL) return fmi3Error;
    set_defaults(c);
    c->mode = MODE_INSTANTIATED;
    return fmi3OK;
}

fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, fmi3Float64 values[], size_t nValues) {
    Instance *c = (Instance *)instance;
    size_t i;
    if (c == NULL) return fmi3Error;
    if (!check_sizes(c, "fmi3GetFloat64", valueReferences, nValueReferences, values, nValues))
        return fmi3Error;
    for (i = 0; i < nValueReferences; i++) {
        if (get_value(c, valueReferences[i], &values[i]) != fmi3OK) return fmi3Error;
    }
    return fmi3OK;
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, const fmi3Float64 values[], size_t nValues) {
    Instance *c = (Instance *)instance;
    size_t i;
    if (c == NULL) return fmi3Error;
    if (!check_sizes(c, "fmi3SetFloat64", valueReferences, nValueReferences, values, nValues))
        return fmi3Error;
    for (i = 0; i < nValueReferences; i++) {
        if (set_value(c, valueReferences[i], values[i]) != fmi3OK) return fmi3Error;
    }
    return fmi3OK;
}

#define NO_VARIABLES_GET(function, type)                                                      \
    fmi3Status function(fmi3Instance instance, const fmi3ValueReference valueReferences[],    \
                        size_t nValueReferences, type values[], size_t nValues) {             \
        (void)values;                                                                         \
        (void)nValues;                                                                        \
        return no_variables(instance, #function, valueReferences, nValueReferences);          \
    }

#define NO_VARIABLES_SET(function, type)                                                      \
    fmi3Status function(fmi3Instance instance, const fmi3ValueReference valueReferences[],    \
                        size_t nValueReferences, const type values[], size_t nValues) {       \
        (void)values;                                                                         \
        (void)nValues;                                                                        \
        return no_variables(instance, #function, valueReferences, nValueReferences);          \
    }

NO_VARIABLES_GET(fmi3GetFloat32, fmi3Float32)
NO_VARIABLES_GET(fmi3GetInt8, fmi3Int8)
NO_VARIABLES_GET(fmi3GetUInt8, fmi3UInt8)
NO_VARIABLES_GET(fmi3GetInt16, fmi3Int16)
NO_VARIABLES_GET(fmi3GetUInt16, fmi3UInt16)
NO_VARIABLES_GET(fmi3GetInt32, fmi3Int32)
NO_VARIABLES_GET(fmi3GetUInt32, fmi3UInt32)
NO_VARIABLES_GET(fmi3GetInt64, fmi3Int64)
NO_VARIABLES_GET(fmi3GetUInt64, fmi3UInt64)
NO_VARIABLES_GET(fmi3GetBoolean, fmi3Boolean)
NO_VARIABLES_GET(fmi3GetString, fmi3String)

NO_VARIABLES_SET(fmi3SetFloat32, fmi3Float32)
NO_VARIABLES_SET(fmi3SetInt8, fmi3Int8)
NO_VARIABLES_SET(fmi3SetUInt8, fmi3UInt8)
NO_VARIABLES_SET(fmi3SetInt16, fmi3Int16)
NO_VARIABLES_SET(fmi3SetUInt16, fmi3UInt16)
NO_VARIABLES_SET(fmi3SetInt32, fmi3Int32)
NO_VARIABLES_SET(fmi3SetUInt32, fmi3UInt32)
NO_VARIABLES_SET(fmi3SetInt64, fmi3Int64)
NO_VARIABLES_SET(fmi3SetUInt64, fmi3UInt64)
NO_VARIABLES_SET(fmi3SetBoolean, fmi3Boolean)
NO_VARIABLES_SET(fmi3SetString, fmi3String)

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, size_t valueSizes[], fmi3Binary values[],
                         size_t nValues) {
    (void)valueSizes;
    (void)values;
    (void)nValues;
    return no_variables(instance, "fmi3GetBinary", valueReferences, nValueReferences);
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                         size_t nValueReferences, const size_t valueSizes[],
                         const fmi3Binary values[], size_t nValues) {
    (void)valueSizes;
    (void)values;
    (void)nValues;
    return no_variables(instance, "fmi3SetBinary", valueReferences, nValueReferences);
}

fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, fmi3Clock values[]) {
    (void)values;
    return no_variables(instance, "fmi3GetClock", valueReferences, nValueReferences);
}

fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                        size_t nValueReferences, const fmi3Clock values[]) {
    (void)values;
    return no_variables(instance, "fmi3SetClock", valueReferences, nValueReferences);
}

/* Variable dependencies, FMU state, derivatives, configuration mode, clocks: not supported
 * (modelDescription.xml declares none of these capabilities). */

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance,
                                               fmi3ValueReference valueReference,
                                               size_t *nDependencies) {
    (void)valueReference;
    (void)nDependencies;
    return unsupported(instance, "fmi3GetNumberOfVariableDependencies");
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[],
                                       fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[],
                                       fmi3DependencyKind dependencyKinds[],
                                       size_t nDependencies) {
    (void)dependent;
    (void)elementIndicesOfDependent;
    (void)independents;
    (void)elementIndicesOfIndependents;
    (void)dependencyKinds;
    (void)nDependencies;
    return unsupported(instance, "fmi3GetVariableDependencies");
}

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *FMUState) {
    (void)FMUState;
    return unsupported(instance, "fmi3GetFMUState");
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState) {
    (void)FMUState;
    return unsupported(instance, "fmi3SetFMUState");
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *FMUState) {
    (void)FMUState;
    return unsupported(instance, "fmi3FreeFMUState");
}

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState FMUState,
                                      size_t *size) {
    (void)FMUState;
    (void)size;
    return unsupported(instance, "fmi3SerializedFMUStateSize");
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState FMUState,
                                 fmi3Byte serializedState[], size_t size) {
    (void)FMUState;
    (void)serializedState;
    (void)size;
    return unsupported(instance, "fmi3SerializeFMUState");
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte serializedState[],
                                   size_t size, fmi3FMUState *FMUState) {
    (void)serializedState;
    (void)size;
    (void)FMUState;
    return unsupported(instance, "fmi3DeserializeFMUState");
}

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[],
                                        size_t nUnknowns, const fmi3ValueReference knowns[],
                                        size_t nKnowns, const fmi3Float64 seed[], size_t nSeed,
                                        fmi3Float64 sensitivity[], size_t nSensitivity) {
    (void)unknowns;
    (void)nUnknowns;
    (void)knowns;
    (void)nKnowns;
    (void)seed;
    (void)nSeed;
    (void)sensitivity;
    (void)nSensitivity;
    return unsupported(instance, "fmi3GetDirectionalDerivative");
}

fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[],
                                    size_t nUnknowns, const fmi3ValueReference knowns[],
                                    size_t nKnowns, const fmi3Float64 seed[], size_t nSeed,
                                    fmi3Float64 sensitivity[], size_t nSensitivity) {
    (void)unknowns;
    (void)nUnknowns;
    (void)knowns;
    (void)nKnowns;
    (void)seed;
    (void)nSeed;
    (void)sensitivity;
    (void)nSensitivity;
    return unsupported(instance, "fmi3GetAdjointDerivative");
}

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance) {
    return unsupported(instance, "fmi3EnterConfigurationMode");
}

fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance) {
    return unsupported(instance, "fmi3ExitConfigurationMode");
}

fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, fmi3Float64 intervals[],
                                  fmi3IntervalQualifier qualifiers[]) {
    (void)valueReferences;
    (void)nValueReferences;
    (void)intervals;
    (void)qualifiers;
    return unsupported(instance, "fmi3GetIntervalDecimal");
}

fmi3Status fmi3GetIntervalFraction(fmi3Instance instance,
                                   const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, fmi3UInt64 counters[],
                                   fmi3UInt64 resolutions[], fmi3IntervalQualifier qualifiers[]) {
    (void)valueReferences;
    (void)nValueReferences;
    (void)counters;
    (void)resolutions;
    (void)qualifiers;
    return unsupported(instance, "fmi3GetIntervalFraction");
}

fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                               size_t nValueReferences, fmi3Float64 shifts[]) {
    (void)valueReferences;
    (void)nValueReferences;
    (void)shifts;
    return unsupported(instance, "fmi3GetShiftDecimal");
}

fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                size_t nValueReferences, fmi3UInt64 counters[],
                                fmi3UInt64 resolutions[]) {
    (void)valueReferences;
    (void)nValueReferences;
    (void)counters;
    (void)resolutions;
    return unsupported(instance, "fmi3GetShiftFraction");
}

fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                  size_t nValueReferences, const fmi3Float64 intervals[]) {
    (void)valueReferences;
    (void)nValueReferences;
    (void)intervals;
    return unsupported(instance, "fmi3SetIntervalDecimal");
}

fmi3Status fmi3SetIntervalFraction(fmi3Instance instance,
                                   const fmi3ValueReference valueReferences[],
                                   size_t nValueReferences, const fmi3UInt64 counters[],
                                   const fmi3UInt64 resolutions[]) {
    (void)valueReferences;
    (void)nValueReferences;
    (void)counters;
    (void)resolutions;
    return unsupported(instance, "fmi3SetIntervalFraction");
}

fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                               size_t nValueReferences, const fmi3Float64 shifts[]) {
    (void)valueReferences;
    (void)nValueReferences;
    (void)shifts;
    return unsupported(instance, "fmi3SetShiftDecimal");
}

fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                                size_t nValueReferences, const fmi3UInt64 counters[],
                                const fmi3UInt64 resolutions[]) {
    (void)valueReferences;
    (void)nValueReferences;
    (void)counters;
    (void)resolutions;
    return unsupported(instance, "fmi3SetShiftFraction");
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance) {
    Instance *c = (Instance *)instance;
    if (!allowed(c, "fmi3EvaluateDiscreteStates", -1, MODE_EVENT | MODE_STEP)) return fmi3Error;
    return fmi3OK; /* no discrete states */
}

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation,
                                    fmi3Boolean *nominalsOfContinuousStatesChanged,
                                    fmi3Boolean *valuesOfContinuousStatesChanged,
                                    fmi3Boolean *nextEventTimeDefined,
                                    fmi3Float64 *nextEventTime) {
    Instance *c = (Instance *)instance;
    if (!allowed(c, "fmi3UpdateDiscreteStates", -1, MODE_EVENT)) return fmi3Error;
    if (discreteStatesNeedUpdate != NULL) *discreteStatesNeedUpdate = fmi3False;
    if (terminateSimulation != NULL) *terminateSimulation = fmi3False;
    if (nominalsOfContinuousStatesChanged != NULL) *nominalsOfContinuousStatesChanged = fmi3False;
    if (valuesOfContinuousStatesChanged != NULL) *valuesOfContinuousStatesChanged = fmi3False;
    if (nextEventTimeDefined != NULL) *nextEventTimeDefined = fmi3False;
    if (nextEventTime != NULL) *nextEventTime = 0.0;
    return fmi3OK;
}

/* ---------------------------------------------------------------------------------------- */
/* Model Exchange                                                                           */
/* ---------------------------------------------------------------------------------------- */

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance) {
    Instance *c = (Instance *)instance;
    if (!allowed(c, "fmi3EnterContinuousTimeMode", TYPE_MODEL_EXCHANGE, MODE_EVENT))
        return fmi3Error;
    c->mode = MODE_CONTINUOUS;
    return fmi3OK;
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance,
                                       fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode,
                                       fmi3Boolean *terminateSimulation) {
    Instance *c = (Instance *)instance;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!allowed(c, "fmi3CompletedIntegratorStep", TYPE_MODEL_EXCHANGE, MODE_CONTINUOUS))
        return fmi3Error;
    if (enterEventMode != NULL) *enterEventMode = fmi3False;
    if (terminateSimulation != NULL) *terminateSimulation = fmi3False;
    return fmi3OK;
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time) {
    Instance *c = (Instance *)instance;
    if (!allowed(c, "fmi3SetTime", TYPE_MODEL_EXCHANGE, MODE_EVENT | MODE_CONTINUOUS))
        return fmi3Error;
    c->time = time;
    return fmi3OK;
}

static int check_nx(Instance *c, const char *function, const void *array, size_t nx) {
    if (nx != N_STATES || array == NULL) {
        LOG_ERROR(c, "%s: expected an array of %d continuous states, got %lu.", function,
                  N_STATES, (unsigned long)nx);
        return 0;
    }
    return 1;
}

#define ME_QUERY_MODES (MODE_INITIALIZATION | MODE_EVENT | MODE_CONTINUOUS | MODE_TERMINATED)

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 continuousStates[],
                                   size_t nContinuousStates) {
    Instance *c = (Instance *)instance;
    if (!allowed(c, "fmi3SetContinuousStates", TYPE_MODEL_EXCHANGE, MODE_CONTINUOUS))
        return fmi3Error;
    if (!check_nx(c, "fmi3SetContinuousStates", continuousStates, nContinuousStates))
        return fmi3Error;
    c->x.w = continuousStates[0];
    c->x.v = continuousStates[1];
    return fmi3OK;
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[],
                                             size_t nContinuousStates) {
    Instance *c = (Instance *)instance;
    if (!allowed(c, "fmi3GetContinuousStateDerivatives", TYPE_MODEL_EXCHANGE, ME_QUERY_MODES))
        return fmi3Error;
    if (!check_nx(c, "fmi3GetContinuousStateDerivatives", derivatives, nContinuousStates))
        return fmi3Error;
    derivatives[0] = c->x.v;
    derivatives[1] = cantilever_acceleration(&c->p, c->F, c->x.w, c->x.v);
    return fmi3OK;
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 eventIndicators[],
                                  size_t nEventIndicators) {
    Instance *c = (Instance *)instance;
    (void)eventIndicators;
    if (!allowed(c, "fmi3GetEventIndicators", TYPE_MODEL_EXCHANGE, ME_QUERY_MODES))
        return fmi3Error;
    if (nEventIndicators != 0) {
        LOG_ERROR(c, "fmi3GetEventIndicators: this model has no event indicators, got %lu.",
                  (unsigned long)nEventIndicators);
        return fmi3Error;
    }
    return fmi3OK;
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 continuousStates[],
                                   size_t nContinuousStates) {
    Instance *c = (Instance *)instance;
    if (!allowed(c, "fmi3GetContinuousStates", TYPE_MODEL_EXCHANGE, ME_QUERY_MODES))
        return fmi3Error;
    if (!check_nx(c, "fmi3GetContinuousStates", continuousStates, nContinuousStates))
        return fmi3Error;
    continuousStates[0] = c->x.w;
    continuousStates[1] = c->x.v;
    return fmi3OK;
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[],
                                             size_t nContinuousStates) {
    Instance *c = (Instance *)instance;
    if (!allowed(c, "fmi3GetNominalsOfContinuousStates", TYPE_MODEL_EXCHANGE,
                 MODE_INSTANTIATED | ME_QUERY_MODES))
        return fmi3Error;
    if (!check_nx(c, "fmi3GetNominalsOfContinuousStates", nominals, nContinuousStates))
        return fmi3Error;
    nominals[0] = NOMINAL_W;
    nominals[1] = NOMINAL_V;
    return fmi3OK;
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *nEventIndicators) {
    Instance *c = (Instance *)instance;
    if (c == NULL || nEventIndicators == NULL) return fmi3Error;
    *nEventIndicators = 0;
    return fmi3OK;
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *nContinuousStates) {
    Instance *c = (Instance *)instance;
    if (c == NULL || nContinuousStates == NULL) return fmi3Error;
    *nContinuousStates = N_STATES;
    return fmi3OK;
}

/* ---------------------------------------------------------------------------------------- */
/* Co-Simulation                                                                            */
/* ---------------------------------------------------------------------------------------- */

fmi3Status fmi3EnterStepMode(fmi3Instance instance) {
    Instance *c = (Instance *)instance;
    if (!allowed(c, "fmi3EnterStepMode", TYPE_CO_SIMULATION, MODE_EVENT)) return fmi3Error;
    c->mode = MODE_STEP;
    return fmi3OK;
}

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance,
                                    const fmi3ValueReference valueReferences[],
                                    size_t nValueReferences, const fmi3Int32 orders[],
                                    fmi3Float64 values[], size_t nValues) {
    (void)valueReferences;
    (void)nValueReferences;
    (void)orders;
    (void)values;
    (void)nValues;
    return unsupported(instance, "fmi3GetOutputDerivatives");
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize,
                      fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation,
                      fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime) {
    Instance *c = (Instance *)instance;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!allowed(c, "fmi3DoStep", TYPE_CO_SIMULATION, MODE_STEP)) return fmi3Error;
    if (!isfinite(communicationStepSize) || communicationStepSize < 0.0) {
        LOG_ERROR(c, "fmi3DoStep: the communication step size must be >= 0, got %g.",
                  communicationStepSize);
        return fmi3Error;
    }
    cantilever_step(&c->p, c->F, communicationStepSize, &c->x);
    c->time = currentCommunicationPoint + communicationStepSize;
    if (eventHandlingNeeded != NULL) *eventHandlingNeeded = fmi3False;
    if (terminateSimulation != NULL) *terminateSimulation = fmi3False;
    if (earlyReturn != NULL) *earlyReturn = fmi3False;
    if (lastSuccessfulTime != NULL) *lastSuccessfulTime = c->time;
    return fmi3OK;
}

/* ---------------------------------------------------------------------------------------- */
/* Scheduled Execution                                                                      */
/* ---------------------------------------------------------------------------------------- */

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                      fmi3Float64 activationTime) {
    (void)clockReference;
    (void)activationTime;
    return unsupported(instance, "fmi3ActivateModelPartition");
}
