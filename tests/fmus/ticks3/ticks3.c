/*
 * ticks3.c - a test FMU (FMI 3.0 Co-Simulation) with a time event at every whole second:
 * counter = 1 + floor(t). When early return is allowed, an fmi3DoStep that would pass the next
 * whole second stops on it and returns fmi3OK with earlyReturn true and lastSuccessfulTime
 * that second, terminateRequested false: an early return without termination, as an FMU that
 * cannot step over an event does; a master goes on from there. Without early return it steps
 * over. Written on the boilerplate of ../stair/fmi3 (the Stair FMU that terminates).
 *
 * Value references: 1 time (independent), 2 counter (output, Float64). It can save and
 * restore its state (canGetAndSetFMUState). The functions this FMU does not support are in
 * unsupported.c.
 */
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"

#define TOKEN "{9d4b2e6c-1f3a-4c8d-b7e5-0a2c4e6f8b1d}"
#define EPS 1e-9

enum { VR_TIME = 1, VR_COUNTER = 2 };

typedef enum { MODE_INSTANTIATED, MODE_INITIALIZATION, MODE_STEP, MODE_TERMINATED } Mode;

typedef struct {
    char *name;
    fmi3InstanceEnvironment env;
    fmi3LogMessageCallback log;
    fmi3Boolean logging_on;
    Mode mode;
    fmi3Float64 time;
    fmi3Boolean terminated;
    fmi3Boolean early_return_allowed;
} Instance;

static void log_message(const Instance *c, fmi3Status status, const char *category,
                        const char *fmt, ...) {
    char text[512];
    va_list args;
    if (c == NULL || c->log == NULL) return;
    if (status < fmi3Error && !c->logging_on) return;
    va_start(args, fmt);
    vsnprintf(text, sizeof text, fmt, args);
    va_end(args);
    c->log(c->env, status, category, text);
}

#define LOG_ERROR(c, ...) log_message((c), fmi3Error, "logStatusError", __VA_ARGS__)

/* Called by the stubs of unsupported.c. */
int ticks3_unsupported(void *instance, const char *function);
int ticks3_unsupported(void *instance, const char *function) {
    LOG_ERROR((Instance *)instance, "%s is not supported by this FMU.", function);
    return fmi3Error;
}

static double counter(const Instance *c) { return 1.0 + floor(c->time + EPS); }

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[]) {
    (void)nCategories;
    (void)categories;
    if (instance == NULL) return fmi3Error;
    ((Instance *)instance)->logging_on = loggingOn;
    return fmi3OK;
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible,
                                          fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment,
                                          fmi3LogMessageCallback logMessage) {
    Instance probe = {(char *)instanceName, instanceEnvironment, logMessage, loggingOn,
                      MODE_INSTANTIATED, 0.0, fmi3False, fmi3False};
    (void)instantiationToken;
    (void)resourcePath;
    (void)visible;
    LOG_ERROR(&probe, "fmi3InstantiateModelExchange: this FMU supports Co-Simulation only.");
    return NULL;
}

fmi3Instance fmi3InstantiateCoSimulation(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3Boolean eventModeUsed,
    fmi3Boolean earlyReturnAllowed, const fmi3ValueReference requiredIntermediateVariables[],
    size_t nRequiredIntermediateVariables, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3IntermediateUpdateCallback intermediateUpdate) {
    Instance probe = {(char *)instanceName, instanceEnvironment, logMessage, loggingOn,
                      MODE_INSTANTIATED, 0.0, fmi3False, fmi3False};
    Instance *c;
    size_t len;
    (void)resourcePath;
    (void)visible;
    (void)eventModeUsed;
    (void)requiredIntermediateVariables;
    (void)nRequiredIntermediateVariables;
    (void)intermediateUpdate;
    if (instanceName == NULL) return NULL;
    if (instantiationToken == NULL || strcmp(instantiationToken, TOKEN) != 0) {
        LOG_ERROR(&probe, "fmi3InstantiateCoSimulation: wrong instantiation token.");
        return NULL;
    }
    c = (Instance *)calloc(1, sizeof(Instance));
    len = strlen(instanceName) + 1;
    if (c != NULL) c->name = (char *)malloc(len);
    if (c == NULL || c->name == NULL) {
        LOG_ERROR(&probe, "fmi3InstantiateCoSimulation: out of memory.");
        free(c);
        return NULL;
    }
    memcpy(c->name, instanceName, len);
    c->env = instanceEnvironment;
    c->log = logMessage;
    c->logging_on = loggingOn;
    c->early_return_allowed = earlyReturnAllowed;
    c->mode = MODE_INSTANTIATED;
    return c;
}

