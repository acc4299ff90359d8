"""Python-side helpers shared by every binding and reference: argument conversion, batch
inputs and outputs, error messages that name the argument.

Nothing here is part of an algorithm; the algorithms live in ``csrc/`` and,
for reading, in :mod:`fusion_altitude.reference`.
"""

from __future__ import annotations

import functools
import math
import warnings
from typing import Mapping, Optional, Sequence, Tuple

import numpy as np

from ._c_tables import FUSION_ALTITUDE_GRAVITY as _FUSION_ALTITUDE_GRAVITY


#: Standard gravity, m/s². Multiply an acceleration in g by this.
GRAVITY = _FUSION_ALTITUDE_GRAVITY  # fusion_altitude.h, through the generated tables


def as_float(value: object, name: str) -> float:
    """Return ``value`` as a Python float, or raise TypeError naming ``name``."""
    if isinstance(value, float):
        return value
    kind = type(value)
    if hasattr(kind, "__float__") or hasattr(kind, "__index__"):  # as CPython's PyFloat_AsDouble
        return float(value)  # type: ignore[arg-type]
    raise TypeError(f"{name} must be a real number, got {kind.__name__}")


def as_float32_vector(value: object, name: str) -> np.ndarray:
    """A 1-D array-like of reals as a contiguous float32 array, or TypeError/ValueError naming it."""
    array = np.asarray(value)
    if array.dtype.kind not in "fiub":
        raise TypeError(f"{name} must be an array of real numbers, got dtype {array.dtype}")
    if array.ndim != 1:
        raise ValueError(f"{name} must be 1-D, got shape {array.shape}")
    with np.errstate(over="ignore"):
        return np.ascontiguousarray(array, dtype=np.float32)


def status_message(messages: Sequence[str], status: object) -> str:
    """The C header's message for ``status`` (an int or enum member) from a generated message table."""
    index = int(status)  # type: ignore[call-overload]
    return messages[index] if 0 <= index < len(messages) else "unknown status"


def raise_input_error(rules: Mapping[int, Tuple[str, str]], status: int, values: Mapping[str, object],
                      index: Optional[int] = None, is_array: Optional[Mapping[str, bool]] = None) -> None:
    """Raise the ValueError for a rejected update, naming the argument (and, in a batch, its first bad index).

    ``rules`` maps each input status to (argument name, rule text); ``is_array``
    says which arguments were given per sample (a scalar gets no index).
    """
    name, rule = rules[status]
    where = name if index is None or not (is_array or {}).get(name, True) else f"{name}[{index}]"
    raise ValueError(f"{where} {rule}, got {values[name]!r}")


#: Rule texts of update inputs that several estimators share (the message is "<argument> <rule>, got <value>").
ACCEL_FINITE = "must be finite (m/s²)"
DT_POSITIVE = "must be finite and > 0 (s)"
SAMPLE_OR_NAN = "must be finite, or NaN for no sample (m)"
BARO_SAMPLE_OR_NAN = "must be finite, or NaN for no baro sample (m)"


def input_rules(statuses, **rules) -> dict:
    """{status: (argument, rule text)} for :func:`raise_input_error`: each keyword is an argument and its rule text,
    rejected with the member ``INVALID_<ARGUMENT>`` of the status enum ``statuses``, or (member name, rule text)."""
    table = {}
    for name, rule in rules.items():
        member, text = rule if isinstance(rule, tuple) else ("INVALID_" + name.upper(), rule)
        table[statuses[member]] = (name, text)  # type: ignore[index]
    return table


def output_arrays(batch_type: type, layout: Sequence[Tuple[Tuple[int, ...], object]],
                  out: Optional[Sequence[np.ndarray]]):
    """New output arrays of ``layout`` ((shape, dtype) per field of ``batch_type``), or ``out`` after checking it."""
    if out is None:
        return batch_type(*(np.empty(shape, dtype=dtype) for shape, dtype in layout))
    if len(out) != len(layout):
        raise ValueError(f"out must hold {len(layout)} arrays ({', '.join(batch_type._fields)}), got {len(out)}")
    for field, array, (shape, dtype) in zip(batch_type._fields, out, layout):
        if not isinstance(array, np.ndarray) or array.dtype != dtype or array.shape != shape \
                or not array.flags.c_contiguous or not array.flags.writeable:
            raise ValueError(f"out.{field} must be a writeable contiguous {np.dtype(dtype).name} array of shape {shape}")
    check_no_overlap(dict(zip(batch_type._fields, out)))
    return batch_type(*out)


