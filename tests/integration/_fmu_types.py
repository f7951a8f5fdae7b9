"""Builds a C FMU whose outputs echo its inputs of every scalar type (FMI 2.0 and 3.0), so a
test sees the values that came through the FMI setters: input value reference v is echoed
by output value reference 100 + v, of the same type. Functions FMPy loads but the model does
not need are stubs (as in _fmu_c.py)."""

from __future__ import annotations

import subprocess
import zipfile
from pathlib import Path

import fmpy  # type: ignore[import-untyped]
from fmpy.fmi2 import FMU2Model, FMU2Slave  # type: ignore[import-untyped]
from fmpy.fmi3 import FMU3Model, FMU3ScheduledExecution, FMU3Slave  # type: ignore[import-untyped]

from tests.integration._fmu_c import _stubs

# (name, FMI 3 type, value reference, extra attributes) of the FMI 3 inputs
FMI3_INPUTS = [
    ("f32", "Float32", 1, ""),
    ("i8", "Int8", 2, ""),
    ("u8", "UInt8", 3, ""),
    ("i16", "Int16", 4, ""),
    ("u16", "UInt16", 5, ""),
    ("i32", "Int32", 6, ' min="-5" max="5"'),
    ("u32", "UInt32", 7, ""),
    ("i64", "Int64", 8, ""),
    ("u64", "UInt64", 9, ""),
    ("b", "Boolean", 10, ""),
    ("e", "Enumeration", 11, ' declaredType="Level"'),
]
FMI2_INPUTS = [  # (name, FMI 2 type, value reference, extra attributes)
    ("x", "Real", 1, ""),
    ("n", "Integer", 2, ' min="-5" max="5"'),
    ("b", "Boolean", 3, ""),
    ("e", "Enumeration", 4, ' declaredType="Level"'),
]

COMMON = r"""
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
typedef struct { double d[16]; int64_t q[16]; } M;
#define M_ ((M*)c)
#define LOOP(n) for (size_t i = 0; i < (n); i++)
#define IN(vr) ((vr) >= 1 && (vr) < 16)
#define OUT(vr) ((vr) >= 101 && (vr) < 116)
"""

FMI2_C = r"""
#include "fmi2Functions.h"
const char* fmi2GetTypesPlatform(void) { return "default"; }
const char* fmi2GetVersion(void) { return "2.0"; }
fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean on, size_t n,
                               const fmi2String cat[]) { return fmi2OK; }
fmi2Component fmi2Instantiate(fmi2String name, fmi2Type t, fmi2String guid, fmi2String res,
        const fmi2CallbackFunctions* f, fmi2Boolean visible, fmi2Boolean loggingOn) {
    return strcmp(guid, "{ECHO}") == 0 ? calloc(1, sizeof(M)) : NULL;
}
void fmi2FreeInstance(fmi2Component c) { free(c); }
fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean td, fmi2Real tol, fmi2Real t0,
                               fmi2Boolean sd, fmi2Real t1) { return fmi2OK; }
fmi2Status fmi2EnterInitializationMode(fmi2Component c) { return fmi2OK; }
fmi2Status fmi2ExitInitializationMode(fmi2Component c) { return fmi2OK; }
fmi2Status fmi2Terminate(fmi2Component c) { return fmi2OK; }
fmi2Status fmi2Reset(fmi2Component c) { return fmi2OK; }
fmi2Status fmi2DoStep(fmi2Component c, fmi2Real t, fmi2Real h, fmi2Boolean noSet) {
    return fmi2OK;
}
fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n, fmi2Real v[]) {
    LOOP(n) { if (!OUT(vr[i])) return fmi2Error; v[i] = M_->d[vr[i] - 100]; } return fmi2OK;
}
fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                       const fmi2Real v[]) {
    LOOP(n) { if (!IN(vr[i])) return fmi2Error; M_->d[vr[i]] = v[i]; } return fmi2OK;
}
fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                          fmi2Integer v[]) {
    LOOP(n) { if (!OUT(vr[i])) return fmi2Error; v[i] = (fmi2Integer)M_->q[vr[i] - 100]; }
    return fmi2OK;
}
fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                          const fmi2Integer v[]) {
    LOOP(n) { if (!IN(vr[i])) return fmi2Error; M_->q[vr[i]] = v[i]; } return fmi2OK;
}
fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                          fmi2Boolean v[]) {
    LOOP(n) { if (!OUT(vr[i])) return fmi2Error; v[i] = (fmi2Boolean)M_->q[vr[i] - 100]; }
    return fmi2OK;
}
fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t n,
                          const fmi2Boolean v[]) {
    LOOP(n) { if (!IN(vr[i])) return fmi2Error; M_->q[vr[i]] = v[i]; } return fmi2OK;
}
"""

