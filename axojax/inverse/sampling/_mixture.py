"""The proposal of :class:`ModeMixture`: a mixture of multivariate Student-t components
in the sampled coordinate z, plus a defensive share from the prior box (:class:`TMixture`,
jax: draws and log density inside the compiled chains), and its weighted EM fit
(:func:`fit_mixture`, numpy: a few hundred to a few thousand points in k <= a few
dimensions, outside any compiled program).

Why Student-t: an independence Metropolis-Hastings chain is uniformly ergodic when the
proposal's tails are at least as heavy as the target's (Mengersen and Tweedie 1996); a
normal fitted to a curved ridge is lighter-tailed than the ridge. Why a defensive share:
the proposal then covers the whole prior box, so no region of positive posterior density
has zero proposal density (Hesterberg 1995), and the chains stay exact whatever the fit
missed (they only mix more slowly there).
"""

from __future__ import annotations

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.scipy.special import gammaln
from jaxtyping import Array, Float, PRNGKeyArray

RIDGE = 1e-8
"""Added to a component's covariance diagonal, times the mean of its diagonal (k >= 1):
a component fitted to nearly collinear points stays proper."""
PRIOR_STRENGTH = 4.0
"""EM shrinks a component's covariance towards its previous one with this many
pseudo-points (times k + 1): a component that a handful of heavy points would collapse
keeps a usable width."""
MIN_SHARE = 1e-3
"""A component whose weight falls below this is removed by :func:`fit_mixture`."""


class TMixture(eqx.Module):
    """A mixture of K multivariate Student-t densities in z (R^k), with a defensive share
    ``defensive`` of the uniform density in u between ``lower`` and ``upper``, pushed to
    z by ``to_z`` (its density there is ``|du/dz|`` over the box's volume).

    Attributes:
        log_weights: (K,) log weights of the t components (normalised among themselves).
        mean: (K, k) their centres in z.
        chol: (K, k, k) lower Cholesky factors of their scale matrices in z.
        df: degrees of freedom (the same for every component).
        defensive: share of the uniform-in-u component, in [0, 1).
        lower, upper: (k,) the prior box in u.
    """

    log_weights: Float[Array, " K"]
    mean: Float[Array, "K k"]
    chol: Float[Array, "K k k"]
    df: float = eqx.field(static=True)
    defensive: float = eqx.field(static=True)
    lower: Float[Array, " k"]
    upper: Float[Array, " k"]

    def _log_t(self, z: Float[Array, " k"]) -> Float[Array, " K"]:
        k = z.shape[-1]
        nu = self.df
        d = jax.vmap(lambda L, m: jax.scipy.linalg.solve_triangular(L, z - m, lower=True))(
            self.chol, self.mean
        )
        maha = jnp.sum(d**2, axis=-1)
        log_det = jnp.sum(jnp.log(jnp.abs(jnp.diagonal(self.chol, axis1=-2, axis2=-1))), axis=-1)
        const = gammaln((nu + k) / 2) - gammaln(nu / 2) - 0.5 * k * jnp.log(nu * jnp.pi)
        return const - log_det - 0.5 * (nu + k) * jnp.log1p(maha / nu)

    def log_prob(self, z: Float[Array, " k"], log_ref: Float[Array, ""]) -> Float[Array, ""]:
        """Log density at z; ``log_ref`` = log|du/dz| at z (the defensive part's density
        in z, before dividing by the box's volume)."""
        log_t = jax.nn.logsumexp(self.log_weights + self._log_t(z))
        if self.defensive <= 0.0:
            return log_t
        log_box = jnp.sum(jnp.log(self.upper - self.lower))
        return jnp.logaddexp(
            math.log1p(-self.defensive) + log_t, math.log(self.defensive) + log_ref - log_box
        )

    def sample(self, key: PRNGKeyArray, to_z) -> Float[Array, " k"]:
        """One draw in z (``to_z``: the problem's map from u to z)."""
        k = self.mean.shape[-1]
        k_pick, k_norm, k_chi, k_def, k_box = jax.random.split(key, 5)
        j = jax.random.categorical(k_pick, self.log_weights)
        g = jax.random.normal(k_norm, (k,))
        s = jax.random.gamma(k_chi, self.df / 2) * 2 / self.df  # chi^2_df / df
        t = self.mean[j] + self.chol[j] @ g / jnp.sqrt(s)
        if self.defensive <= 0.0:
            return t
        box = to_z(jax.random.uniform(k_box, (k,), minval=self.lower, maxval=self.upper))
        return jnp.where(jax.random.uniform(k_def) < self.defensive, box, t)

    def responsibilities(self, z: Float[Array, "n k"]) -> Float[Array, "n K"]:
        """Each point's posterior share among the t components (the defensive part left
        out): which component, hence which mode, a draw belongs to."""
        log_t = jax.vmap(self._log_t)(z) + self.log_weights
        return jax.nn.softmax(log_t, axis=-1)


