"""Builds tiny C FMUs for tests: a first-order lag `der(y) = (u - y) / tau`, `g = 2 u`.

Variables (value references shared by the FMI 2.0 and 3.0 flavours):
1 u (input, -10..10), 2 y (output, state, start 0), 3 der(y), 4 g = 2u (output),
5 tau (tunable parameter, start 1), 6 n (Integer/Int32 output: crossings of y = 0.5),
7 label (String output "lag"), 8 z = y - 0.5 (FMI 3 event indicator variable).
Co-simulation steps exactly (`y = u + (y - u) exp(-h / tau)`); doStep fails with a logged
error when u is exactly -7, setting tau above 1e6 (no declared max) too. Functions FMPy
loads but the model does not need are stubs.
"""

from __future__ import annotations

import subprocess
import zipfile
from pathlib import Path

import fmpy  # type: ignore[import-untyped]
from fmpy.fmi2 import FMU2Model, FMU2Slave  # type: ignore[import-untyped]
from fmpy.fmi3 import FMU3Model, FMU3ScheduledExecution, FMU3Slave  # type: ignore[import-untyped]

CORE = r"""
#include <math.h>
#include <stdlib.h>
#include <string.h>
typedef struct M {
    double time, u, y, tau; int n, above, error;
    void (*log)(struct M*, int, const char*);
    void *env, *logger; char *name;
} M;
static M* m_new(const char* name) {
    M* m = (M*)calloc(1, sizeof(M));
    m->tau = 1.0; m->name = strdup(name ? name : "lag");
    return m;
}
static void m_free(M* m) { if (m) { free(m->name); free(m); } }
static void m_cross(M* m) {  /* the solver stops near z = 0: switch with a margin */
    int a = m->y > (m->above ? 0.5 + 1e-6 : 0.5 - 1e-6);
    if (a != m->above) { m->n++; m->above = a; }
}
static int m_get(M* m, unsigned vr, double* v) {
    switch (vr) {
    case 1: *v = m->u; return 1;  case 2: *v = m->y; return 1;
    case 3: *v = (m->u - m->y) / m->tau; return 1;  case 4: *v = 2 * m->u; return 1;
    case 5: *v = m->tau; return 1;  case 8: *v = m->y - 0.5; return 1;
    } return 0;
}
static int m_set(M* m, unsigned vr, double v) {
    switch (vr) {
    case 1: m->u = v; return 1;  case 2: m->y = v; return 1;
    case 5: if (v <= 0 || v > 1e6) { m->log(m, 3, "tau must be in (0, 1e6]"); return 0; }
        m->tau = v; return 1;
    } m->log(m, 3, "variable cannot be set"); return 0;
}
static int m_step(M* m, double h) {
    if (m->u == -7.0) { m->log(m, 3, "u = -7 is not allowed"); return 0; }
    m->y = m->u + (m->y - m->u) * exp(-h / m->tau); m->time += h; m_cross(m); return 1;
}
#define LOOP(n) for (size_t i = 0; i < (n); i++)
"""