FMI3_ACCESSORS = "".join(
    f"""
fmi3Status fmi3Get{t}(fmi3Instance c, const fmi3ValueReference vr[], size_t n, fmi3{t} v[],
                      size_t nv) {{
    LOOP(n) {{ if (!OUT(vr[i])) return fmi3Error; v[i] = (fmi3{t})M_->{f}[vr[i] - 100]; }}
    return fmi3OK;
}}
fmi3Status fmi3Set{t}(fmi3Instance c, const fmi3ValueReference vr[], size_t n,
                      const fmi3{t} v[], size_t nv) {{
    LOOP(n) {{ if (!IN(vr[i])) return fmi3Error; M_->{f}[vr[i]] = {cast}v[i]; }}
    return fmi3OK;
}}
"""
    for t, f, cast in [
        ("Float64", "d", ""),
        ("Float32", "d", ""),
        ("Int8", "q", ""),
        ("UInt8", "q", ""),
        ("Int16", "q", ""),
        ("UInt16", "q", ""),
        ("Int32", "q", ""),
        ("UInt32", "q", ""),
        ("Int64", "q", ""),
        ("UInt64", "q", "(int64_t)"),
        ("Boolean", "q", ""),
    ]
)

FMI3_C = (
    r"""
#include "fmi3Functions.h"
const char* fmi3GetVersion(void) { return "3.0"; }
fmi3Status fmi3SetDebugLogging(fmi3Instance c, fmi3Boolean on, size_t n,
                               const fmi3String cat[]) { return fmi3OK; }
fmi3Instance fmi3InstantiateCoSimulation(fmi3String name, fmi3String token, fmi3String res,
        fmi3Boolean vis, fmi3Boolean lo, fmi3Boolean em, fmi3Boolean er,
        const fmi3ValueReference rv[], size_t nrv, fmi3InstanceEnvironment env,
        fmi3LogMessageCallback f, fmi3IntermediateUpdateCallback iu) {
    return strcmp(token, "{ECHO}") == 0 ? calloc(1, sizeof(M)) : NULL;
}
void fmi3FreeInstance(fmi3Instance c) { free(c); }
fmi3Status fmi3EnterInitializationMode(fmi3Instance c, fmi3Boolean td, fmi3Float64 tol,
        fmi3Float64 t0, fmi3Boolean sd, fmi3Float64 t1) { return fmi3OK; }
fmi3Status fmi3ExitInitializationMode(fmi3Instance c) { return fmi3OK; }
fmi3Status fmi3EnterStepMode(fmi3Instance c) { return fmi3OK; }
fmi3Status fmi3Terminate(fmi3Instance c) { return fmi3OK; }
fmi3Status fmi3Reset(fmi3Instance c) { return fmi3OK; }
fmi3Status fmi3DoStep(fmi3Instance c, fmi3Float64 t, fmi3Float64 h, fmi3Boolean noSet,
        fmi3Boolean* ev, fmi3Boolean* term, fmi3Boolean* early, fmi3Float64* last) {
    *ev = 0; *term = 0; *early = 0; *last = t + h; return fmi3OK;
}
"""
    + FMI3_ACCESSORS
    + r"""
"""
)


