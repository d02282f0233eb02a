"""The samplers' compiled programs: :func:`compiled` runs a piece ``fn(static, *dynamic)``
by an ahead-of-time compiled program, cached per piece, static values and the dynamic
arrays' shapes; :class:`Clock` runs pieces so and adds up the seconds spent compiling.

Each piece runs as fn(static, *dynamic): the arrays of the problem (when it is a pytree,
e.g. an equinox Module) and of the prior are dynamic, so problems of one structure with
other data (another seed, another condition) reuse the compiled program. Shared by every
sampler of :mod:`axojax.inverse.sampling` (and open to one of a user's own)."""

from __future__ import annotations

import time
from typing import Any

import equinox as eqx
import jax
import jax.numpy as jnp

CACHE_SIZE = 16
"""Compiled programs kept (the oldest dropped first)."""
_CACHE: dict = {}


class Static:
    """A static argument: hashed by value where it can be, else by identity."""

    def __init__(self, obj):
        self.obj = obj
        try:
            self._hash = hash(obj)
            self._by_value = True
        except TypeError:
            self._hash = id(obj)
            self._by_value = False

    def __hash__(self):
        return self._hash

    def __eq__(self, other):
        if not isinstance(other, Static) or self._by_value != other._by_value:
            return False
        return bool(self.obj == other.obj) if self._by_value else self.obj is other.obj


def compiled(fn, static, dynamic: tuple) -> tuple[Any, float]:
    """``fn(static, *dynamic)`` run by an ahead-of-time compiled program (cached per fn,
    static values and the dynamic arrays' shapes), and the seconds spent compiling."""
    target, *rest = dynamic
    dyn, stat = eqx.partition(target, eqx.is_array)
    leaves, treedef = jax.tree.flatten((dyn, rest))
    key = (
        fn,
        Static((stat, static)),
        treedef,
        tuple((jnp.shape(x), jnp.result_type(x)) for x in leaves),
    )
    seconds = 0.0
    if key not in _CACHE:
        t0 = time.perf_counter()

        def run(static_, dyn_, rest_):
            stat_, fixed = static_.obj
            return fn(fixed, eqx.combine(dyn_, stat_), *rest_)

        _CACHE[key] = (
            jax.jit(run, static_argnums=0).lower(Static((stat, static)), dyn, rest).compile()
        )
        seconds = time.perf_counter() - t0
        while len(_CACHE) > CACHE_SIZE:
            _CACHE.pop(next(iter(_CACHE)))
    return _CACHE[key](dyn, rest), seconds


class Clock:
    """Runs compiled pieces (:func:`compiled`) and adds up their compilation."""

    def __init__(self):
        self.seconds = 0.0

    def call(self, fn, static, *dynamic):
        out, seconds = compiled(fn, static, dynamic)
        self.seconds += seconds
        return out
