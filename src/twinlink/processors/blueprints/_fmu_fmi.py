"""The FMI layer of the FMU blueprint: loading, logging, raw calls and status checks.

FMPy's own wrappers raise `FMICallException` and allocate ctypes arrays on each call; here
the per-step functions are bound once from the shared library with pointer arguments as
plain addresses, and return the FMI status. `fmi_failure` is the one place that turns an
FMI status into a `BlueprintError`; `fmi_errors` does the same for FMPy's exceptions.
"""

from __future__ import annotations

import contextlib
import ctypes
import functools
import logging
import weakref
from collections import deque
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any, ClassVar, cast

import fmpy  # type: ignore[import-untyped]
from fmpy.fmi1 import FMICallException  # type: ignore[import-untyped]
from fmpy.fmi2 import (  # type: ignore[import-untyped]
    FMU2Model,
    FMU2Slave,
    fmi2CallbackAllocateMemoryTYPE,
    fmi2CallbackFreeMemoryTYPE,
    fmi2CallbackFunctions,
    fmi2CallbackLoggerTYPE,
    fmi2EventInfo,
)
from fmpy.fmi3 import FMU3Model, FMU3Slave  # type: ignore[import-untyped]
from fmpy.logging import addLoggerProxy  # type: ignore[import-untyped]

from ..blueprint import BlueprintError
from ..fmuinfo import FLOAT_TYPES, INT_TYPES, FmuInfo, FmuVariable, Scalar
from ..fmurules import INT_RANGES

STATUS = ("ok", "warning", "discard", "error", "fatal", "pending")
WARNING, DISCARD, ERROR, FATAL = 1, 2, 3, 4
TERMINATE = 100  # not an FMI status: the FMU asked to end the simulation
EARLY_RETURN = 101  # not an FMI status: FMI 3 earlyReturn, the step ended before its end
# fmi2StatusKind values (fmi2FunctionTypes.h)
_FMI2_LAST_SUCCESSFUL_TIME, _FMI2_TERMINATED = 2, 3
Raw = Callable[..., int]
_V = ctypes.c_void_p
_SZ = ctypes.c_size_t


class FmuLog:
    """The FMU's last log messages, fed by the FMI logger callback (which must never raise)."""

    def __init__(self, level: str, logger: logging.Logger, keep: int = 50) -> None:
        self.level = level  # off: keep problems only; errors: also log them; all: everything
        self.logger = logger
        self.messages: deque[str] = deque(maxlen=keep)
        self.failed = 0  # the worst failing status seen (ERROR, FATAL...), 0 if none
        self.failure = ""  # the message of the first failure
        # While instantiating, every message is kept whatever the level: an FMU that fails
        # there (a Python FMU missing a module) often says why only at its info level.
        self.instantiating = False

    def add(self, status: int, category: bytes | None, message: bytes | None) -> None:
        try:
            if status < WARNING and self.level != "all" and not self.instantiating:
                return
            label = STATUS[status] if 0 <= status < len(STATUS) else str(status)
            text = (message or b"").decode("utf-8", "replace").strip()
            cat = (category or b"").decode("utf-8", "replace")
            self.messages.append(f"[{label}] {cat + ': ' if cat else ''}{text}")
            if self.level != "off":
                self.logger.log(logging.WARNING if status >= WARNING else logging.DEBUG, text)
        except Exception:  # an exception must not cross into the FMU's C code
            pass

    def fmi3_callback(self, env: Any, status: int, category: bytes, message: bytes) -> None:
        self.add(status, category, message)

    def tail(self, n: int = 5) -> str:
        return " | ".join(list(self.messages)[-n:]) or "(no log message)"


class Terminated(Exception):
    """The FMU ended the simulation at FMU time `time` (FMI 2 fmi2Discard with
    fmi2Terminated, FMI 3 terminateRequested). Not a failure: the step up to `time` is valid,
    and the loops say in `rows` how many output rows they read, the last at `time`."""

    def __init__(self, time: float) -> None:
        super().__init__(f"the FMU asked to terminate at t = {time:g} s")
        self.time = time
        self.rows = 0


