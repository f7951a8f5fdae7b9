"""Maestro's var-step constraints, read from a file (`parse`) and applied by the var-step
master (varstep.py) on top of its own error estimate.

Each constraint bounds the next step before it is taken (`bound`: the latest time it may
reach) and may ask for a step to be redone shorter once taken (`retry`), as Maestro's
legacy COE does:

- zerocrossing: a port's value (or the difference of two ports) crossing zero is hit within
  `abstol`: the step is shortened to the crossing the last points predict (a line, or a
  parabola with `order` 2), and a step that crosses it with both ends further than `abstol`
  from zero is redone up to the crossing interpolated between them;
- boundeddifference: no port changes over a step by more than `abstol` or `reltol` times its
  magnitude (whichever is larger); the next step is sized from the last change, and a step
  over the bound is redone shorter (Maestro's spread between several ports is not used:
  each port is bounded on its own);
- samplingrate: every sampling point (startTime + k rate) 10^base s is a communication point;
- fmumaxstepsize: no step longer than an FMU's fmi2GetMaxStepsize (INTO-CPS's FMI 2
  extension), asked of the FMI 2 instances in this process that export it.

`safety` keeps a predicted step that fraction short of its limit (boundeddifference: 0.1,
zerocrossing: 0 by default). No bound is below the algorithm's min_size but a sampling
point's (a step must land on it), so no answer of an FMU or a prediction stalls the run.
Redoing a step needs every instance's state, as for the error estimate; without it a
constraint only bounds the next step.
"""

from __future__ import annotations

import ctypes
import math
from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from .model import Algorithm, Constraint, ConstraintKind, Port

if TYPE_CHECKING:  # the readers import this module: no FMI layer for them
    from .protocol import SlaveLike

KINDS: tuple[ConstraintKind, ...] = (
    "zerocrossing",
    "boundeddifference",
    "samplingrate",
    "fmumaxstepsize",
)
ZC_ABSTOL, BD_ABSTOL, BD_RELTOL, BD_SAFETY = 1e-3, 1e-3, 1e-2, 0.1

PortOf = Callable[[Any, str], Port]  # (the text in the file, where) -> Port
Fail = Callable[[str, str], Exception]  # (where, problem) -> the reader's format error


def parse(raw: Any, where: str, port: PortOf, fail: Fail) -> tuple[Constraint, ...]:
    """`constraints` of a var-step algorithm as Maestro writes it: an object of name ->
    {"type": ..., ...}."""
    if raw is None:
        return ()
    if not isinstance(raw, dict):
        raise fail(where, 'is not an object of name -> {"type": ...}')
    return tuple(
        _parse_one(str(name), body, f"{where}.{name}", port, fail) for name, body in raw.items()
    )


class _Fields:
    """A constraint's numbers read with errors naming their key."""

    def __init__(self, raw: dict[str, Any], where: str, fail: Fail) -> None:
        self.raw, self.where, self.fail = raw, where, fail

    def number(self, key: str, *, positive: bool = False, signed: bool = False) -> float | None:
        value, where = self.raw.get(key), f"{self.where}.{key}"
        if isinstance(value, str):  # the INTO-CPS app writes some numbers as strings
            try:
                value = float(value)
            except ValueError:
                raise self.fail(where, f"{value!r} is not a number") from None
        if value is None:
            return None
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.fail(where, f"{value!r} is not a number")
        if not math.isfinite(value) or (value < 0 and not signed) or (positive and value == 0):
            above = "above 0" if positive else "0 or more"
            raise self.fail(where, f"{value!r} is not a finite number {above}")
        return float(value)

    def integer(self, key: str, default: int) -> int:
        value = self.number(key, signed=key == "base")
        if value is None:
            return default
        if value != int(value):
            raise self.fail(f"{self.where}.{key}", f"{value!r} is not a whole number")
        return int(value)


