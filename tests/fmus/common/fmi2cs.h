/*
 * fmi2cs.h - the FMI 2.0 Co-Simulation boilerplate of the small test FMUs in tests/fmus.
 *
 * Each test FMU folder holds a symbolic link to this file, so the FMU's sources/ folder is
 * self-contained. It implements every fmi2 function (FMPy loads them all); Model Exchange,
 * FMU state and derivatives are refused with fmi2Error and a logged message, except FMU state
 * (get, set, free; not serialization) in a model that defines MODEL_FMU_STATE (and declares
 * canGetAndSetFMUstate="true"), for the var-step master's rollback.
 *
 * The model file defines, before including this header:
 *     MODEL_GUID     the guid of its modelDescription.xml
 *     N_REALS        the number of Real variables; value reference i is c->r[i]
 * and, after including it:
 *     static void model_defaults(Instance *c);              start values into c->r
 *     static int model_settable(fmi2ValueReference vr);     1 for inputs and parameters
 *     static void model_outputs(Instance *c);               outputs from inputs (before get)
 *     static fmi2Status model_do_step(Instance *c, fmi2Real h);
 * Only Real variables exist. Errors are always logged; other messages only with logging on.
 * A model may set c->terminated (fmi2GetBooleanStatus(fmi2Terminated) says it) and return
 * fmi2Discard from model_do_step, with c->time where it stopped. A model that defines
 * MODEL_REFUSE_INSTANCE implements static int model_refuse(Instance *probe): nonzero makes
 * fmi2Instantiate fail (after the model logged why) and return NULL.
 */
#ifndef TEST_FMI2CS_H
#define TEST_FMI2CS_H

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"

typedef enum {
    MODE_INSTANTIATED,
    MODE_INITIALIZATION,
    MODE_STEP,
    MODE_TERMINATED
} Mode;

typedef struct {
    char *name;
    fmi2CallbackFunctions cb;
    fmi2Boolean logging_on;
    Mode mode;
    fmi2Real time;
    fmi2Boolean terminated;
    fmi2Real r[N_REALS];
} Instance;

static void model_defaults(Instance *c);
static int model_settable(fmi2ValueReference vr);
static void model_outputs(Instance *c);
static fmi2Status model_do_step(Instance *c, fmi2Real h);
#ifdef MODEL_REFUSE_INSTANCE
static int model_refuse(Instance *probe);
#endif

/* The message is formatted here and its '%' doubled: the logger treats it as a format. */
static void log_message(const Instance *c, fmi2Status status, const char *category,
                        const char *fmt, ...) {
    char text[512];
    char escaped[1024];
    size_t i, j;
    va_list args;

    if (c == NULL || c->cb.logger == NULL) return;
    if (status < fmi2Error && !c->logging_on) return;
    va_start(args, fmt);
    vsnprintf(text, sizeof text, fmt, args);
    va_end(args);
    for (i = 0, j = 0; text[i] != '\0' && j + 2 < sizeof escaped; i++) {
        if (text[i] == '%') escaped[j++] = '%';
        escaped[j++] = text[i];
    }
    escaped[j] = '\0';
    c->cb.logger(c->cb.componentEnvironment, c->name, status, category, escaped);
}

#define LOG_ERROR(c, ...) log_message((c), fmi2Error, "logStatusError", __VA_ARGS__)

static fmi2Status unsupported(fmi2Component c, const char *function) {
    LOG_ERROR((Instance *)c, "%s is not supported by this FMU.", function);
    return fmi2Error;
}

static int in_mode(Instance *c, const char *function, int ok) {
    if (c == NULL) return 0;
    if (!ok) LOG_ERROR(c, "%s must not be called in mode %d.", function, (int)c->mode);
    return ok;
}

static fmi2Status no_variables(fmi2Component c, const char *function, size_t nvr) {
    if (c == NULL) return fmi2Error;
    if (nvr == 0) return fmi2OK;
    LOG_ERROR((Instance *)c, "%s: this model has only Real variables.", function);
    return fmi2Error;
}

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }

const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[]) {
    (void)nCategories;
    (void)categories;
    if (c == NULL) return fmi2Error;
    ((Instance *)c)->logging_on = loggingOn;
    return fmi2OK;
}

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation,
                              const fmi2CallbackFunctions *functions, fmi2Boolean visible,
                              fmi2Boolean loggingOn) {
    Instance probe;
    Instance *c;
    size_t len;

    (void)fmuResourceLocation;
    (void)visible;
    if (functions == NULL || instanceName == NULL) return NULL;
    memset(&probe, 0, sizeof probe);
    probe.cb = *functions;
    probe.name = (char *)instanceName;
    probe.logging_on = loggingOn;
    if (fmuType != fmi2CoSimulation) {
        LOG_ERROR(&probe, "fmi2Instantiate: this FMU supports Co-Simulation only.");
        return NULL;
    }
    if (fmuGUID == NULL || strcmp(fmuGUID, MODEL_GUID) != 0) {
        LOG_ERROR(&probe, "fmi2Instantiate: wrong GUID.");
        return NULL;
    }
#ifdef MODEL_REFUSE_INSTANCE
    if (model_refuse(&probe)) return NULL;
#endif
    c = (Instance *)calloc(1, sizeof(Instance));
    len = strlen(instanceName) + 1;
    if (c != NULL) c->name = (char *)malloc(len);
    if (c == NULL || c->name == NULL) {
        LOG_ERROR(&probe, "fmi2Instantiate: out of memory.");
        free(c);
        return NULL;
    }
    memcpy(c->name, instanceName, len);
    c->cb = *functions;
    c->logging_on = loggingOn;
    c->mode = MODE_INSTANTIATED;
    model_defaults(c);
    return c;
}

void fmi2FreeInstance(fmi2Component c) {
    Instance *inst = (Instance *)c;
    if (inst == NULL) return;
    free(inst->name);
    free(inst);
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined,
                               fmi2Real stopTime) {
    Instance *inst = (Instance *)c;
    (void)toleranceDefined;
    (void)tolerance;
    (void)stopTimeDefined;
    (void)stopTime;
    if (!in_mode(inst, "fmi2SetupExperiment", inst != NULL && inst->mode == MODE_INSTANTIATED))
        return fmi2Error;
    inst->time = startTime;
    return fmi2OK;
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) {
    Instance *inst = (Instance *)c;
    if (!in_mode(inst, "fmi2EnterInitializationMode",
                 inst != NULL && inst->mode == MODE_INSTANTIATED))
        return fmi2Error;
    inst->mode = MODE_INITIALIZATION;
    return fmi2OK;
}

fmi2Status fmi2ExitInitializationMode(fmi2Component c) {
    Instance *inst = (Instance *)c;
    if (!in_mode(inst, "fmi2ExitInitializationMode",
                 inst != NULL && inst->mode == MODE_INITIALIZATION))
        return fmi2Error;
    inst->mode = MODE_STEP;
    return fmi2OK;
}

fmi2Status fmi2Terminate(fmi2Component c) {
    Instance *inst = (Instance *)c;
    if (inst == NULL) return fmi2Error;
    inst->mode = MODE_TERMINATED;
    return fmi2OK;
}

fmi2Status fmi2Reset(fmi2Component c) {
    Instance *inst = (Instance *)c;
    if (inst == NULL) return fmi2Error;
    inst->mode = MODE_INSTANTIATED;
    inst->time = 0.0;
    inst->terminated = fmi2False;
    model_defaults(inst);
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
    model_outputs(inst);
    for (i = 0; i < nvr; i++) {
        if (vr[i] >= N_REALS) {
            LOG_ERROR(inst, "fmi2GetReal: unknown value reference %u.", vr[i]);
            return fmi2Error;
        }
        value[i] = inst->r[vr[i]];
    }
    return fmi2OK;
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
        if (vr[i] >= N_REALS) {
            LOG_ERROR(inst, "fmi2SetReal: unknown value reference %u.", vr[i]);
            return fmi2Error;
        }
        if (!model_settable(vr[i])) {
            LOG_ERROR(inst, "fmi2SetReal: value reference %u cannot be set.", vr[i]);
            return fmi2Error;
        }
        inst->r[vr[i]] = value[i];
    }
    return fmi2OK;
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          fmi2Integer value[]) {
    (void)vr;
    (void)value;
    return no_variables(c, "fmi2GetInteger", nvr);
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          fmi2Boolean value[]) {
    (void)vr;
    (void)value;
    return no_variables(c, "fmi2GetBoolean", nvr);
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         fmi2String value[]) {
    (void)vr;
    (void)value;
    return no_variables(c, "fmi2GetString", nvr);
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          const fmi2Integer value[]) {
    (void)vr;
    (void)value;
    return no_variables(c, "fmi2SetInteger", nvr);
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                          const fmi2Boolean value[]) {
    (void)vr;
    (void)value;
    return no_variables(c, "fmi2SetBoolean", nvr);
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                         const fmi2String value[]) {
    (void)vr;
    (void)value;
    return no_variables(c, "fmi2SetString", nvr);
}