def fmi_failure(function: str, status: int, log: FmuLog, when: str = "") -> BlueprintError:
    """The error for an FMI call that returned `status` (discard, error, fatal or TERMINATE)."""
    log.failed = max(log.failed, status)
    if status == TERMINATE:
        message = f"{function}: the FMU asked to terminate{when}: {log.tail()}"
    else:
        label = STATUS[status] if 0 <= status < len(STATUS) else f"status {status}"
        message = f"{function} returned {label}{when}: {log.tail()}"
    log.failure = log.failure or message
    return BlueprintError(message)


@contextmanager
def fmi_errors(log: FmuLog) -> Iterator[None]:
    """Turn the exceptions of FMPy's convenience wrappers into BlueprintError."""
    try:
        yield
    except FMICallException as err:
        raise fmi_failure(str(err.function), int(err.status), log) from err
    except BlueprintError:
        raise
    except Exception as err:  # FMPy raises plain Exception ("Failed to instantiate model")
        raise BlueprintError(f"FMU call failed: {err}: {log.tail()}") from err


# FMI 2 loggers are variadic: FMPy's native proxy formats the message and calls one global
# Python function (the last one registered). One module-level callback, never freed, finds
# the instance's FmuLog through the componentEnvironment key.
_LOGS: weakref.WeakValueDictionary[int, FmuLog] = weakref.WeakValueDictionary()
_fallback = logging.getLogger("twinlink.fmu")


def _fmi2_dispatch(env: int | None, name: bytes, status: int, cat: bytes, msg: bytes) -> None:
    log = _LOGS.get(env or 0)
    if log is not None:
        log.add(status, cat, msg)
    elif status >= WARNING:
        _fallback.warning("%s", (msg or b"").decode("utf-8", "replace"))


_FMI2_LOGGER = fmi2CallbackLoggerTYPE(_fmi2_dispatch)


def _fmi2_callbacks(log: FmuLog) -> Any:
    key = id(log)
    _LOGS[key] = log
    callbacks = fmi2CallbackFunctions()
    callbacks.logger = _FMI2_LOGGER
    callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(fmpy.calloc)
    callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(fmpy.free)
    callbacks.componentEnvironment = key
    addLoggerProxy(ctypes.byref(callbacks))
    return callbacks


def instantiate(
    info: FmuInfo, kind: str, unzipdir: Path, log: FmuLog, instance: str
) -> tuple[Any, FmiApi]:
    """Load the FMU's library and instantiate it; returns the FMPy object and its raw API."""
    interface = info.interface(kind)
    if interface is None or not interface.has_binary:
        raise BlueprintError(f"the FMU has no {kind} binary for this platform")
    fmi3 = info.fmi_version.startswith("3")
    classes = {"CoSimulation": (FMU2Slave, FMU3Slave), "ModelExchange": (FMU2Model, FMU3Model)}
    cls = classes[kind][1 if fmi3 else 0]
    # Logging is on while instantiating, so an FMU that fails there can say why; it is
    # turned off afterwards unless the level is "all".
    on = True
    try:  # FMPy loads every function of the FMI version (and chdirs while loading)
        fmu = cls(
            guid=info.guid,
            modelIdentifier=interface.model_identifier,
            unzipDirectory=str(unzipdir),
            instanceName=instance,
        )
    except Exception as err:  # plain Exception, OSError, AttributeError for a missing function
        raise BlueprintError(f"cannot load the FMU's binary: {err}") from err
    log.instantiating = True
    try:
        with fmi_errors(log):
            if fmi3:
                # early return is handled (CoSimulation goes on from lastSuccessfulTime)
                early = {"earlyReturnAllowed": True} if kind == "CoSimulation" else {}
                fmu.instantiate(loggingOn=on, logMessage=log.fmi3_callback, **early)
            else:
                fmu.instantiate(callbacks=_fmi2_callbacks(log), loggingOn=on)
    except BlueprintError as err:
        fmu.freeLibrary()
        for line in log.messages:  # the FMU's own words, in the processor's logs
            log.logger.warning("FMU: %s", line)
        raise BlueprintError(f"cannot instantiate the FMU: {err}") from err
    finally:
        log.instantiating = False
    if log.level != "all":
        # Quiet again; an FMU that refuses keeps logging, and FmuLog drops what is not kept.
        with contextlib.suppress(Exception):
            fmu.setDebugLogging(loggingOn=False, categories=[])
    api = Fmi3Api(fmu, kind) if fmi3 else Fmi2Api(fmu, kind)
    return fmu, api