def _parse_one(name: str, raw: Any, where: str, port: PortOf, fail: Fail) -> Constraint:
    if not isinstance(raw, dict):
        raise fail(where, "is not an object")
    kind = raw.get("type")
    if kind not in KINDS:
        raise fail(f"{where}.type", f"{kind!r} is not one of {', '.join(KINDS)}")
    fields = _Fields(raw, where, fail)
    number, integer = fields.number, fields.integer

    ports: tuple[Port, ...] = ()
    if kind in ("zerocrossing", "boundeddifference"):
        listed = raw.get("ports")
        if not isinstance(listed, list) or not listed:
            raise fail(f"{where}.ports", "is not a list of ports")
        ports = tuple(port(p, f"{where}.ports") for p in listed)
        if kind == "zerocrossing" and len(ports) > 2:
            raise fail(f"{where}.ports", "takes one port, or two whose difference is watched")
    safety = number("safety")
    if safety is not None and safety >= 1:
        raise fail(f"{where}.safety", f"{safety} is not a fraction below 1")
    order = integer("order", 1)
    if order not in (1, 2):
        raise fail(f"{where}.order", f"{order} is neither 1 nor 2")
    rate = integer("rate", 1)
    if kind == "samplingrate" and rate <= 0:
        raise fail(f"{where}.rate", f"{rate} is not above 0")
    skip = raw.get("skipDiscrete", True)
    if not isinstance(skip, bool):
        raise fail(f"{where}.skipDiscrete", "is not true or false")
    return Constraint(
        name=name,
        kind=kind,
        ports=ports,
        order=order,
        abstol=number("abstol"),
        reltol=number("reltol"),
        safety=safety,
        skip_discrete=skip,
        base=integer("base", 0),
        rate=rate,
        start_time=integer("startTime", 0),
    )


def to_mapping(constraint: Constraint) -> dict[str, Any]:
    """`constraint` as Maestro writes it (the YAML form writes it so too)."""
    out: dict[str, Any] = {"type": constraint.kind}
    if constraint.ports:
        out["ports"] = [str(p) for p in constraint.ports]
    if constraint.kind == "zerocrossing":
        out["order"] = constraint.order
    if constraint.kind == "samplingrate":
        out |= {"base": constraint.base, "rate": constraint.rate}
        out["startTime"] = constraint.start_time
    for key in ("abstol", "reltol", "safety"):
        if getattr(constraint, key) is not None:
            out[key] = getattr(constraint, key)
    if constraint.kind == "boundeddifference" and not constraint.skip_discrete:
        out["skipDiscrete"] = False
    return out


# --- applying them --------------------------------------------------------------------

_Reader = Callable[[], float]


class _Check:
    def start(self, t: float) -> None:
        """After initialization, at the start time."""

    def bound(self, t: float, target: float) -> float:
        """The latest time the step from t may reach (<= target)."""
        return target

    def retry(self, t: float, h: float) -> float | None:
        """After a step of h from t: a shorter step to redo it with, None if it holds."""
        return None

    def accept(self, t: float, h: float) -> None:
        """The step of h to t was kept."""


class _ZeroCrossing(_Check):
    def __init__(self, c: Constraint, value: _Reader, floor: float) -> None:
        self.value = value
        self.floor = floor  # min_size: no shorter step for a prediction
        self.order = c.order
        self.abstol = ZC_ABSTOL if c.abstol is None else c.abstol
        self.safety = c.safety or 0.0
        self.points: list[tuple[float, float]] = []  # (t, f) at the last accepted points

    def start(self, t: float) -> None:
        self.points = [(t, self.value())]

    def bound(self, t: float, target: float) -> float:
        f1 = self.points[-1][1]
        if abs(f1) <= self.abstol or len(self.points) < 2:
            return target  # at a crossing now (let it pass), or nothing to predict from
        crossing = self._predicted()
        if crossing is None or not t < crossing < target:
            return target
        return min(target, t + max(self.floor, (crossing - t) * (1.0 - self.safety)))

    def _predicted(self) -> float | None:
        """The next time the last points' line (parabola) reaches zero, None if it does not."""
        (t0, f0), (t1, f1) = self.points[-2], self.points[-1]
        if self.order == 2 and len(self.points) >= 3:
            ts = np.array([p[0] for p in self.points[-3:]]) - t1
            fs = np.array([p[1] for p in self.points[-3:]])
            roots = np.roots(np.polyfit(ts, fs, 2))
            ahead = [float(r.real) for r in roots if abs(r.imag) < 1e-12 and r.real > 0]
            return t1 + min(ahead) if ahead else None
        slope = (f1 - f0) / (t1 - t0)
        if slope == 0.0 or slope * f1 > 0:
            return None  # moving away from zero
        return t1 - f1 / slope

    def retry(self, t: float, h: float) -> float | None:
        f0, f1 = self.points[-1][1], self.value()
        if f0 * f1 >= 0 or min(abs(f0), abs(f1)) <= self.abstol:
            return None  # no crossing in the step, or one hit within tolerance
        # the crossing interpolated between the step's ends (regula falsi)
        return h * min(0.99, max(0.01, f0 / (f0 - f1)))

    def accept(self, t: float, h: float) -> None:
        self.points = [*self.points[-2:], (t, self.value())]