FMI2_C = r"""
#include "fmi2Functions.h"
#define M_ ((M*)c)
static void m_log2(M* m, int s, const char* msg) {
    fmi2CallbackLogger f = (fmi2CallbackLogger)m->logger;
    if (f) f(m->env, m->name, (fmi2Status)s, "logStatusError", "%s", msg);
}
const char* fmi2GetTypesPlatform(void) { return "default"; }
const char* fmi2GetVersion(void) { return "2.0"; }
fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n,
                               const fmi2String cat[]) { return fmi2OK; }
fmi2Component fmi2Instantiate(fmi2String name, fmi2Type t, fmi2String guid, fmi2String res,
        const fmi2CallbackFunctions* f, fmi2Boolean visible, fmi2Boolean loggingOn) {
    if (strcmp(guid, "{GUID}") != 0) return NULL;
    M* m = m_new(name); m->log = m_log2; m->logger = (void*)f->logger;
    m->env = f->componentEnvironment; return m;
}
void fmi2FreeInstance(fmi2Component c) { m_free(M_); }
fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean td, fmi2Real tol, fmi2Real t0,
                               fmi2Boolean sd, fmi2Real t1) { M_->time = t0; return fmi2OK; }
fmi2Status fmi2EnterInitializationMode(fmi2Component c) { return fmi2OK; }
fmi2Status fmi2ExitInitializationMode(fmi2Component c) { M_->above = M_->y > 0.5; return fmi2OK; }
fmi2Status fmi2Terminate(fmi2Component c) { return fmi2OK; }
fmi2Status fmi2Reset(fmi2Component c) { return fmi2OK; }
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    LOOP(n) if (!m_get(M_, vr[i], &v[i])) return fmi2Error; return fmi2OK;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                       const fmi2Real v[]) {
    LOOP(n) if (!m_set(M_, vr[i], v[i])) return fmi2Error; return fmi2OK;
}
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                          fmi2Integer v[]) {
    LOOP(n) { if (vr[i] != 6) return fmi2Error; v[i] = M_->n; } return fmi2OK;
}
fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                         fmi2String v[]) {
    LOOP(n) { if (vr[i] != 7) return fmi2Error; v[i] = "lag"; } return fmi2OK;
}
fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSet) {
    return m_step(M_, h) ? fmi2OK : fmi2Error;
}
fmi2Status fmi2SetTime(fmi2Component c, fmi2Real t) { M_->time = t; return fmi2OK; }
fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t n) {
    M_->y = x[0]; return fmi2OK;
}
fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t n) {
    x[0] = M_->y; return fmi2OK;
}
fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real dx[], size_t n) {
    m_get(M_, 3, &dx[0]); return fmi2OK;
}
fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real z[], size_t n) {
    z[0] = M_->y - 0.5; return fmi2OK;
}
fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x[], size_t n) {
    x[0] = 1.0; return fmi2OK;
}
fmi2Status fmi2EnterEventMode(fmi2Component c) { return fmi2OK; }
fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo* e) {
    m_cross(M_); memset(e, 0, sizeof(*e)); return fmi2OK;
}
fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c) { return fmi2OK; }
fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSet, fmi2Boolean* ev,
                                       fmi2Boolean* term) { *ev = 0; *term = 0; return fmi2OK; }
"""