def _bind(dll: Any, name: str, *argtypes: Any) -> Raw:
    try:
        function = dll[name]
    except AttributeError as err:
        raise BlueprintError(f"the FMU's binary has no function {name}") from err
    function.argtypes = list(argtypes)
    function.restype = ctypes.c_int
    return cast(Raw, function)


class FmiApi:
    """Raw FMI calls bound to one instance; pointers are passed as addresses (int)."""

    fmi3 = False
    prefix = "fmi2"
    REAL = "Real"
    # the numpy dtype values of each numeric type are read as; Enumeration as the integer type
    DTYPES: ClassVar[dict[str, str]] = {
        "Real": "float64",
        "Integer": "int32",
        "Enumeration": "int32",
        "Boolean": "int32",
    }
    _n_values: ClassVar[tuple[Any, ...]] = ()  # FMI 3 get/set take the number of values too

    def __init__(self, fmu: Any, kind: str) -> None:
        self.c: int = fmu.component
        self.kind = kind
        self._dll = fmu.dll
        self._arrays: list[Any] = []  # value reference arrays the accessors point to

    def function(self, op: str, type_: str) -> str:
        """The FMI function that gets or sets (`op`) values of `type_`."""
        if type_ == "Enumeration":
            type_ = "Int64" if self.fmi3 else "Integer"
        return f"{self.prefix}{op}{type_}"

    def accessor(self, op: str, type_: str, vrs: list[int]) -> Callable[[int], int]:
        """A call that gets or sets the values of `vrs` from / at the address it is given."""
        array = (ctypes.c_uint * len(vrs))(*vrs)
        self._arrays.append(array)
        at, n = ctypes.addressof(array), len(vrs)
        raw = _bind(self._dll, self.function(op, type_), _V, _V, _SZ, _V, *self._n_values)
        if self.fmi3:
            return lambda values: raw(self.c, at, n, values, n)
        return functools.partial(raw, self.c, at, n)

    def do_step(self, t: float, h: float) -> int:
        raise NotImplementedError

    def discarded(self, t: float) -> tuple[bool, float]:
        raise NotImplementedError

    # model exchange; names as FMPy's solvers expect them
    def set_time(self, t: float) -> int:
        return self._set_time(self.c, t)

    def set_x(self, x: Any, n: int) -> int:
        return self._set_x(self.c, x, n)

    def get_x(self, x: Any, n: int) -> int:
        return self._get_x(self.c, x, n)

    def get_dx(self, dx: Any, n: int) -> int:
        return self._get_dx(self.c, dx, n)

    def get_z(self, z: Any, n: int) -> int:
        return self._get_z(self.c, z, n)

    def get_nominals(self, x: Any, n: int) -> int:
        return self._get_nominals(self.c, x, n)

    def enter_event_mode(self) -> int:
        return self._enter_event(self.c)

    def enter_continuous_time_mode(self) -> int:
        return self._enter_ct(self.c)

    def completed_integrator_step(self) -> tuple[int, bool, bool]:
        raise NotImplementedError

    def update_discrete_states(self) -> tuple[int, bool, bool, float | None]:
        """(status, again, terminate, next time event or None)"""
        raise NotImplementedError

    def _bind_me(self, dll: Any, p: str, derivatives: str) -> None:
        self._set_time = _bind(dll, f"{p}SetTime", _V, ctypes.c_double)
        self._set_x = _bind(dll, f"{p}SetContinuousStates", _V, _V, _SZ)
        self._get_x = _bind(dll, f"{p}GetContinuousStates", _V, _V, _SZ)
        self._get_dx = _bind(dll, derivatives, _V, _V, _SZ)
        self._get_z = _bind(dll, f"{p}GetEventIndicators", _V, _V, _SZ)
        self._get_nominals = _bind(dll, f"{p}GetNominalsOfContinuousStates", _V, _V, _SZ)
        self._enter_event = _bind(dll, f"{p}EnterEventMode", _V)
        self._enter_ct = _bind(dll, f"{p}EnterContinuousTimeMode", _V)


