"""``axojax fit --posterior``: the flags of the posterior that follows a fit
(``--posterior``, ``--chains``, ``--warmup``, ``--along``, ``--sampler``), their checks,
and the run of :func:`axojax.inverse.posterior`: NUTS from the fit's optimum (with the
warm-state cache when the compilation cache is on, the Laplace approximation printed
first), ``--sampler smc``: independent SMC runs from the prior, or ``--sampler modes``:
independence Metropolis-Hastings chains from a mixture fitted to every mode;
``--sampler auto`` (the default): the library's choice by the number of free parameters
(:func:`axojax.inverse.choose_sampler`), NUTS when a NUTS flag (``--along``,
``--warmup``) is given. The report's ``sampler_reason`` says which ran and why. The
defaults (the warm-up, the chains' layout, the transport chosen from the fit) are the
library's own (:mod:`axojax.inverse.sampling`): the command passes its flags only."""

from __future__ import annotations

import argparse
import sys
import warnings

from ...cache import WARM_SUBDIR, compilation_cache_dir
from ...inverse import SMC, ModeMixture, ProfileTransport, choose_sampler, posterior
from ...inverse.sampling import (
    MAX_ALONG_WARMUP,
    MAX_DEFAULT_WARMUP,
    MIN_WARMUP,
    MODES_MAX_FREE,
)
from .. import common
from .text import render_laplace

AUTO = "auto"
"""``--sampler``'s default (the library picks by the problem: :func:`sampler_of`), and
what :func:`transport_of` returns without ``--along``: the library chooses from the fit
(:func:`axojax.inverse.posterior`'s ``transport="auto"``)."""

MAX_DRAWS = 100_000  # draws per chain of --posterior (a 3-parameter posterior needs ~1000)
MAX_CHAINS = 64


def check_arguments(args: argparse.Namespace) -> None:
    """One-line errors for the posterior's flags (before any work)."""
    if args.posterior is None:
        if args.chains != 4:
            raise common.CLIError("--chains: applies to the posterior; add --posterior DRAWS")
        if args.warmup is not None:
            raise common.CLIError("--warmup: applies to the posterior; add --posterior DRAWS")
        if args.along is not None:
            raise common.CLIError("--along: applies to the posterior; add --posterior DRAWS")
        if args.sampler != AUTO:
            raise common.CLIError("--sampler: applies to the posterior; add --posterior DRAWS")
        return
    if args.sampler not in ("nuts", AUTO):
        for flag, value in (("--warmup", args.warmup), ("--along", args.along)):
            if value is not None:
                raise common.CLIError(f"{flag}: applies to NUTS, not to --sampler {args.sampler}")
    if args.warmup is not None and not MIN_WARMUP <= args.warmup <= MAX_DRAWS:
        raise common.CLIError(
            f"--warmup: steps per chain must be in {MIN_WARMUP}..{MAX_DRAWS}, got {args.warmup}"
        )
    if not 4 <= args.posterior <= MAX_DRAWS:
        raise common.CLIError(
            f"--posterior: draws per chain must be in 4..{MAX_DRAWS}, got {args.posterior}"
        )
    if not 1 <= args.chains <= MAX_CHAINS:
        raise common.CLIError(
            f"--chains: expected an integer in 1..{MAX_CHAINS}, got {args.chains}"
        )


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The posterior's flags of ``axojax fit``."""
    parser.add_argument(
        "--posterior",
        type=int,
        default=None,
        metavar="DRAWS",
        help="then sample the posterior: DRAWS per chain, by the sampler --sampler picks (NUTS "
        'from the optimum after --warmup steps). Adds "posterior" to the report: the line after '
        "its table gives the result, and the exit status is 1 when the chains did not converge; "
        "with --out FIT.json the draws go to FIT.posterior.npz, drawn by 'axojax plot'",
    )
    parser.add_argument(
        "--chains",
        type=int,
        default=4,
        metavar="C",
        help="posterior chains (default 4; with --posterior)",
    )
    parser.add_argument(
        "--warmup",
        type=int,
        default=None,
        metavar="STEPS",
        help="posterior warm-up (window adaptation) steps per chain (default: DRAWS, at least "
        f"{MIN_WARMUP} and at most {MAX_DEFAULT_WARMUP}, {MAX_ALONG_WARMUP} with --along: the chains "
        "start whitened by the Laplace approximation at the optimum; with --posterior)",
    )
    parser.add_argument(
        "--along",
        default=None,
        metavar="NAME",
        help="with --posterior: sample in coordinates straightened along the profile of the free "
        "parameter NAME (a long curved ridge, e.g. ks when p and ks are fitted to a frequency and a "
        "wavelength: the ridge is p as a function of ks); the posterior is the same, the trajectories "
        "shorter (axojax.inverse.ProfileTransport). Default: chosen from the fit, along the "
        "parameter of the widest standard error when two correlate by 0.99 or more, else (up to "
        "three free parameters) the profile that importance sampling prefers to the Laplace "
        "whitening, if any (axojax.inverse.suggest_transport); 'none': plain NUTS in whitened "
        "coordinates",
    )
    parser.add_argument(
        "--sampler",
        choices=(AUTO, "nuts", "smc", "modes"),
        default=AUTO,
        help=f"with --posterior: '{AUTO}' (default): 'modes' up to {MODES_MAX_FREE} free parameters, "
        "'nuts' beyond or with --along or --warmup (the report says which and why); "
        "'nuts': NUTS chains from the optimum; 'modes': "
        "independence Metropolis-Hastings chains from a Student-t mixture fitted to every mode by "
        "tempered importance sampling from the prior, the fit's optima seeded "
        "(axojax.inverse.ModeMixture): for up to about three free parameters with several modes, "
        "cliffs where the dominant eigenmode changes (the report names the switch lines met) or "
        "a long curved ridge; no gradients; 'smc': adaptive "
        "tempered sequential Monte Carlo from the prior (axojax.inverse.SMC), --chains independent "
        "runs of DRAWS particles each, for posteriors with several modes (as many targets as free "
        "parameters) or cliffs where the dominant eigenmode changes; no gradients, several times "
        "more evaluations per effective draw than NUTS on one smooth mode (docs/fitting.md)",
    )