#ifdef MODEL_FMU_STATE
/* The whole state but the name and callbacks: what a rollback restores. */
typedef struct {
    Mode mode;
    fmi2Real time;
    fmi2Boolean terminated;
    fmi2Real r[N_REALS];
} SavedState;

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s) {
    Instance *inst = (Instance *)c;
    SavedState *saved;
    if (inst == NULL || s == NULL) return fmi2Error;
    saved = *s != NULL ? (SavedState *)*s : (SavedState *)malloc(sizeof(SavedState));
    if (saved == NULL) {
        LOG_ERROR(inst, "fmi2GetFMUstate: out of memory.");
        return fmi2Error;
    }
    saved->mode = inst->mode;
    saved->time = inst->time;
    saved->terminated = inst->terminated;
    memcpy(saved->r, inst->r, sizeof saved->r);
    *s = saved;
    return fmi2OK;
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s) {
    Instance *inst = (Instance *)c;
    const SavedState *saved = (const SavedState *)s;
    if (inst == NULL || saved == NULL) return fmi2Error;
    inst->mode = saved->mode;
    inst->time = saved->time;
    inst->terminated = saved->terminated;
    memcpy(inst->r, saved->r, sizeof inst->r);
    return fmi2OK;
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s) {
    if (c == NULL || s == NULL) return fmi2Error;
    free(*s);
    *s = NULL;
    return fmi2OK;
}
#else
fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s) {
    (void)s;
    return unsupported(c, "fmi2GetFMUstate");
}

fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s) {
    (void)s;
    return unsupported(c, "fmi2SetFMUstate");
}

fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s) {
    (void)s;
    return unsupported(c, "fmi2FreeFMUstate");
}
#endif

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *size) {
    (void)s;
    (void)size;
    return unsupported(c, "fmi2SerializedFMUstateSize");
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte bytes[],
                                 size_t size) {
    (void)s;
    (void)bytes;
    (void)size;
    return unsupported(c, "fmi2SerializeFMUstate");
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size,
                                   fmi2FMUstate *s) {
    (void)bytes;
    (void)size;
    (void)s;
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

/* Model Exchange: not supported (Co-Simulation only). */

fmi2Status fmi2EnterEventMode(fmi2Component c) { return unsupported(c, "fmi2EnterEventMode"); }

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info) {
    (void)info;
    return unsupported(c, "fmi2NewDiscreteStates");
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) {
    return unsupported(c, "fmi2EnterContinuousTimeMode");
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetPrior,
                                       fmi2Boolean *enterEventMode,
                                       fmi2Boolean *terminateSimulation) {
    (void)noSetPrior;
    (void)enterEventMode;
    (void)terminateSimulation;
    return unsupported(c, "fmi2CompletedIntegratorStep");
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time) {
    (void)time;
    return unsupported(c, "fmi2SetTime");
}

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx) {
    (void)x;
    (void)nx;
    return unsupported(c, "fmi2SetContinuousStates");
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx) {
    (void)derivatives;
    (void)nx;
    return unsupported(c, "fmi2GetDerivatives");
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni) {
    (void)eventIndicators;
    (void)ni;
    return unsupported(c, "fmi2GetEventIndicators");
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx) {
    (void)x;
    (void)nx;
    return unsupported(c, "fmi2GetContinuousStates");
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx) {
    (void)x_nominal;
    (void)nx;
    return unsupported(c, "fmi2GetNominalsOfContinuousStates");
}

/* Co-Simulation */

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
    fmi2Status status;
    (void)noSetFMUStatePriorToCurrentPoint;
    if (!in_mode(inst, "fmi2DoStep", inst != NULL && inst->mode == MODE_STEP)) return fmi2Error;
    status = model_do_step(inst, communicationStepSize);
    if (status <= fmi2Warning) inst->time = currentCommunicationPoint + communicationStepSize;
    return status;
}

fmi2Status fmi2CancelStep(fmi2Component c) { return unsupported(c, "fmi2CancelStep"); }

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value) {
    (void)s;
    (void)value;
    return unsupported(c, "fmi2GetStatus");
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value) {
    Instance *inst = (Instance *)c;
    if (inst != NULL && s == fmi2LastSuccessfulTime && value != NULL) {
        *value = inst->time;
        return fmi2OK;
    }
    return unsupported(c, "fmi2GetRealStatus for this status kind");
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value) {
    (void)s;
    (void)value;
    return unsupported(c, "fmi2GetIntegerStatus");
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value) {
    if (c != NULL && s == fmi2Terminated && value != NULL) {
        *value = ((Instance *)c)->terminated;
        return fmi2OK;
    }
    return unsupported(c, "fmi2GetBooleanStatus for this status kind");
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value) {
    (void)s;
    (void)value;
    return unsupported(c, "fmi2GetStringStatus");
}

#endif /* TEST_FMI2CS_H */