class Fmi2Api(FmiApi):
    def __init__(self, fmu: Any, kind: str) -> None:
        super().__init__(fmu, kind)
        dll, i = fmu.dll, ctypes.c_int
        self._flags = (i * 2)()  # completedIntegratorStep's enterEventMode, terminateSimulation
        self._event_info = fmi2EventInfo()
        if kind == "CoSimulation":
            self._do_step = _bind(dll, "fmi2DoStep", _V, ctypes.c_double, ctypes.c_double, i)
            self._bool_status = _bind(dll, "fmi2GetBooleanStatus", _V, i, _V)
            self._real_status = _bind(dll, "fmi2GetRealStatus", _V, i, _V)
            self._status_bool = i()
            self._status_real = ctypes.c_double()
        else:
            self._bind_me(dll, "fmi2", "fmi2GetDerivatives")
            self._completed = _bind(dll, "fmi2CompletedIntegratorStep", _V, i, _V, _V)
            self._new_discrete = _bind(dll, "fmi2NewDiscreteStates", _V, _V)

    def do_step(self, t: float, h: float) -> int:
        return self._do_step(self.c, t, h, 1)

    def discarded(self, t: float) -> tuple[bool, float]:
        """After fmi2Discard: whether the FMU terminated, and its last successful time (`t`,
        the step's start, when it cannot say)."""
        b, r = self._status_bool, self._status_real
        status = self._bool_status(self.c, _FMI2_TERMINATED, ctypes.addressof(b))
        terminated = status <= WARNING and bool(b.value)
        status = self._real_status(self.c, _FMI2_LAST_SUCCESSFUL_TIME, ctypes.addressof(r))
        return terminated, (r.value if status <= WARNING else t)

    def completed_integrator_step(self) -> tuple[int, bool, bool]:
        f = self._flags
        status = self._completed(self.c, 1, ctypes.addressof(f), ctypes.addressof(f) + 4)
        return status, bool(f[0]), bool(f[1])

    def update_discrete_states(self) -> tuple[int, bool, bool, float | None]:
        e = self._event_info
        status = self._new_discrete(self.c, ctypes.addressof(e))
        next_time = e.nextEventTime if e.nextEventTimeDefined else None
        return status, bool(e.newDiscreteStatesNeeded), bool(e.terminateSimulation), next_time


class Fmi3Api(FmiApi):
    fmi3 = True
    prefix = "fmi3"
    REAL = "Float64"
    DTYPES: ClassVar[dict[str, str]] = {
        t: t.lower() for t in ("Float64", "Float32", "Int8", "UInt8", "Int16", "UInt16")
    } | {t: t.lower() for t in ("Int32", "UInt32", "Int64", "UInt64")}
    DTYPES |= {"Enumeration": "int64", "Boolean": "bool"}
    _n_values: ClassVar[tuple[Any, ...]] = (_SZ,)

    def __init__(self, fmu: Any, kind: str) -> None:
        super().__init__(fmu, kind)
        dll, b = fmu.dll, ctypes.c_bool
        self._flags = (b * 5)()
        self._time = ctypes.c_double()
        a, t = ctypes.addressof(self._flags), ctypes.addressof(self._time)
        self._flag_addrs = [a + k for k in range(5)]
        if kind == "CoSimulation":
            d = ctypes.c_double
            self._do_step = _bind(dll, "fmi3DoStep", _V, d, d, b, _V, _V, _V, _V)
            self._step_args = (a, a + 1, a + 2, t)
        else:
            self._bind_me(dll, "fmi3", "fmi3GetContinuousStateDerivatives")
            self._completed = _bind(dll, "fmi3CompletedIntegratorStep", _V, b, _V, _V)
            self._update = _bind(dll, "fmi3UpdateDiscreteStates", _V, _V, _V, _V, _V, _V, _V)

    def do_step(self, t: float, h: float) -> int:
        status = self._do_step(self.c, t, h, True, *self._step_args)
        if status <= WARNING and (self._flags[1] or self._flags[2]):
            return TERMINATE if self._flags[1] else EARLY_RETURN
        return status

    def discarded(self, t: float) -> tuple[bool, float]:
        """After fmi3DoStep: whether the FMU asked to terminate, and lastSuccessfulTime."""
        return bool(self._flags[1]), float(self._time.value)

    def completed_integrator_step(self) -> tuple[int, bool, bool]:
        a = self._flag_addrs
        status = self._completed(self.c, True, a[0], a[1])
        return status, self._flags[0], self._flags[1]

    def update_discrete_states(self) -> tuple[int, bool, bool, float | None]:
        f = self._flags
        status = self._update(self.c, *self._flag_addrs, ctypes.addressof(self._time))
        return status, f[0], f[1], self._time.value if f[4] else None