class _BoundedDifference(_Check):
    def __init__(self, c: Constraint, values: Sequence[_Reader], floor: float) -> None:
        self.values = values
        self.floor = floor  # min_size: no shorter step for the last change
        self.abstol = BD_ABSTOL if c.abstol is None else c.abstol
        self.reltol = BD_RELTOL if c.reltol is None else c.reltol
        self.safety = BD_SAFETY if c.safety is None else c.safety
        self.last = np.zeros(len(values))
        self.next_h = math.inf  # the step the last change allows

    def _now(self) -> np.ndarray[Any, np.dtype[np.float64]]:
        return np.array([read() for read in self.values], dtype=np.float64)

    def _ratio(self, now: np.ndarray[Any, np.dtype[np.float64]]) -> float:
        bound = np.maximum(self.abstol, self.reltol * np.maximum(np.abs(now), np.abs(self.last)))
        change = np.abs(now - self.last)
        return float(np.max(change / np.maximum(bound, 1e-300))) if len(now) else 0.0

    def start(self, t: float) -> None:
        self.last = self._now()

    def bound(self, t: float, target: float) -> float:
        return min(target, t + max(self.floor, self.next_h))

    def retry(self, t: float, h: float) -> float | None:
        ratio = self._ratio(self._now())
        return h * (1.0 - self.safety) / ratio if ratio > 1.0 else None

    def accept(self, t: float, h: float) -> None:
        now = self._now()
        ratio = self._ratio(now)
        self.next_h = h * (1.0 - self.safety) / ratio if ratio > 0 else math.inf
        self.last = now


class _Sampling(_Check):
    def __init__(self, c: Constraint) -> None:
        self.base, self.first_units, self.rate_units = c.base, c.start_time, c.rate
        self.first, self.period = self._time(c.start_time), self._time(c.rate)

    def _time(self, units: int) -> float:
        """`units` of 10^base s, rounded once (3 * 10^-1 is 0.3, not 0.30000000000000004)."""
        return units * 10.0**self.base if self.base >= 0 else units / 10.0**-self.base

    def bound(self, t: float, target: float) -> float:
        if t < self.first * (1 - 1e-12) - 1e-15:
            return min(target, self.first)
        k = math.floor((t - self.first) / self.period + 1e-9) + 1
        return min(target, self._time(self.first_units + k * self.rate_units))


class _FmuMaxStepSize(_Check):
    def __init__(self, asks: Sequence[Callable[[], float | None]], floor: float) -> None:
        self.asks = asks
        self.floor = floor  # min_size: a smaller answer gives this (Maestro does so too)

    def bound(self, t: float, target: float) -> float:
        for ask in self.asks:
            size = ask()
            if size is not None and size > 0:
                target = min(target, t + max(self.floor, size))
        return target