FMI3_C = r"""
#include "fmi3Functions.h"
#define M_ ((M*)c)
static void m_log3(M* m, int s, const char* msg) {
    fmi3LogMessageCallback f = (fmi3LogMessageCallback)m->logger;
    if (f) f(m->env, (fmi3Status)s, "logStatusError", msg);
}
static M* m_new3(fmi3String name, fmi3String token, fmi3InstanceEnvironment env,
                 fmi3LogMessageCallback log) {
    if (strcmp(token, "{GUID}") != 0) return NULL;
    M* m = m_new(name); m->log = m_log3; m->logger = (void*)log; m->env = env; return m;
}
const char* fmi3GetVersion(void) { return "3.0"; }
fmi3Status fmi3SetDebugLogging(fmi3Instance c, fmi3Boolean on, size_t n,
                               const fmi3String cat[]) { return fmi3OK; }
fmi3Instance fmi3InstantiateModelExchange(fmi3String name, fmi3String token, fmi3String res,
        fmi3Boolean vis, fmi3Boolean lo, fmi3InstanceEnvironment env, fmi3LogMessageCallback f) {
    return m_new3(name, token, env, f);
}
fmi3Instance fmi3InstantiateCoSimulation(fmi3String name, fmi3String token, fmi3String res,
        fmi3Boolean vis, fmi3Boolean lo, fmi3Boolean em, fmi3Boolean er,
        const fmi3ValueReference rv[], size_t nrv, fmi3InstanceEnvironment env,
        fmi3LogMessageCallback f, fmi3IntermediateUpdateCallback iu) {
    return m_new3(name, token, env, f);
}
void fmi3FreeInstance(fmi3Instance c) { m_free(M_); }
fmi3Status fmi3EnterInitializationMode(fmi3Instance c, fmi3Boolean td, fmi3Float64 tol,
        fmi3Float64 t0, fmi3Boolean sd, fmi3Float64 t1) { M_->time = t0; return fmi3OK; }
fmi3Status fmi3ExitInitializationMode(fmi3Instance c) { M_->above = M_->y > 0.5; return fmi3OK; }
fmi3Status fmi3EnterEventMode(fmi3Instance c) { return fmi3OK; }
fmi3Status fmi3EnterStepMode(fmi3Instance c) { return fmi3OK; }
fmi3Status fmi3Terminate(fmi3Instance c) { return fmi3OK; }
fmi3Status fmi3Reset(fmi3Instance c) { return fmi3OK; }
fmi3Status fmi3GetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t n,
                          fmi3Float64 v[], size_t nv) {
    LOOP(n) if (!m_get(M_, vr[i], &v[i])) return fmi3Error; return fmi3OK;
}
fmi3Status fmi3SetFloat64(fmi3Instance c, const fmi3ValueReference vr[], size_t n,
                          const fmi3Float64 v[], size_t nv) {
    LOOP(n) if (!m_set(M_, vr[i], v[i])) return fmi3Error; return fmi3OK;
}
fmi3Status fmi3GetInt32(fmi3Instance c, const fmi3ValueReference vr[], size_t n,
                        fmi3Int32 v[], size_t nv) {
    LOOP(n) { if (vr[i] != 6) return fmi3Error; v[i] = M_->n; } return fmi3OK;
}
fmi3Status fmi3GetString(fmi3Instance c, const fmi3ValueReference vr[], size_t n,
                         fmi3String v[], size_t nv) {
    LOOP(n) { if (vr[i] != 7) return fmi3Error; v[i] = "lag"; } return fmi3OK;
}
fmi3Status fmi3DoStep(fmi3Instance c, fmi3Float64 t, fmi3Float64 h, fmi3Boolean noSet,
        fmi3Boolean* ev, fmi3Boolean* term, fmi3Boolean* early, fmi3Float64* last) {
    *ev = 0; *term = 0; *early = 0; *last = t + h;
    return m_step(M_, h) ? fmi3OK : fmi3Error;
}
fmi3Status fmi3SetTime(fmi3Instance c, fmi3Float64 t) { M_->time = t; return fmi3OK; }
fmi3Status fmi3SetContinuousStates(fmi3Instance c, const fmi3Float64 x[], size_t n) {
    M_->y = x[0]; return fmi3OK;
}
fmi3Status fmi3GetContinuousStates(fmi3Instance c, fmi3Float64 x[], size_t n) {
    x[0] = M_->y; return fmi3OK;
}
fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance c, fmi3Float64 dx[], size_t n) {
    m_get(M_, 3, &dx[0]); return fmi3OK;
}
fmi3Status fmi3GetEventIndicators(fmi3Instance c, fmi3Float64 z[], size_t n) {
    z[0] = M_->y - 0.5; return fmi3OK;
}
fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance c, fmi3Float64 x[], size_t n) {
    x[0] = 1.0; return fmi3OK;
}
fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance c, size_t* n) { *n = 1; return fmi3OK; }
fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance c, size_t* n) { *n = 1; return fmi3OK; }
fmi3Status fmi3UpdateDiscreteStates(fmi3Instance c, fmi3Boolean* upd, fmi3Boolean* term,
        fmi3Boolean* nom, fmi3Boolean* val, fmi3Boolean* ted, fmi3Float64* te) {
    m_cross(M_); *upd = *term = *nom = *val = *ted = 0; *te = 0; return fmi3OK;
}
fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance c) { return fmi3OK; }
fmi3Status fmi3CompletedIntegratorStep(fmi3Instance c, fmi3Boolean noSet, fmi3Boolean* ev,
        fmi3Boolean* term) { *ev = 0; *term = 0; return fmi3OK; }
"""

UNITS = """<UnitDefinitions>
  <Unit name="m"><BaseUnit m="1"/></Unit><Unit name="s"><BaseUnit s="1"/></Unit>
  <Unit name="m/s"><BaseUnit m="1" s="-1"/></Unit></UnitDefinitions>
"""

FMI2_XML = f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="lag" guid="{{GUID}}"
  description="first-order lag" generationTool="twinlink tests" numberOfEventIndicators="1">
<ModelExchange modelIdentifier="lag"/>
<CoSimulation modelIdentifier="lag" canHandleVariableCommunicationStepSize="true"/>
{UNITS}<DefaultExperiment startTime="0" stopTime="10" stepSize="0.01"/>
<ModelVariables>
  <ScalarVariable name="u" valueReference="1" causality="input" variability="continuous"
    description="input"><Real start="0" min="-10" max="10" unit="m"/></ScalarVariable>
  <ScalarVariable name="y" valueReference="2" causality="output" variability="continuous"
    initial="exact"><Real start="0" unit="m"/></ScalarVariable>
  <ScalarVariable name="der(y)" valueReference="3" causality="local"
    variability="continuous"><Real derivative="2" unit="m/s"/></ScalarVariable>
  <ScalarVariable name="g" valueReference="4" causality="output"><Real unit="m"/></ScalarVariable>
  <ScalarVariable name="tau" valueReference="5" causality="parameter" variability="tunable">
    <Real start="1" min="1e-6" unit="s"/></ScalarVariable>
  <ScalarVariable name="n" valueReference="6" causality="output" variability="discrete">
    <Integer/></ScalarVariable>
  <ScalarVariable name="label" valueReference="7" causality="output" variability="constant">
    <String start="lag"/></ScalarVariable>