def value_for(var: FmuVariable, value: Scalar) -> Scalar:
    """`value` converted to the type of `var`; BlueprintError if it does not fit."""
    try:
        converted = _convert(var, value)
    except (TypeError, ValueError, OverflowError) as err:
        raise BlueprintError(f"{var.name} ({var.type}) cannot take {value!r}: {err}") from err
    if isinstance(converted, int | float) and not isinstance(converted, bool):
        low, high = var.min, var.max
        if (low is not None and converted < low) or (high is not None and converted > high):
            span = f"[{'' if low is None else f'{low:g}'}, {'' if high is None else f'{high:g}'}]"
            raise BlueprintError(f"{var.name} = {value!r} is outside its range {span}")
    return converted


def _convert(var: FmuVariable, value: Scalar) -> Scalar:
    if var.type in FLOAT_TYPES:
        return float(value)
    if var.type in INT_TYPES:
        number = float(value)
        if number != int(number):
            raise ValueError("not a whole number")
        low, high = INT_RANGES.get(var.type, (int(number), int(number)))
        if not low <= int(number) <= high:  # the FMU would wrap it around (UInt8 300 -> 44)
            raise ValueError(f"outside the range of {var.type} [{low}, {high}]")
        return int(number)
    if var.type == "Boolean":
        if isinstance(value, str):
            if value.strip().lower() not in {"true", "false", "1", "0"}:
                raise ValueError("not true or false")
            return value.strip().lower() in {"true", "1"}
        return bool(value)
    if var.type == "String":
        return str(value)
    raise ValueError(f"variables of type {var.type} cannot be set")


def set_values(fmu: Any, fmi3: bool, values: list[tuple[FmuVariable, Scalar]], log: FmuLog) -> None:
    """Set variables by name through FMPy's typed setters (not a hot path)."""
    with fmi_errors(log):
        for var, value in values:
            type_ = var.type
            if type_ == "Enumeration":
                type_ = "Int64" if fmi3 else "Integer"
            v = int(value) if type_ == "Boolean" and not fmi3 else value
            getattr(fmu, "set" + type_)([var.value_reference], [v])


def initialize(
    fmu: Any,
    fmi3: bool,
    before: list[tuple[FmuVariable, Scalar]],
    during: list[tuple[FmuVariable, Scalar]],
    tolerance: float | None,
    log: FmuLog,
) -> None:
    """From instantiated through initialization mode, at time 0, setting start values.

    Afterwards a co-simulation FMU is ready to step, a model-exchange FMU is in event mode.
    """
    with fmi_errors(log):
        if not fmi3:
            fmu.setupExperiment(tolerance=tolerance, startTime=0.0)
        set_values(fmu, fmi3, before, log)
        if fmi3:
            fmu.enterInitializationMode(tolerance=tolerance, startTime=0.0)
        else:
            fmu.enterInitializationMode()
        set_values(fmu, fmi3, during, log)
        fmu.exitInitializationMode()
