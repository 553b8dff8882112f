"""Conversion of user input to floats and arrays, with errors that name the argument."""

from __future__ import annotations

import math
import numbers

import numpy as np

from ._errors import ParameterError


def real(name: str, value: object) -> float:
    """``value`` as a finite Python float, or a ParameterError naming ``name``."""
    if type(value) is float and math.isfinite(value):
        return value  # the common case, without the checks against the numeric ABCs
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Real, np.floating)):
        raise ParameterError(f"{name} = {shown(value)} is not allowed: it must be a real number")
    try:
        x = float(value)
    except OverflowError:
        raise ParameterError(
            f"{name} = {shown(value)} is not allowed: it must be a finite number (a float "
            "holds at most 1.8e+308)"
        ) from None
    if not math.isfinite(x):
        raise ParameterError(f"{name} = {x} is not allowed: it must be a finite number")
    return x


def shown(value: object) -> str:
    """``repr(value)``, or for an integer of more than 60 digits its number of digits (Python
    refuses to print an integer of more than 4300 digits)."""
    if isinstance(value, numbers.Integral) and abs(int(value)).bit_length() > 200:
        digits = int(abs(int(value)).bit_length() * math.log10(2)) + 1
        return f"<an integer of about {digits} digits>"
    return repr(value)


def floats(name: str, value: object) -> np.ndarray:
    """``value`` as a float64 array of any shape (not checked further), or a ParameterError
    naming ``name`` where it is not numbers (a string, a complex number, a ragged list)."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(
            f"{name} = {value!r} is not allowed: it must be a number or an array of numbers"
        ) from None
    return arr


def times(name: str, value: object) -> np.ndarray:
    """``value`` as a contiguous 1-D float64 array of finite numbers (a scalar gives length 1)."""
    arr = floats(name, value)
    if arr.ndim == 0:
        arr = arr.reshape(1)
    if arr.ndim != 1:
        raise ParameterError(f"{name} has shape {arr.shape}, which is not allowed: it must be 1-D")
    bad = ~np.isfinite(arr)
    if bad.any():
        i = int(np.argmax(bad))
        raise ParameterError(
            f"{name}[{i}] = {arr[i]} is not allowed: every time must be a finite number"
        )
    return np.ascontiguousarray(arr)


def integer(name: str, value: object) -> int:
    """``value`` as a Python int (an int or a numpy integer, not a bool), or a ParameterError
    naming ``name``: quantum numbers and sizes are counted, never measured."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Integral, np.integer)):
        raise ParameterError(f"{name} = {shown(value)} is not allowed: it must be an integer")
    return int(value)


def vector(name: str, value, n: int) -> list[float]:
    """``n`` finite numbers, each checked by name (``name[i]``)."""
    try:
        arr = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ParameterError(f"{name} = {value!r} is not allowed: it must be {n} numbers") from None
    if arr.shape != (n,):
        raise ParameterError(
            f"{name} has shape {arr.shape}, which is not allowed: it must be {n} numbers"
        )
    return [real(f"{name}[{i}]", x) for i, x in enumerate(arr)]