def check_no_overlap(arrays: "dict[str, np.ndarray]", prefix: str = "out.") -> None:
    """ValueError naming the first two of ``arrays`` that share memory (each output must have its own: one
    array for every output would be written over by each in turn and return garbage)."""
    names = list(arrays)
    for i, first in enumerate(names):
        for second in names[i + 1:]:
            if np.may_share_memory(arrays[first], arrays[second]) and \
                    np.shares_memory(arrays[first], arrays[second], max_work=10 ** 6):
                raise ValueError(f"{prefix}{first} and {prefix}{second} share memory: give each output its own array")


def prepare_inputs(accel: object, baro_altitude: object, dt: object) -> Tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
    """Convert per-sample (accel, baro_altitude, dt) to contiguous float32 vectors and check their lengths.

    Returns accel and baro_altitude (length n), dt (length n, or 1 for a
    scalar dt) and whether dt was given per sample.
    """
    accel32 = as_float32_vector(accel, "accel")
    baro32 = as_float32_vector(baro_altitude, "baro_altitude")
    n = accel32.shape[0]
    if baro32.shape[0] != n:
        raise ValueError(f"baro_altitude has {baro32.shape[0]} samples but accel has {n}")
    dt_is_array = np.ndim(dt) != 0
    if dt_is_array:
        dt32 = as_float32_vector(dt, "dt")
        if dt32.shape[0] != n:
            raise ValueError(f"dt has {dt32.shape[0]} samples but accel has {n}")
    else:
        with np.errstate(over="ignore"):
            dt32 = np.array([as_float(dt, "dt")], dtype=np.float32)
    return accel32, baro32, dt32, dt_is_array


def optional_input(value: object, name: str, n: int, fill: float = math.nan) -> np.ndarray:
    """A per-step float32 input of a batch: None → [fill], a scalar → [value] (both broadcast, step 0),
    else a contiguous vector of length n."""
    if value is None:
        return np.array([fill], dtype=np.float32)
    if np.ndim(value) == 0:
        with np.errstate(over="ignore"):
            return np.array([as_float(value, name)], dtype=np.float32)
    array = as_float32_vector(value, name)
    if array.shape[0] != n:
        raise ValueError(f"{name} has {array.shape[0]} samples but accel has {n}")
    return array


def optional_inputs(arguments: Mapping[str, object]) -> Tuple[int, dict, dict]:
    """The float32 inputs of a multi-sensor batch: ``arguments`` maps names to values, accel first.

    Returns (n, inputs, steps): ``inputs[name]`` has length n, or 1 for a
    scalar or None (then ``steps[name]`` is 0, else 1).
    """
    if arguments.get("dt", 0) is None:
        raise TypeError("dt must be a real number or an array, got None")
    names = iter(arguments)
    first = next(names)
    accel32 = as_float32_vector(arguments[first], first)
    n = accel32.shape[0]
    inputs = {first: accel32}
    inputs.update((name, optional_input(arguments[name], name, n)) for name in names)
    steps = {name: 0 if value is None or np.ndim(value) == 0 else 1 for name, value in arguments.items()}
    return n, inputs, steps


class _Unset:
    """The default of a binding argument left out: the bindings tell it from any value a caller passes."""

    __slots__ = ()

    def __repr__(self) -> str:
        return "<unset>"


UNSET = _Unset()


#: Whether this module runs compiled (setup.py compiles it with Cython): compiled functions have no Python
#: frame, which decides the stacklevel that makes a warning point at the caller's line.
_COMPILED = not __file__.endswith((".py", ".pyc"))


def legacy_arguments(owner: str, method: str, legacy: Tuple[str, ...], args: Sequence[object], kwargs: dict,
                     no_sample: object, frames: int = 1) -> dict:
    """The keyword arguments of a call ``method(accel, *args, **kwargs)`` whose positional arguments after
    accel are in the old order ``legacy``: warns (DeprecationWarning, at the caller's line), then adds
    ``args`` to ``kwargs`` under their old names; TypeError for too many or a name given twice. A left-out
    ``baro_altitude`` is ``no_sample``. ``frames``: Python frames between the caller and this function
    when it runs uncompiled (the Cython bindings have none; :func:`argument_order`'s wrapper is one).
    """
    name = f"{owner}.{method}"
    warnings.warn(f"{name}: positional arguments after accel are read in the old order (accel, "
                  f"{', '.join(legacy[:len(args)])}); from the next release the order is (accel, "
                  "baro_altitude, dt, ...): pass them by keyword", DeprecationWarning,
                  stacklevel=1 if _COMPILED else frames + 1)
    if len(args) > len(legacy):
        raise TypeError(f"{name}() takes at most {len(legacy) + 1} positional arguments after self")
    for key, value in zip(legacy, args):
        if key in kwargs:
            raise TypeError(f"{name}() got multiple values for argument {key!r}")
        kwargs[key] = value
    kwargs.setdefault("baro_altitude", no_sample)
    return kwargs