MODES_HINT_MAX = MODES_MAX_FREE
"""Free parameters up to which a NUTS run that warns suggests ``--sampler modes``."""


def transport_of(args: argparse.Namespace, names) -> ProfileTransport | str | None:
    """``--along`` as the transport over the free parameters ``names``: None with
    ``--along none``, :data:`AUTO` without the flag; a one-line error when it names none
    of them or there are fewer than two."""
    if args.along is None:
        return AUTO
    if args.along == "none":
        return None
    try:
        transport = ProfileTransport(args.along)
        transport.index(names)
    except ValueError as err:
        raise common.CLIError(f"--along: {str(err).split(': ', 1)[-1]}") from None
    return transport


def sampler_of(args: argparse.Namespace, problem) -> tuple[str, str]:
    """``--sampler`` for ``problem``: the sampler's name ("nuts", "smc" or "modes") and why
    (the report's ``sampler_reason``). :data:`AUTO`: NUTS when ``--along`` or ``--warmup``
    (NUTS's settings) is given, else :func:`axojax.inverse.choose_sampler`'s choice."""
    if args.sampler != AUTO:
        return args.sampler, f"--sampler {args.sampler}: given"
    given = [f for f, v in (("--along", args.along), ("--warmup", args.warmup)) if v is not None]
    if given:
        return "nuts", f"--sampler {AUTO}: {' and '.join(given)} given (NUTS's settings)"
    sampler, why = choose_sampler(problem)
    return ("modes" if isinstance(sampler, ModeMixture) else "nuts"), f"--sampler {AUTO}: {why}"


def sample(
    args: argparse.Namespace,
    problem,
    result,
    progress: bool,
    transport: ProfileTransport | str | None,
):
    """The posterior of ``problem`` from the fit ``result``'s optimum (``--posterior``) by
    the sampler :func:`sampler_of` picks, and why; NUTS along ``transport``
    (:func:`transport_of`; :data:`AUTO`: what :func:`axojax.inverse.suggest_transport`
    picks from the fit). Its warnings (R-hat, ESS, divergences) one line each on stderr."""
    name, why = sampler_of(args, problem)
    if name != "nuts":
        return _sample_gradient_free(name, args, problem, result, progress), why
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            post = posterior(
                problem,
                draws=args.posterior,
                chains=args.chains,
                warmup=args.warmup,
                init=result,
                progress=progress,
                cache=_warm_cache_dir(),
                on_laplace=None if args.json else _print_laplace,
                transport=transport,
            )
    except ValueError as err:
        raise common.CLIError(f"--posterior: {err}") from None
    for w in caught:  # R-hat, ESS and divergence warnings: one line each on stderr
        print(f"axojax: fit: posterior: {w.message}", file=sys.stderr)
    if (caught or post.divergences) and len(post.names) <= MODES_HINT_MAX:
        print(
            "axojax: fit: posterior: NUTS's draws are not to be trusted here (above); with up to three "
            "free parameters --sampler modes samples without gradients, finds every mode and crosses "
            "cliffs (docs/fitting.md)",
            file=sys.stderr,
        )
    return post, why


def _sample_gradient_free(name: str, args: argparse.Namespace, problem, result, progress: bool):
    """``--sampler smc``: ``--chains`` SMC runs of ``--posterior`` particles each, from the
    prior; ``--sampler modes``: ``--chains`` chains of ``--posterior`` draws from a mixture
    fitted to every mode, the fit ``result``'s optima seeded. The warnings one line each on
    stderr."""
    sampler, init = (SMC(), None) if name == "smc" else (ModeMixture(), result)
    try:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            post = posterior(
                problem,
                draws=args.posterior,
                chains=args.chains,
                sampler=sampler,
                init=init,
                progress=progress,
            )
    except ValueError as err:
        raise common.CLIError(f"--posterior: {err}") from None
    for w in caught:
        print(f"axojax: fit: posterior: {w.message}", file=sys.stderr)
    return post


def _warm_cache_dir():
    """Where ``--posterior`` keeps its start-up (:mod:`axojax.inverse.sampling._warm_cache`):
    ``posterior/`` in the compilation cache's directory when that cache is on (the
    ``axojax`` command: :mod:`axojax.cache`), else nowhere."""
    directory = compilation_cache_dir()
    return None if directory is None else directory / WARM_SUBDIR


def _print_laplace(laplace) -> None:
    """The fast answer, on stdout before the warm-up starts (text output only)."""
    print("\n".join(render_laplace(laplace.to_json())), flush=True)
