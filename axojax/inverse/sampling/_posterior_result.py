"""The result of :func:`axojax.inverse.posterior`: :class:`Posterior` (draws and their
summaries), its ``.npz`` file and the ``"posterior"`` block of a fit report."""

from __future__ import annotations

import dataclasses
import json
import math
from collections.abc import Mapping
from typing import Any

import numpy as np

from ..._io import atomic_path
from ...results import RESULTS, check_arrays, read_checked
from ...results import name as result_name
from ._laplace import Laplace

NPZ_KIND = "posterior"


@dataclasses.dataclass(frozen=True)
class Posterior:
    """Draws of a posterior and their summaries.

    Attributes:
        names: the k free parameters.
        u: (chains, draws, k) draws in the fitted coordinate (log or linear).
        value_names: names of ``values``' last axis (the free parameters first, then
            anything else ``problem.values`` reports, e.g. a tied kl).
        values: (chains, draws, n_values) the same draws as dimensionless parameter values.
        log_density: (chains, draws) log posterior density (in z) of each draw.
        divergent: (chains, draws) whether the draw's trajectory diverged.
        lower, upper: (k,) bounds in ``u``.
        log_coordinate: per name, whether ``u`` is the natural log of the value.
        mean, sd, q05, q50, q95: per name, of the parameter values (pooled over chains).
        mean_u, sd_u: per name, in the fitted coordinate (compare ``sd_u`` with the
            uniform prior's ``(upper - lower) / sqrt(12)``).
        rhat: per name, rank-normalised split R-hat (:mod:`.diagnostics`).
        ess, ess_tail: per name, bulk and tail effective sample size (total over chains).
        divergences: divergent transitions after warm-up (all chains).
        step_size: (chains,) adapted step sizes (in the whitened coordinates unless
            ``NUTS(whiten=False)``); acceptance: mean acceptance rate.
        warmup: warm-up steps per chain.
        gradients: log-density evaluations (gradient or not) of all chains, warm-up
            included: NUTS's leapfrog steps (each a value and gradient) of every step run
            (the draws kept and the compiled chunk's surplus), and two per chain at its
            start; the starts' optimisation and Laplace approximation are not counted.
        seconds: wall time of the whole call (compilation, optimisation, warm-up, sampling).
        seconds_compile: the part spent compiling (0 when a problem of the same structure
            was sampled before in this process: compiled programs are cached).
        seconds_start, seconds_warmup, seconds_sampling: wall time of the starts (mode
            and Laplace approximation), of the warm-up and of the draws (each with its
            compilation, if any).
        seconds_per_gradient: seconds of the warm-up and the draws, less their
            compilation, over ``gradients`` (vmapped chains evaluate theirs together).
        seconds_per_ess: seconds / the smallest bulk ESS.
        start_u: (k,) centre of the starts (the posterior mode unless ``init`` was given).
        message: what makes the draws untrustworthy (R-hat, ESS, divergences), one
            clause each, or the message of ``result`` (``"successful"``).
        result: :class:`axojax.results.RESULTS` item: ``successful``, or
            ``chains_not_converged`` (``message`` says why). The one test of success is
            ``post.result == RESULTS.successful``.
        laplace: the :class:`~axojax.inverse.sampling._laplace.Laplace` approximation at the centre
            of the starts (the fast answer; None in files written before it existed).
        sd_ratio: per name, posterior sd / Laplace sd, in u (1: the approximation holds).
        shift: per name, (posterior mean - Laplace centre) / Laplace sd, in u.
        tree_depth: mean NUTS tree depth of the draws (doublings; ``2**depth - 1``
            gradients at most).
        tree_depth_saturated: share of the draws whose tree reached ``max_num_doublings``.
        max_num_doublings: the sampler's tree depth limit.
        gradients_per_draw: mean gradients (leapfrog steps) per draw after warm-up.
        warm_cache: the start-up's cache (``posterior(cache=...)``): "off" (none, or a
            problem that cannot be fingerprinted), "stored" (computed and kept) or
            "loaded" (an identical run's: no start-up computed, ``seconds_warmup`` 0).
        seconds_compile_draws: the compilation of the draws' program, within
            ``seconds_sampling`` (so the first draw came ``seconds - seconds_sampling +
            seconds_compile_draws`` after the start, plus its own steps).
        transport: the parameter whose profile straightened the sampled coordinates
            (``posterior(transport=ProfileTransport(...))``), or None.
        sampler: "nuts", "smc" (``posterior(sampler=SMC(...))``: the chains are
            independent runs, the draws their particles; no divergences, step sizes,
            warm-up, start or Laplace approximation; ``gradients`` counts values) or
            "modes" (``posterior(sampler=ModeMixture(...))``: independence
            Metropolis-Hastings chains; ``warmup`` is the burn-in, ``gradients`` counts
            values).
        tempering_stages: per SMC run, its tempering stages (empty for NUTS).
        log_evidence: per SMC run, the log of the posterior's normalising constant over
            the uniform reference in u (runs that agree to ~0.1 saw the same modes).
        modes: per mode found (``sampler="modes"``), heaviest first: ``centre`` (the
            values of its best draw), ``log_density`` there, ``mass`` (its share of the
            draws), ``mass_importance`` (its share by importance weights) and
            ``components`` (:func:`~axojax.inverse.sampling.mode_report.mode_masses`).
        switches: the lines where the dominant eigenmode switches that the sampler met
            (``sampler="modes"``): ``points`` (values), ``range`` ({name: [min, max]}),
            ``jump`` (residuals, sigmas) (:func:`~axojax.inverse.sampling.switches.find_switches`).
    """

    names: tuple[str, ...]
    u: np.ndarray
    value_names: tuple[str, ...]
    values: np.ndarray
    log_density: np.ndarray
    divergent: np.ndarray
    lower: np.ndarray
    upper: np.ndarray
    log_coordinate: dict[str, bool]
    mean: dict[str, float]
    sd: dict[str, float]
    q05: dict[str, float]
    q50: dict[str, float]
    q95: dict[str, float]
    mean_u: dict[str, float]
    sd_u: dict[str, float]
    rhat: dict[str, float]
    ess: dict[str, float]
    ess_tail: dict[str, float]
    divergences: int
    step_size: np.ndarray
    acceptance: float
    warmup: int
    gradients: int
    seconds: float
    seconds_compile: float
    seconds_start: float
    seconds_warmup: float
    seconds_sampling: float
    seconds_per_gradient: float
    seconds_per_ess: float
    start_u: np.ndarray
    message: str
    result: RESULTS = dataclasses.field(default_factory=lambda: RESULTS.successful)
    laplace: Laplace | None = None
    sd_ratio: dict[str, float] = dataclasses.field(default_factory=dict)
    shift: dict[str, float] = dataclasses.field(default_factory=dict)
    tree_depth: float = math.nan
    tree_depth_saturated: float = math.nan
    max_num_doublings: int = 0
    gradients_per_draw: float = math.nan
    warm_cache: str = "off"
    seconds_compile_draws: float = 0.0
    transport: str | None = None
    sampler: str = "nuts"
    tempering_stages: tuple[int, ...] = ()
    log_evidence: tuple[float, ...] = ()
    modes: tuple[dict, ...] = ()
    switches: tuple[dict, ...] = ()

    @property
    def chains(self) -> int:
        return int(self.u.shape[0])

    @property
    def draws(self) -> int:
        """Draws per chain."""
        return int(self.u.shape[1])

    @property
    def gradients_per_ess(self) -> float:
        """Log-density evaluations (:attr:`gradients`) per effective draw of the parameter
        with the smallest bulk ESS (inf when an ESS is 0)."""
        ess = min(self.ess.values(), default=0.0)
        return float(self.gradients) / ess if ess > 0 else math.inf

    def value_draws(self, name: str) -> np.ndarray:
        """(chains, draws) draws of one parameter value."""
        return self.values[..., self.value_names.index(name)]

    @property
    def start(self) -> dict[str, float]:
        """The centre of the starts as parameter values (the posterior mode by default)."""
        return {
            n: float(math.exp(v) if self.log_coordinate[n] else v)
            for n, v in zip(self.names, self.start_u)
        }

    def to_json(self) -> dict[str, Any]:
        """The ``"posterior"`` block of ``axojax fit --posterior --json`` (docs/interface.md):
        ``draws`` (per chain), ``chains``, ``mean``, ``sd``, ``q05``, ``q95``, ``rhat``,
        ``ess`` (bulk), ``seconds``; also ``q50``, ``ess_tail``, ``divergences``, ``acceptance``,
        ``warmup``, ``seconds_compile``, ``seconds_start``, ``seconds_warmup``,
        ``seconds_sampling``, ``seconds_per_gradient``, ``seconds_per_ess``, ``message``, ``result``
        (the name of :attr:`result`), ``laplace`` (:meth:`Laplace.to_json`, or None),
        ``sd_ratio``, ``shift``, ``tree_depth``, ``tree_depth_saturated``,
        ``max_num_doublings``, ``gradients_per_draw``, ``warm_cache`` ("off", "stored"
        or "loaded": :func:`~axojax.inverse.posterior`'s ``cache``),
        ``seconds_compile_draws``, ``transport`` (the parameter along whose profile the
        sampled coordinates were straightened, or None), ``gradients`` (every log-density
        evaluation of the chains, warm-up included: :attr:`gradients`) and
        ``gradients_per_ess`` (``gradients`` over the smallest bulk ESS: the cost of one
        effective draw of the worst-sampled parameter), ``sampler`` ("nuts", "smc" or
        "modes"), ``tempering_stages`` and ``log_evidence`` (per SMC run; empty for NUTS),
        ``modes`` and ``switches`` (``sampler="modes"``; empty otherwise)."""
        return {
            "draws": self.draws,
            "chains": self.chains,
            "mean": dict(self.mean),
            "sd": dict(self.sd),
            "q05": dict(self.q05),
            "q50": dict(self.q50),
            "q95": dict(self.q95),
            "rhat": dict(self.rhat),
            "ess": dict(self.ess),
            "ess_tail": dict(self.ess_tail),
            "divergences": self.divergences,
            "acceptance": self.acceptance,
            "warmup": self.warmup,
            "seconds": self.seconds,
            "seconds_compile": self.seconds_compile,
            "seconds_start": self.seconds_start,
            "seconds_warmup": self.seconds_warmup,
            "seconds_sampling": self.seconds_sampling,
            "seconds_per_gradient": self.seconds_per_gradient,
            "seconds_per_ess": self.seconds_per_ess,
            "message": self.message,
            "result": result_name(self.result),
            "laplace": None if self.laplace is None else self.laplace.to_json(),
            "sd_ratio": dict(self.sd_ratio),
            "shift": dict(self.shift),
            "tree_depth": self.tree_depth,
            "tree_depth_saturated": self.tree_depth_saturated,
            "max_num_doublings": self.max_num_doublings,
            "gradients_per_draw": self.gradients_per_draw,
            "warm_cache": self.warm_cache,
            "seconds_compile_draws": self.seconds_compile_draws,
            "transport": self.transport,
            "gradients": int(self.gradients),
            "gradients_per_ess": self.gradients_per_ess,
            "sampler": self.sampler,
            "tempering_stages": list(self.tempering_stages),
            "log_evidence": list(self.log_evidence),
            "modes": list(self.modes),
            "switches": list(self.switches),
        }

    def save(self, path, *, truth: Mapping[str, float] | None = None) -> None:
        """Write an ``.npz`` for ``axojax plot`` (corner plot): arrays ``u``, ``values``,
        ``log_density``, ``divergent``, ``lower``, ``upper``, ``step_size``, ``start_u``
        and a ``meta`` JSON string (``kind = "posterior"``, the names, the scalar
        summaries, optional ``truth`` {name: value} drawn as markers)."""
        meta = {
            "kind": NPZ_KIND,
            "names": list(self.names),
            "value_names": list(self.value_names),
            "log_coordinate": self.log_coordinate,
            "truth": None if truth is None else {k: float(v) for k, v in truth.items()},
            "result": result_name(self.result),
            "laplace": None if self.laplace is None else self.laplace.to_dict(),
            **{
                f.name: getattr(self, f.name)
                for f in dataclasses.fields(self)
                if f.name in _SCALAR_FIELDS
            },
        }
        with atomic_path(path) as tmp:  # a killed run leaves no half-written file
            with open(tmp, "wb") as f:
                np.savez(
                    f,
                    meta=json.dumps(meta),
                    **{name: np.asarray(getattr(self, name)) for name in _ARRAY_FIELDS},
                )

    @classmethod
    def load(cls, path) -> Posterior:
        """Read what :meth:`save` wrote."""
        with np.load(path, allow_pickle=False) as f:
            meta = json.loads(str(f["meta"]))
            if meta.get("kind") != NPZ_KIND:
                raise ValueError(
                    f"{str(path)!r} is not an axojax posterior (kind {meta.get('kind')!r})"
                )
            arrays = {name: np.asarray(f[name]) for name in _ARRAY_FIELDS}
        scalars = {k: meta[k] for k in _SCALAR_FIELDS if k in meta}  # older files: fewer
        laplace = meta.get("laplace")
        for name in ("tempering_stages", "log_evidence", "modes", "switches"):  # JSON lists
            if name in scalars:
                scalars[name] = tuple(scalars[name])
        return cls(
            laplace=None if laplace is None else Laplace.from_dict(laplace),
            names=tuple(meta["names"]),
            value_names=tuple(meta["value_names"]),
            log_coordinate=meta["log_coordinate"],
            result=getattr(RESULTS, meta.get("result", "successful")),
            **scalars,
            **arrays,
        )

    @classmethod
    def read(cls, path) -> Posterior:
        """:meth:`load`, the file checked whole (draws of every parameter); a file that is
        not is one :class:`~axojax.results.ResultFileError` naming it."""

        def checked(path):
            post = cls.load(path)
            check_arrays(path, NPZ_KIND, {"u": post.u}, {"u": (None, None, len(post.names))})
            return post

        return read_checked(path, NPZ_KIND, checked)


_ARRAY_FIELDS = (
    "u",
    "values",
    "log_density",
    "divergent",
    "lower",
    "upper",
    "step_size",
    "start_u",
)
_SCALAR_FIELDS = (
    "mean",
    "sd",
    "q05",
    "q50",
    "q95",
    "mean_u",
    "sd_u",
    "rhat",
    "ess",
    "ess_tail",
    "divergences",
    "acceptance",
    "warmup",
    "gradients",
    "seconds",
    "seconds_compile",
    "seconds_start",
    "seconds_warmup",
    "seconds_sampling",
    "seconds_per_gradient",
    "seconds_per_ess",
    "message",
    "sd_ratio",
    "shift",
    "tree_depth",
    "tree_depth_saturated",
    "max_num_doublings",
    "gradients_per_draw",
    "warm_cache",
    "seconds_compile_draws",
    "transport",
    "sampler",
    "tempering_stages",
    "log_evidence",
    "modes",
    "switches",
)


def load_truth(path) -> dict[str, float] | None:
    """The ``truth`` markers stored by :meth:`Posterior.save` (None if none)."""
    with np.load(path, allow_pickle=False) as f:
        return json.loads(str(f["meta"])).get("truth")