def positional_after_accel(owner: str, method: str, names: Tuple[str, ...], legacy: Tuple[str, ...],
                           args: Sequence[object], values: Sequence[object], unset: object) -> tuple:
    """The argument values of a binding's ``method(accel, *args, **keywords)`` called with positional
    arguments after accel (``args`` not empty; the keyword path never comes here).

    ``names`` are the keyword arguments in order, ``baro_altitude`` and ``dt`` first; ``values`` what the
    call gave them (``unset``: left out). One positional argument with ``dt=`` is the contract order
    ``(accel, baro_altitude, dt=...)``; anything else is the deprecated old order ``(accel, *legacy)``
    (:func:`legacy_arguments`: a DeprecationWarning at the caller's line). Returns the values in the order
    of ``names``, ``unset`` where left out. The same rules as :func:`argument_order`, which the reference
    uses.
    """
    if len(args) == 1 and values[1] is not unset:
        if values[0] is not unset:
            raise TypeError(f"{method}() got multiple values for keyword argument 'baro_altitude'")
        return (args[0], *values[1:])
    given = {name: value for name, value in zip(names, values) if value is not unset}
    given = legacy_arguments(owner, method, legacy, args, given, unset, frames=2)
    return tuple(given.get(name, unset) for name in names)


def argument_order(legacy: Tuple[str, ...]):
    """Decorator: the contract order ``(accel, baro_altitude, dt, *, other sensors...)`` for an estimator whose
    old order was ``(accel, *legacy)``: for one release, positional arguments after ``accel`` keep their old
    meaning, with a DeprecationWarning (pass baro_altitude= and dt= by keyword; in the next release the
    positional order is the new one). Keywords work throughout; ``baro_altitude`` may be left out, as
    before: no sample (NaN per sample, None in a batch). ``update(accel, baro_altitude, dt=dt)`` (one
    positional after accel, dt by keyword) is the contract order too, without a warning.

    The pure-Python reference uses this decorator; the Cython bindings do the same in their own argument
    parsing (``*args`` after accel, keyword-only sensors), calling :func:`legacy_arguments` only when
    positional arguments follow accel, so that the keyword path costs nothing.
    """
    def decorate(method):
        no_sample = None if method.__name__ == "update_batch" else math.nan

        @functools.wraps(method)
        def wrapper(self, accel, *args, **kwargs):
            if not args:  # keywords: the fast path, positional into the method
                baro_altitude, dt = kwargs.pop("baro_altitude", no_sample), kwargs.pop("dt", None)
                if kwargs:
                    return method(self, accel, baro_altitude, dt, **kwargs)
                return method(self, accel, baro_altitude, dt)
            if len(args) == 1 and "dt" in kwargs:
                return method(self, accel, args[0], kwargs.pop("dt"), **kwargs)
            return method(self, accel, **legacy_arguments(type(self).__name__, method.__name__, legacy, args, kwargs,
                                                          no_sample, frames=2))
        return wrapper
    return decorate


def share_signatures(binding: type, reference: type, names: Sequence[str]) -> None:
    """Give the binding's methods ``names`` the reference's signature (what ``inspect.signature`` and ``help``
    show): the bindings parse ``(accel, *args, baro_altitude=, dt=, ...)`` to keep the deprecated positional
    order for one release, but their contract is the reference's ``(accel, baro_altitude, dt, *, ...)``."""
    import inspect
    for name in names:
        getattr(binding, name).__signature__ = inspect.signature(getattr(reference, name))


def batch_raises_and_notes(unit: str) -> str:
    """The Raises and Notes sections of a binding's ``update_batch`` docstring (a batch of ``unit``: "sample" or
    "step"), written once for the bindings that state them alike; a contract class appends them to its docstring."""
    return f"""

        Raises
        ------
        ValueError
            A bad {unit}, naming the argument and its first bad index; nothing
            is applied to the state.

        Notes
        -----
        Equal, bit for bit, to calling :meth:`update` for each {unit}. The loop
        runs with the GIL released.
        """


def share_docstrings(binding: type, reference: type) -> None:
    """Give each method of the binding class that has no docstring the reference's (written once, there)."""
    for name, member in vars(binding).items():
        source = getattr(reference, name, None)
        if callable(member) and not getattr(member, "__doc__", None) and getattr(source, "__doc__", None):
            member.__doc__ = source.__doc__