fmi3Instance fmi3InstantiateScheduledExecution(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment instanceEnvironment,
    fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate,
    fmi3LockPreemptionCallback lockPreemption, fmi3UnlockPreemptionCallback unlockPreemption) {
    Instance probe = {(char *)instanceName, instanceEnvironment, logMessage, loggingOn,
                      MODE_INSTANTIATED, 0.0, fmi3False, fmi3False};
    (void)instantiationToken;
    (void)resourcePath;
    (void)visible;
    (void)clockUpdate;
    (void)lockPreemption;
    (void)unlockPreemption;
    LOG_ERROR(&probe, "fmi3InstantiateScheduledExecution: this FMU supports Co-Simulation only.");
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
    if (c == NULL || c->mode != MODE_INSTANTIATED) return fmi3Error;
    c->time = startTime;
    c->mode = MODE_INITIALIZATION;
    return fmi3OK;
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
    Instance *c = (Instance *)instance;
    if (c == NULL || c->mode != MODE_INITIALIZATION) return fmi3Error;
    c->mode = MODE_STEP;
    return fmi3OK;
}

fmi3Status fmi3Terminate(fmi3Instance instance) {
    Instance *c = (Instance *)instance;
    if (c == NULL) return fmi3Error;
    c->mode = MODE_TERMINATED;
    return fmi3OK;
}

fmi3Status fmi3Reset(fmi3Instance instance) {
    Instance *c = (Instance *)instance;
    if (c == NULL) return fmi3Error;
    c->mode = MODE_INSTANTIATED;
    c->time = 0.0;
    c->terminated = fmi3False;
    return fmi3OK;
}

fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, fmi3Float64 values[], size_t nValues) {
    Instance *c = (Instance *)instance;
    size_t i;
    if (c == NULL) return fmi3Error;
    if (nValues != nValueReferences) {
        LOG_ERROR(c, "fmi3GetFloat64: nValues %zu != nValueReferences %zu.", nValues,
                  nValueReferences);
        return fmi3Error;
    }
    for (i = 0; i < nValueReferences; i++) {
        switch (valueReferences[i]) {
            case VR_TIME: values[i] = c->time; break;
            case VR_COUNTER: values[i] = counter(c); break;
            default:
                LOG_ERROR(c, "fmi3GetFloat64: unknown value reference %u.",
                          (unsigned)valueReferences[i]);
                return fmi3Error;
        }
    }
    return fmi3OK;
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference valueReferences[],
                          size_t nValueReferences, const fmi3Float64 values[], size_t nValues) {
    Instance *c = (Instance *)instance;
    (void)valueReferences;
    (void)values;
    (void)nValues;
    if (c == NULL) return fmi3Error;
    if (nValueReferences == 0) return fmi3OK;
    LOG_ERROR(c, "fmi3SetFloat64: this FMU has no variable that can be set.");
    return fmi3Error;
}

/* FMU state (canGetAndSetFMUState): the time and whether it ended, for a var-step master's
 * rollback. */
typedef struct {
    Mode mode;
    fmi3Float64 time;
    fmi3Boolean terminated;
} SavedState;

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *FMUState) {
    Instance *c = (Instance *)instance;
    SavedState *saved;
    if (c == NULL || FMUState == NULL) return fmi3Error;
    saved = *FMUState != NULL ? (SavedState *)*FMUState : (SavedState *)malloc(sizeof *saved);
    if (saved == NULL) {
        LOG_ERROR(c, "fmi3GetFMUState: out of memory.");
        return fmi3Error;
    }
    saved->mode = c->mode;
    saved->time = c->time;
    saved->terminated = c->terminated;
    *FMUState = saved;
    return fmi3OK;
}

fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState FMUState) {
    Instance *c = (Instance *)instance;
    const SavedState *saved = (const SavedState *)FMUState;
    if (c == NULL || saved == NULL) return fmi3Error;
    c->mode = saved->mode;
    c->time = saved->time;
    c->terminated = saved->terminated;
    return fmi3OK;
}

fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *FMUState) {
    if (instance == NULL || FMUState == NULL) return fmi3Error;
    free(*FMUState);
    *FMUState = NULL;
    return fmi3OK;
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize,
                      fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation,
                      fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime) {
    Instance *c = (Instance *)instance;
    fmi3Float64 end = currentCommunicationPoint + communicationStepSize, tick;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (c == NULL || c->mode != MODE_STEP) return fmi3Error;
    if (c->terminated) {
        LOG_ERROR(c, "fmi3DoStep: the simulation has ended at t = %g s.", c->time);
        return fmi3Error;
    }
    *eventHandlingNeeded = fmi3False;
    *terminateSimulation = fmi3False;
    *earlyReturn = fmi3False;
    tick = floor(c->time + EPS) + 1.0; /* the next whole second */
    if (c->early_return_allowed && end > tick + EPS) {
        *earlyReturn = fmi3True;
        end = tick;
        log_message(c, fmi3OK, "logEvents", "a tick at t = %g s: the step returns there", tick);
    }
    c->time = end;
    *lastSuccessfulTime = end;
    return fmi3OK;
}