class Constraints:
    """The constraints of one run over its instances' buffers."""

    def __init__(self, checks: Sequence[_Check], warnings: Sequence[str]) -> None:
        self.checks = list(checks)
        self.warnings = list(warnings)  # what is not applied as the file asks

    def start(self, t: float) -> None:
        for check in self.checks:
            check.start(t)

    def bound(self, t: float, target: float) -> float:
        for check in self.checks:
            target = check.bound(t, target)
        return target

    def retry(self, t: float, h: float) -> float | None:
        shorter = [s for check in self.checks if (s := check.retry(t, h)) is not None]
        return min(shorter) if shorter else None

    def accept(self, t: float, h: float) -> None:
        for check in self.checks:
            check.accept(t, h)


def prepare(algorithm: Algorithm, slaves: Sequence[SlaveLike]) -> Constraints:
    """The algorithm's constraints over `slaves`, their ports registered with their instances
    (before the buffers are bound: the values are read from the buffers after each step)."""
    by_name = {s.name: s for s in slaves}
    floor = algorithm.min_size or algorithm.size
    checks: list[_Check] = []
    warnings: list[str] = []
    for c in algorithm.constraints:
        if c.kind == "samplingrate":
            checks.append(_Sampling(c))
        elif c.kind == "fmumaxstepsize":
            asks, missing = _max_step_asks(slaves)
            if missing:
                warnings.append(
                    f"constraint {c.name} (fmumaxstepsize): {', '.join(missing)} "
                    "provide no fmi2GetMaxStepsize; "
                    + ("only the others are asked" if asks else "not applied")
                )
            if asks:
                checks.append(_FmuMaxStepSize(asks, floor))
        elif c.kind == "zerocrossing":
            value = _difference([_reader(by_name, p) for p in c.ports])
            checks.append(_ZeroCrossing(c, value, floor))
        else:
            ports = [p for p in c.ports if not (c.skip_discrete and _discrete(by_name, p))]
            if ports:
                values = [_reader(by_name, p) for p in ports]
                checks.append(_BoundedDifference(c, values, floor))
    return Constraints(checks, warnings)


def _discrete(by_name: dict[str, SlaveLike], port: Port) -> bool:
    var = by_name[port.instance].info.variable(port.variable)
    if var is None:
        return False  # the instance's port() says so
    return var.type in ("Integer", "Boolean", "Enumeration") or var.type.startswith(("Int", "UInt"))


def _reader(by_name: dict[str, SlaveLike], port: Port) -> _Reader:
    """Register `port` as an output read after each step; its value then."""
    group, index = by_name[port.instance].port(port.variable, into=False)
    return lambda: float(group.buffer[index])  # the buffer bound later, looked up each time


def _difference(readers: Sequence[_Reader]) -> _Reader:
    if len(readers) == 1:
        return readers[0]
    first, second = readers
    return lambda: first() - second()


def _max_step_asks(
    slaves: Sequence[SlaveLike],
) -> tuple[list[Callable[[], float | None]], list[str]]:
    """fmi2GetMaxStepsize of each instance that exports it (an FMI 2 co-simulation FMU run
    in this process), and the labels of those that do not."""
    asks: list[Callable[[], float | None]] = []
    missing: list[str] = []
    for slave in slaves:
        ask = _max_step_of(slave)
        if ask is None:
            missing.append(slave.label)
        else:
            asks.append(ask)
    return asks, missing


def _max_step_of(slave: SlaveLike) -> Callable[[], float | None] | None:
    fmu: Any = getattr(slave, "fmu", None)  # slaves.Slave: FMPy's FMU2Slave / FMU3Slave
    dll = getattr(fmu, "dll", None)
    if fmu is None or dll is None or getattr(slave, "fmi3", True):
        return None
    identifier = getattr(fmu, "modelIdentifier", "")
    for symbol in ("fmi2GetMaxStepsize", f"{identifier}_fmi2GetMaxStepsize"):
        try:
            function = getattr(dll, symbol)
        except AttributeError:
            continue
        function.argtypes = [ctypes.c_void_p, ctypes.POINTER(ctypes.c_double)]
        function.restype = ctypes.c_int
        component = fmu.component

        def ask(function: Any = function, component: Any = component) -> float | None:
            size = ctypes.c_double(0.0)
            status = function(component, ctypes.byref(size))
            return size.value if status == 0 else None  # fmi2OK: a size; else no opinion

        return ask
    return None
