"""The sampler base class (:class:`AbstractSampler`): what :func:`~axojax.inverse.posterior`
calls. A sampler is an equinox Module whose fields are its settings and whose
:meth:`~AbstractSampler.run` samples one problem's posterior; :class:`NUTS`, :class:`SMC`
and :class:`ModeMixture` are three, and one of a user's own is passed the same way
(``posterior(problem, sampler=MySampler())``)."""

from __future__ import annotations

import abc
import os
from collections.abc import Callable
from typing import Any

import equinox as eqx

from ._laplace import Laplace
from ._posterior_result import Posterior

AUTO = "auto"
"""``transport``'s default (:func:`~axojax.inverse.posterior`): the sampler chooses (NUTS:
:func:`~axojax.inverse.suggest_transport` of a least-squares fit it starts from, else the
affine whitening; a gradient-free sampler: none)."""


class AbstractSampler(eqx.Module):
    """A posterior sampler: its settings (the fields) and :meth:`run`, which
    :func:`~axojax.inverse.posterior` calls once it has checked the arguments every
    sampler shares. Subclass it (fields for the settings, ``run`` for the work) to pass a
    sampler of one's own as ``posterior(problem, sampler=...)``;
    :mod:`axojax.inverse.sampling.summaries` and :mod:`~axojax.inverse.sampling.programs`
    hold what the three built in share (draws as values, statistics, a gradient-free
    sampler's :class:`~axojax.inverse.Posterior`, compiled pieces)."""

    @abc.abstractmethod
    def run(
        self,
        problem: Any,
        *,
        draws: int,
        chains: int,
        warmup: int | None,
        seed: int,
        init: Any,
        prior: Callable | None,
        vectorize: bool | None,
        progress: bool,
        on_laplace: Callable[[Laplace], None] | None,
        cache: bool | str | os.PathLike | None,
        transport: Any,
    ) -> Posterior:
        """The posterior of ``problem`` (an :class:`~axojax.inverse.InverseProblem`).

        :func:`~axojax.inverse.posterior` passes every argument it took, checked: ``draws``
        and ``chains`` integers >= 1 (draws >= 4), ``warmup`` an integer >= 0 or None
        (the sampler's own default), ``prior`` a callable log prior in u or None (the
        problem's own; a ``{name: (mean_u, sd_u)}`` mapping already made a
        :class:`~axojax.inverse.NormalPrior`); ``init``, ``vectorize``, ``on_laplace``,
        ``cache`` and ``transport`` as :func:`~axojax.inverse.posterior` documents them.
        A sampler ignores what does not apply to it and refuses, with a one-line
        ``ValueError``, what it cannot honour (e.g. a transport). Warnings for the caller
        (R-hat, ESS, ...) are one line each."""


def refuse_transport(sampler: str, transport: Any) -> None:
    """One-line ``ValueError`` for a transport given to ``sampler`` (named), which samples
    z as it is; :data:`AUTO` and None pass."""
    if transport is not None and not (isinstance(transport, str) and transport == AUTO):
        raise ValueError(f"transport: applies to NUTS; {sampler} samples z as it is")