</ModelVariables>
<ModelStructure>
  <Outputs><Unknown index="2"/><Unknown index="4" dependencies="1"/><Unknown index="6"/>
    <Unknown index="7"/></Outputs>
  <Derivatives><Unknown index="3"/></Derivatives>
  <InitialUnknowns><Unknown index="3"/><Unknown index="4"/><Unknown index="6"/></InitialUnknowns>
</ModelStructure>
</fmiModelDescription>
"""

FMI3_XML = f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="3.0" modelName="lag3" instantiationToken="{{GUID}}"
  description="first-order lag" generationTool="twinlink tests">
<ModelExchange modelIdentifier="lag3"/>
<CoSimulation modelIdentifier="lag3" canHandleVariableCommunicationStepSize="true"/>
{UNITS}<DefaultExperiment startTime="0" stopTime="10" stepSize="0.01"/>
<ModelVariables>
  <Float64 name="time" valueReference="0" causality="independent" variability="continuous"/>
  <Float64 name="u" valueReference="1" causality="input" start="0" min="-10" max="10"
    unit="m" description="input"/>
  <Float64 name="y" valueReference="2" causality="output" initial="exact" start="0" unit="m"/>
  <Float64 name="der(y)" valueReference="3" causality="local" derivative="2" unit="m/s"/>
  <Float64 name="g" valueReference="4" causality="output" unit="m"/>
  <Float64 name="tau" valueReference="5" causality="parameter" variability="tunable"
    start="1" min="1e-6" unit="s"/>
  <Int32 name="n" valueReference="6" causality="output" variability="discrete"/>
  <String name="label" valueReference="7" causality="output" variability="constant">
    <Start value="lag"/></String>
  <Float64 name="z" valueReference="8" causality="local"/>
</ModelVariables>
<ModelStructure>
  <Output valueReference="2"/><Output valueReference="4" dependencies="1"/>
  <Output valueReference="6"/><Output valueReference="7"/>
  <ContinuousStateDerivative valueReference="3"/>
  <InitialUnknown valueReference="3"/><InitialUnknown valueReference="4"/>
  <InitialUnknown valueReference="6"/>
  <EventIndicator valueReference="8"/>
</ModelStructure>
</fmiModelDescription>
"""


def _stubs(classes: tuple[type, ...], prefix: str, source: str) -> str:
    """`int f() { return 3; }` (error) for each FMI function FMPy loads that `source` lacks."""
    names = {n for cls in classes for n in dir(cls) if n.startswith(prefix)}
    return "".join(f"int {n}() {{ return 3; }}\n" for n in sorted(names) if f" {n}(" not in source)


def build_fmu(folder: Path, version: int = 2, name: str = "lag.fmu") -> Path:
    """Compile the lag model as an FMI `version` (2 or 3) FMU in `folder` and return its path."""
    work = folder / f"build{version}"
    work.mkdir(parents=True, exist_ok=True)
    if version == 2:
        source, xml, ident, plat = CORE + FMI2_C, FMI2_XML, "lag", "linux64"
        stubs = _stubs((FMU2Slave, FMU2Model), "fmi2", source)
    else:
        source, xml, ident, plat = CORE + FMI3_C, FMI3_XML, "lag3", "x86_64-linux"
        stubs = _stubs((FMU3Slave, FMU3Model, FMU3ScheduledExecution), "fmi3", source)
    (work / "model.c").write_text(source)
    (work / "stubs.c").write_text(stubs)  # no header: K&R declarations of unused functions
    lib = work / f"{ident}.so"
    headers = Path(fmpy.__file__).parent / "c-code"
    sources = [str(work / "model.c"), str(work / "stubs.c")]
    subprocess.run(
        ["gcc", "-shared", "-fPIC", "-O2", f"-I{headers}", "-o", str(lib), *sources, "-lm"],
        check=True,
        capture_output=True,
    )
    path = folder / name
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
        zf.writestr("modelDescription.xml", xml)
        zf.write(lib, f"binaries/{plat}/{ident}.so")
    return path
