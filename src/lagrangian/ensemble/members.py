"""The members of an ensemble: initial values and parameters broadcast together.

``initial`` and ``params`` map names to array-likes; all are broadcast
together (NumPy rules) to the member shape.  A 1-D (or scalar) shape gives the
dimension ``member``; a grid (ndim >= 2) names each axis after the first
input that varies along that axis only (``theta1`` x ``theta2``), else
``axis<k>``.  A :class:`GridAxis` (the CLI's ``--grid NAME=LO:HI:N``) is such a
grid axis given by its range, made into values only once the members are known to
fit in memory.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..errors import ModelError
from ..numeric.compiled import check_initial

if TYPE_CHECKING:
    from ..numeric.compiled import CompiledSystem


@dataclass(frozen=True)
class GridAxis:
    """``count`` values from ``low`` to ``high`` (a linspace) along axis ``axis`` of ``ndim``."""

    low: float
    high: float
    count: int
    axis: int = 0
    ndim: int = 1

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(self.count if k == self.axis else 1 for k in range(self.ndim))

    def __array__(self, dtype=None, copy=None) -> np.ndarray:
        values = np.linspace(self.low, self.high, self.count).reshape(self.shape)
        return values if dtype is None else values.astype(dtype)


@dataclass(frozen=True)
class Members:
    """The batch: y0 (2n, B), params (P,) or (P, B), and the grid's dims and coordinates."""

    y0: np.ndarray
    params: np.ndarray
    shape: tuple[int, ...]
    dims: tuple[str, ...]
    coords: dict[str, tuple[tuple[str, ...], np.ndarray]]

    @property
    def count(self) -> int:
        return self.y0.shape[1]


def members(
    compiled: CompiledSystem,
    initial: Mapping[str, object] | None,
    params: Mapping[str, object] | None,
    *,
    before_allocating: Callable[[int], None] | None = None,
) -> Members:
    """The batch of ``compiled``'s states and parameters (see the module docstring).

    ``before_allocating(count)`` is called with the number of members once it is
    known, before the batch is made (to refuse one that cannot fit in memory).
    """
    initial, params = dict(initial or {}), dict(params or {})
    state_names = [*compiled.coordinate_names, *(f"{q}_dot" for q in compiled.coordinate_names)]
    for name in initial:
        if name not in state_names:
            raise ModelError(f"'{name}' is not a coordinate or velocity ({', '.join(state_names)})")
    for name in params:
        if name not in compiled.parameter_names:
            known = ", ".join(compiled.parameter_names) or "none"
            raise ModelError(f"unknown parameter '{name}' (parameters: {known})")
    given = {**initial, **params}
    if len(given) != len(initial) + len(params):
        raise ModelError("a name is given both as an initial value and as a parameter")
    try:
        shapes = {name: _shape(value) for name, value in given.items()}
        shape = np.broadcast_shapes(*shapes.values()) if shapes else ()
    except (TypeError, ValueError) as error:
        raise ModelError(f"the initial values and parameters do not broadcast: {error}") from None
    shape = shape or (1,)
    count = math.prod(shape)  # a Python int: no overflow for a hostile grid
    if count == 0:
        raise ModelError("the ensemble has no members")
    if before_allocating is not None:
        before_allocating(count)
    arrays = {name: np.asarray(value, dtype=float) for name, value in given.items()}
    for name in initial:
        check_initial(name, arrays[name])
    # the model file's own checks (sign, 3-D bodies' inertia) for every member, before the
    # defaults are read, so the error names the value given
    compiled.check_parameters({name: arrays[name] for name in params})
    y0 = np.repeat(compiled.state_vector({})[:, None], count, axis=1)
    for name in initial:
        y0[state_names.index(name)] = np.broadcast_to(arrays[name], shape).ravel()
    base = compiled.parameter_vector({name: np.ravel(arrays[name])[0] for name in params})
    if params:
        p = np.repeat(base[:, None], count, axis=1)
        for name in params:
            p[compiled.parameter_names.index(name)] = np.broadcast_to(arrays[name], shape).ravel()
    else:
        p = base
    dims, coords = _dims(shape, arrays)
    return Members(y0=y0, params=p, shape=shape, dims=dims, coords=coords)


def _shape(value: object) -> tuple[int, ...]:
    """The shape of an input, without making the values of a :class:`GridAxis`."""
    if isinstance(value, GridAxis):
        return value.shape
    return np.asarray(value, dtype=float).shape


def _dims(shape, arrays):
    if len(shape) == 1:
        dims = ("member",)
        coords = {name: (dims, np.broadcast_to(a, shape).copy()) for name, a in arrays.items()}
        return dims, coords
    ndim = len(shape)
    padded = {name: a.reshape((1,) * (ndim - a.ndim) + a.shape) for name, a in arrays.items()}
    dims = [f"axis{k}" for k in range(ndim)]
    along: dict[str, int] = {}
    for name, a in padded.items():
        varying = [k for k in range(ndim) if a.shape[k] > 1]
        if len(varying) == 1:
            along[name] = varying[0]
    for k in range(ndim):
        for name, axis in along.items():
            if axis == k and shape[k] > 1:
                dims[k] = name
                break
    coords = {}
    for name, a in padded.items():
        if name in along:
            coords[name] = ((dims[along[name]],), a.ravel().copy())
        else:
            coords[name] = (tuple(dims), np.broadcast_to(a, shape).copy())
    return tuple(dims), coords