def _fmi2_xml() -> str:
    inputs = "".join(
        f'<ScalarVariable name="{n}" valueReference="{vr}" causality="input" '
        f'variability="{"continuous" if t == "Real" else "discrete"}">'
        f'<{t} start="{1 if t == "Enumeration" else 0}"{extra}/></ScalarVariable>\n'
        for n, t, vr, extra in FMI2_INPUTS
    )
    outputs = "".join(
        f'<ScalarVariable name="{n}_out" valueReference="{100 + vr}" causality="output" '
        f'variability="{"continuous" if t == "Real" else "discrete"}">'
        f"<{t}{extra if t == 'Enumeration' else ''}/></ScalarVariable>\n"
        for n, t, vr, extra in FMI2_INPUTS
    )
    first = len(FMI2_INPUTS) + 1
    unknowns = "".join(f'<Unknown index="{first + i}"/>' for i in range(len(FMI2_INPUTS)))
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="2.0" modelName="echo" guid="{{ECHO}}"
  generationTool="twinlink tests" numberOfEventIndicators="0">
<CoSimulation modelIdentifier="echo" canHandleVariableCommunicationStepSize="true"/>
<TypeDefinitions><SimpleType name="Level"><Enumeration>
  <Item name="low" value="1"/><Item name="mid" value="2"/><Item name="high" value="3"/>
</Enumeration></SimpleType></TypeDefinitions>
<ModelVariables>
{inputs}{outputs}</ModelVariables>
<ModelStructure><Outputs>{unknowns}</Outputs><InitialUnknowns>{unknowns}</InitialUnknowns>
</ModelStructure>
</fmiModelDescription>
"""


def _fmi3_xml() -> str:
    def start(t: str) -> str:
        return {"Enumeration": ' start="1"', "Boolean": ' start="false"'}.get(t, ' start="0"')

    def discrete(t: str) -> str:
        return "" if t == "Float32" else ' variability="discrete"'

    inputs = "".join(
        f'<{t} name="{n}" valueReference="{vr}" causality="input"{discrete(t)}{start(t)}{extra}/>\n'
        for n, t, vr, extra in FMI3_INPUTS
    )
    outputs = "".join(
        f'<{t} name="{n}_out" valueReference="{100 + vr}" causality="output"'
        f"{discrete(t)}"
        f"{extra if t == 'Enumeration' else ''}/>\n"
        for n, t, vr, extra in FMI3_INPUTS
    )
    structure = "".join(
        f'<{kind} valueReference="{100 + vr}"/>'
        for kind in ("Output", "InitialUnknown")
        for _, _, vr, _ in FMI3_INPUTS
    )
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<fmiModelDescription fmiVersion="3.0" modelName="echo3" instantiationToken="{{ECHO}}"
  generationTool="twinlink tests">
<CoSimulation modelIdentifier="echo3" canHandleVariableCommunicationStepSize="true"/>
<TypeDefinitions><EnumerationType name="Level">
  <Item name="low" value="1"/><Item name="mid" value="2"/><Item name="high" value="3"/>
</EnumerationType></TypeDefinitions>
<ModelVariables>
<Float64 name="time" valueReference="0" causality="independent" variability="continuous"/>
{inputs}{outputs}</ModelVariables>
<ModelStructure>{structure}</ModelStructure>
</fmiModelDescription>
"""


def build_echo_fmu(folder: Path, version: int = 2) -> Path:
    """Compile the echo model as an FMI `version` (2 or 3) FMU in `folder`; its path."""
    work = folder / f"echo{version}"
    work.mkdir(parents=True, exist_ok=True)
    if version == 2:
        source, xml, ident, plat = COMMON + FMI2_C, _fmi2_xml(), "echo", "linux64"
        stubs = _stubs((FMU2Slave, FMU2Model), "fmi2", source)
    else:
        source, xml, ident, plat = COMMON + FMI3_C, _fmi3_xml(), "echo3", "x86_64-linux"
        stubs = _stubs((FMU3Slave, FMU3Model, FMU3ScheduledExecution), "fmi3", source)
    (work / "model.c").write_text(source)
    (work / "stubs.c").write_text(stubs)
    lib = work / f"{ident}.so"
    headers = Path(fmpy.__file__).parent / "c-code"
    sources = [str(work / "model.c"), str(work / "stubs.c")]
    subprocess.run(
        ["gcc", "-shared", "-fPIC", "-O2", f"-I{headers}", "-o", str(lib), *sources],
        check=True,
        capture_output=True,
    )
    path = folder / f"{ident}.fmu"
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as zf:
        zf.writestr("modelDescription.xml", xml)
        zf.write(lib, f"binaries/{plat}/{ident}.so")
    return path