def gaussian_logpdf(z: np.ndarray, mean: np.ndarray, cov: np.ndarray) -> np.ndarray:
    """(n, K) log normal densities of the points z (n, k) under K components."""
    n, k = z.shape
    out = np.empty((n, len(mean)))
    for j, (m, c) in enumerate(zip(mean, cov)):
        L = np.linalg.cholesky(c)
        d = np.linalg.solve(L, (z - m).T)
        out[:, j] = (
            -0.5 * np.sum(d**2, axis=0)
            - np.sum(np.log(np.diag(L)))
            - 0.5 * k * math.log(2 * math.pi)
        )
    return out


def _proper(cov: np.ndarray) -> np.ndarray:
    """cov symmetrised, its diagonal raised by RIDGE times its mean (a proper matrix)."""
    k = cov.shape[-1]
    cov = 0.5 * (cov + cov.T)
    scale = max(float(np.trace(cov)) / k, 1e-300)
    return cov + RIDGE * scale * np.eye(k)


def fit_mixture(
    z: Float[np.ndarray, "n k"],
    weights: Float[np.ndarray, " n"],
    mean: Float[np.ndarray, "K k"],
    cov: Float[np.ndarray, "K k k"],
    share: Float[np.ndarray, " K"],
    iterations: int = 30,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Weighted EM for a normal mixture, from (``mean``, ``cov``, ``share``): the points
    ``z`` with importance ``weights`` (any scale, >= 0). Each covariance is shrunk towards
    its start with :data:`PRIOR_STRENGTH` x (k + 1) pseudo-points, and components whose
    share falls below :data:`MIN_SHARE` are removed (at least one is kept). Returns
    (mean (K', k), cov (K', k, k), share (K',)), the shares summing to 1."""
    n, k = z.shape
    w = np.asarray(weights, dtype=float)
    w = w / np.sum(w)
    mean, cov, share = (np.array(a, dtype=float) for a in (mean, cov, share))
    start_cov = cov.copy()
    n_eff = 1.0 / np.sum(w**2)
    prior_n = PRIOR_STRENGTH * (k + 1)
    for _ in range(iterations):
        log_r = gaussian_logpdf(z, mean, cov) + np.log(np.maximum(share, 1e-300))
        log_r -= np.max(log_r, axis=1, keepdims=True)
        r = np.exp(log_r)
        r /= np.sum(r, axis=1, keepdims=True)
        wr = w[:, None] * r  # (n, K)
        mass = np.sum(wr, axis=0)
        keep = mass >= MIN_SHARE * np.sum(mass)
        if not np.any(keep):
            keep[np.argmax(mass)] = True
        wr, mass, start_cov = wr[:, keep], mass[keep], start_cov[keep]
        mean = (wr.T @ z) / mass[:, None]
        new_cov = []
        for j in range(len(mass)):
            d = z - mean[j]
            emp = (wr[:, j, None] * d).T @ d / mass[j]
            m_eff = n_eff * mass[j]
            new_cov.append(_proper((m_eff * emp + prior_n * start_cov[j]) / (m_eff + prior_n)))
        cov = np.stack(new_cov)
        share = mass / np.sum(mass)
    return mean, cov, share


def split_to(
    mean: Float[np.ndarray, "K k"],
    cov: Float[np.ndarray, "K k k"],
    share: Float[np.ndarray, " K"],
    count: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Split components until there are ``count``: each time the one of largest share x
    sd along its principal axis, into two at mean +- sd/2 along that axis, each with half
    the share and a quarter less variance along it (the pair keeps its mean and
    covariance). EM merges or drops components as the density narrows; splitting them
    back along their longest axis is what lets a few components tile a long curved
    ridge."""
    mean, cov, share = (np.array(a, dtype=float) for a in (mean, cov, share))
    while len(share) < count:
        lam, vec = np.linalg.eigh(cov)
        sd = np.sqrt(np.maximum(lam[:, -1], 0.0))
        j = int(np.argmax(share * sd))
        step = 0.5 * sd[j] * vec[j][:, -1]
        child = cov[j] - np.outer(step, step)
        mean = np.concatenate([np.delete(mean, j, 0), [mean[j] - step, mean[j] + step]])
        cov = np.concatenate([np.delete(cov, j, 0), [child, child]])
        share = np.concatenate([np.delete(share, j), [share[j] / 2, share[j] / 2]])
    return mean, cov, share


def mixture_of(
    mean: np.ndarray, cov: np.ndarray, share: np.ndarray, df: float, defensive: float, lower, upper
) -> TMixture:
    """The :class:`TMixture` with t components of scale matrices ``cov`` (the fitted
    normals' covariances: the t's spread is wider, ``df / (df - 2)`` of it)."""
    chol = np.stack([np.linalg.cholesky(_proper(c)) for c in cov])
    return TMixture(
        log_weights=jnp.asarray(np.log(share / np.sum(share))),
        mean=jnp.asarray(mean),
        chol=jnp.asarray(chol),
        df=float(df),
        defensive=float(defensive),
        lower=jnp.asarray(np.asarray(lower, dtype=float)),
        upper=jnp.asarray(np.asarray(upper, dtype=float)),
    )
