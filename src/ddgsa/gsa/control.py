"""Saltelli's estimators with a Gaussian-process control variate: the same answer for a fraction of the runs.

Saltelli's design (matrices ``A``, ``B`` and ``AB_i``, ``A`` with column ``i`` from ``B``) estimates
every Sobol variance as the mean of a per-row quantity ``q`` -- Saltelli (2010)'s first-order
``f_B (f_ABi - f_A)``, Jansen's total ``(f_A - f_ABi)^2 / 2`` and the variance itself. For any
function ``g`` of the inputs,

.. math:: E[q(f)] = E[q(g)] + E[q(f) - q(g)],

and when ``g`` is a surrogate of ``f`` whose Sobol variances are known *exactly*, only the second
mean needs the model runs -- and ``q(f) - q(g)`` varies much less than ``q(f)`` when ``g`` is close to
``f`` (a control variate with coefficient one; Qian, Peherstorfer et al. 2018, *SIAM/ASA JUQ* 6 use
the same idea across model fidelities). The estimate is unbiased whatever ``g`` is, provided ``g``
was fitted without the Saltelli rows: a poor surrogate costs precision, never correctness.

The surrogate is the posterior mean of a Gaussian process with a squared-exponential kernel with
one length per input, fitted (scikit-learn) on points drawn *before* the Saltelli rows, in the unit
cube ``u = F(x)`` of the inputs' CDFs, where every input is uniform. Its kernel is a product over
the inputs, so its Sobol variances are closed forms (Oakley & O'Hagan 2004, *J. R. Stat. Soc. B*
66): with ``m(u) = sum_j a_j prod_l k_l(u_l, c_jl)``,
``I_l(c) = int_0^1 k_l(u, c) du`` and ``J_l(c, c') = int_0^1 k_l(u, c) k_l(u, c') du`` (error
functions), ``E[m] = a . prod_l I_l``, ``E[m^2] = a^T (prod_l J_l) a``,
``E[E[m | u_i]^2] = (a I_-i)^T J_i (a I_-i)`` and
``E[E[m | u_-i]^2] = (a I_i)^T (prod_{l != i} J_l) (a I_i)``.

A response near a resonance, ``A ~ 1 / |k - m w^2 + i c w|``, is a sharp peak in the parameters
that no smooth process follows; its inverse square is a smooth quadratic. So for an output positive at
every training point whose own process is not within :data:`GOOD_LOO`, :func:`fit_control` also fits
processes of ``log y``, ``1 / y`` and ``1 / y^2`` and maps them back (:class:`TransformedSurrogate`),
keeping whichever has the smallest leave-one-out error in the output's units. A mapped-back process
has no closed-form variances: they are estimated by randomised quasi-Monte Carlo on the surrogate
(cheap: no model runs), and their standard errors join the error bound.

Error bound: the bootstrap over the design's rows and twice the difference between the first half
of the rows and all of them, the rule of SALib's ``saltelli`` (:mod:`ddgsa.gsa.salib`, calibrated by
``ddgsa bench trust``); the part of a process of the output itself is exact and adds nothing. With ``g = 0`` the estimates
are SALib's own.

Cost: the error of a row with total index ``ST`` falls from about ``SALTELLI_K sqrt(ST / N)`` to about
``SALTELLI_K sqrt(min(ST, 2 e^2) / N)``, ``e`` the surrogate's relative leave-one-out error
(:func:`controlled_level`): a surrogate within 10 % needs about ``ST / 0.02`` times fewer base points.
Heavy-tailed residuals (a peak the process still misses) keep it above that.
"""

from __future__ import annotations

import math
import os
from collections.abc import Callable, Iterable, Iterator, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field, replace
from functools import cached_property, lru_cache
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.special import erf

MAX_TRAIN = 1000
"""Most points the process is conditioned on (its solve is cubic, its exact variances quadratic in them)."""
FIT_POINTS = 256
"""Most points the kernel's hyperparameters are fitted on (evenly spread over the training points)."""
CHUNK = 1 << 18
"""Kernel entries a surrogate evaluates at once (2 MiB: the in-place passes stay in the cache; 3x faster
than one 32 MiB block with temporaries)."""
THREADS = max(1, min(4, len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1))
"""Threads a surrogate's evaluation of many points runs its chunks on (numpy releases the GIL in the products
and the exponential; each chunk's values are the same on any thread). The study's main process samples its
controls' moments between two stages of model runs, while the workers are idle: on the rig's 27-input
escalations that sampling was 76 % of the analysis (``py-spy``, session 20), on one core."""
MIN_LENGTH = 0.01
"""Shortest kernel length in the unit cube."""
NUGGETS = (1e-6, 1e-4, 1e-3, 1e-2, 1e-1)
"""Noise variances (relative to the values' variance) tried in turn, each at least the fitted one:
a larger one bounds the weights (about ``1 / nugget``), and so the round-off of the exact variances'
quadratic forms, at the price of a smoother fit (a weaker control, never a biased estimate)."""
MAX_LOO = 0.5
"""Largest relative leave-one-out error of a process used as a control: beyond it the residual's
variance could exceed the output's (a correlation below about 0.7), and the control would hurt."""
MAX_ROUNDOFF = 1e-4
"""Largest round-off allowed in the exact variances, relative to the variance: ``eps |a|^T J |a|``
(the scale of the quadratic form's terms times the machine epsilon)."""


@dataclass(frozen=True)
class GaussianSurrogate:
    """Posterior mean of a Gaussian process on the unit cube (see the module), in the units it was fitted in.

    ``m(u) = offset + sum_j weights_j exp(-sum_l (u_l - centres_jl)^2 / (2 length_l^2))``; ``variance``,
    ``first`` and ``total`` are its exact variance and first-order and total variances (d,) under
    uniform inputs.
    """

    centres: NDArray[np.float64]      # (n, d) training points in the unit cube
    weights: NDArray[np.float64]      # (n,)
    length: NDArray[np.float64]       # (d,) kernel lengths in the unit cube
    offset: float                     # the training values' mean
    loo: float                        # leave-one-out RMS error over the training values' standard deviation
    variance: float
    first: NDArray[np.float64]
    total: NDArray[np.float64]
    loo_values: NDArray[np.float64]   # (n,) leave-one-out predictions at the training points
    regressor: Any = field(default=None, compare=False, repr=False)   # (sklearn regressor, values' sd): the posterior

    @classmethod
    def fit(cls, u: NDArray[np.float64], y: NDArray[np.float64],
            max_loo: float = MAX_LOO, exact: bool = True,
            drawn: NDArray[np.bool_] | None = None) -> "GaussianSurrogate | None":
        """Fit to finite values ``y`` (n,) at unit-cube points ``u`` (n, d): hyperparameters by maximum
        likelihood on at most :data:`FIT_POINTS` of them, the weights on at most :data:`MAX_TRAIN`,
        with the first of :data:`NUGGETS` whose exact variances round off by less than
        :data:`MAX_ROUNDOFF`; None when none does, when its leave-one-out error exceeds ``max_loo``
        or when the values are constant. ``exact=False``: a process whose variances are not needed
        (that of a :class:`TransformedSurrogate`; its variances are left at zero, never read), keeping
        its fitted regressor for the posterior. ``drawn`` (n,): the points drawn from the input
        distribution (default all); the leave-one-out error is taken over those of the training
        points, so that it estimates the error under the input distribution when others (focus
        points) are among them."""
        from scipy.linalg import cho_solve
        from sklearn.gaussian_process import GaussianProcessRegressor
        from sklearn.gaussian_process.kernels import RBF, ConstantKernel, WhiteKernel

        u = np.asarray(u, dtype=float)
        y = np.asarray(y, dtype=float)
        n, d = u.shape
        train = _spread(n, MAX_TRAIN)
        u, y = u[train], y[train]
        mine = _drawn_among(train, drawn)
        offset, sd = float(y.mean()), float(y.std())
        if not sd > 0:
            return None
        z = (y - offset) / sd
        kernel = (ConstantKernel(1.0, (1e-3, 1e3)) * RBF(np.full(d, 0.3), (MIN_LENGTH, 1e2))
                  + WhiteKernel(1e-3, (NUGGETS[0], 1.0)))
        sub = _spread(len(u), FIT_POINTS)
        theta = _max_likelihood(kernel.theta, kernel.bounds, u[sub], z[sub])
        # log-hyperparameters to 0.01 (1 %): the optimiser's end point moves with round-off in the
        # values (an output x 1e12 is standardised to the same numbers within 1e-16), the rounded one
        # does not -- the same process, indices and flags for the output in any unit
        hyper = kernel.clone_with_theta(np.round(theta, 2))
        s2 = float(hyper.k1.k1.constant_value)
        length = np.atleast_1d(np.asarray(hyper.k1.k2.length_scale, dtype=float)) * np.ones(d)
        fitted = float(hyper.k2.noise_level)
        for nugget in NUGGETS:
            noise = max(fitted, nugget)
            gp = GaussianProcessRegressor(hyper.k1 + WhiteKernel(noise, "fixed"), optimizer=None).fit(u, z)
            a = s2 * sd * gp.alpha_
            variances = _exact_variances(u, a, length) if exact else (0.0, np.zeros(d), np.zeros(d))
            if variances is not None:
                kinv_diag = cho_solve((gp.L_, True), np.eye(len(u))).diagonal()
                gap = gp.alpha_ / kinv_diag                               # z minus its leave-one-out prediction
                spread = float(z[mine].std())
                loo = float(np.sqrt(np.mean(gap[mine] ** 2)) / spread) if spread > 0 else np.inf
                if loo > max_loo:
                    return None
                return cls(u, a, length, offset, loo, *variances, y - sd * gap, None if exact else (gp, sd))
        return None

    def affine(self, shift: float, scale: float) -> "GaussianSurrogate":
        """The surrogate of ``(y - shift) / scale`` (same process, values mapped)."""
        return GaussianSurrogate(self.centres, self.weights / scale, self.length, (self.offset - shift) / scale,
                                 self.loo, self.variance / scale ** 2, self.first / scale ** 2,
                                 self.total / scale ** 2, (self.loo_values - shift) / scale)

    def __call__(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """The surrogate at unit-cube points ``u`` (m, d), in chunks (bounded memory), many chunks on
        :data:`THREADS` threads."""
        u = np.atleast_2d(np.asarray(u, dtype=float))
        # -|v - c|^2 / 2 = v.c - |v|^2 / 2 - |c|^2 / 2, one product: [v, -|v|^2 / 2, 1] . [c, 1, -|c|^2 / 2],
        # about the cube's centre (the squares, whose round-off the sum keeps, 4x smaller than about a corner)
        c = (self.centres - 0.5) / self.length
        centres = np.column_stack([c, np.ones(len(c)), -0.5 * (c ** 2).sum(axis=1)]).T
        out = np.empty(len(u))
        step = max(1, CHUNK // max(len(c), 1))

        def chunk(k: int) -> None:
            v = (u[k:k + step] - 0.5) / self.length
            t = np.column_stack([v, -0.5 * (v ** 2).sum(axis=1), np.ones(len(v))]) @ centres
            np.exp(t, out=t)
            out[k:k + step] = self.offset + t @ self.weights

        _chunked(chunk, range(0, len(u), step))
        return out

    def variances(self) -> tuple[float, NDArray[np.float64], NDArray[np.float64]]:
        """Exact variance under uniform inputs, and the first-order and total variances per input."""
        return self.variance, self.first, self.total

    @property
    def fitted_to(self) -> str:
        """What the process was fitted to: the output itself."""
        return "y"

    def without_posterior(self) -> "GaussianSurrogate":
        """Itself (its variances are closed forms; it keeps no regressor)."""
        return self

    def variance_errors(self) -> tuple[float, NDArray[np.float64], NDArray[np.float64]]:
        """Standard errors of :meth:`variances`: zero (closed forms)."""
        return 0.0, np.zeros_like(self.first), np.zeros_like(self.total)


POWERS = (0.0, -1.0, -2.0)
"""Power transforms tried besides the identity for an output positive at every training point:
``log y`` and ``y^p``. A response near a resonance, ``A ~ 1 / |k - m w^2 + i c w|``, has a sharp
peak in the parameters that no smooth process follows, while ``A^-2`` is a smooth quadratic."""
GOOD_LOO = 0.1
"""A process of the output itself within this leave-one-out error is kept without trying the powers."""
REPLICATES = 8
"""Independent scrambles of the Monte Carlo estimate of a transformed surrogate's variances (their
spread gives its standard error)."""
SURROGATE_RUNS = 1 << 21
"""About how many surrogate evaluations estimate a transformed surrogate's variances."""
MAX_SURROGATE_RUNS = 1 << 23
"""The most :func:`refine_moments` spends on one surrogate's variances: 4 times :data:`SURROGATE_RUNS` (at Monte
Carlo's rate its sampled error halves; measured: 3-17 times smaller at 16 times the runs on an analytic
resonance, 1.2-2.1 times at 4 times on the rig's steady scene). A process of ~1 000 centres takes about 8 s of CPU
per 2^21 evaluations: the rig's seven steady outputs' controls with two shared features, 27 inputs, cost about
5 min more, once per escalation (its controls are frozen at its first Saltelli stage and keep their moments)."""
CHUNK_VALUES = 1 << 21
"""Coordinates of surrogate points made at once (16 MiB) when its variances are sampled."""


@lru_cache(maxsize=1)
def _blas() -> Any:
    """threadpoolctl's view of the loaded BLAS libraries, found once (the search costs ~50 ms)."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController()


def _chunked(work: Callable[[int], None], starts: range) -> None:
    """``work(k)`` for every chunk start ``k``: in turn for a few chunks, else on :data:`THREADS` threads with
    BLAS on one thread each (no more threads than cores)."""
    if THREADS == 1 or len(starts) < 2 * THREADS:
        for k in starts:
            work(k)
        return
    with _blas().limit(limits=1, user_api="blas"), ThreadPoolExecutor(THREADS) as pool:   # (no BLAS: no limit)
        for _ in pool.map(work, starts):            # results in place; re-raises a chunk's error
            pass


@dataclass(frozen=True)
class _PowerProcess:
    """A Gaussian process ``m`` of ``z = (y / ref)^power`` (``log`` for power 0), mapped back as
    ``ref h(clip(m, low, high))``, with its Sobol variances estimated once, when first asked for."""

    process: GaussianSurrogate
    power: float
    ref: float
    low: float
    high: float
    seed: int

    def __call__(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        return self.ref * _untransform(np.clip(self.process(u), self.low, self.high), self.power)

    def error(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """The mapped-back process's linearised posterior standard deviation at ``u`` (m, d), in the
        output's units: ``ref |h'(m(u))|`` times the process's posterior standard deviation."""
        gp, sd = self.process.regressor
        _, std = gp.predict(u, return_std=True)
        z = np.clip(self.process(u), self.low, self.high)
        slope = np.exp(z) if self.power == 0 else np.abs(z ** (1.0 / self.power - 1.0) / self.power)
        return self.ref * slope * sd * std

    @cached_property
    def moments(self) -> tuple[tuple[float, NDArray[np.float64], NDArray[np.float64]],
                               tuple[float, NDArray[np.float64], NDArray[np.float64]]]:
        """Variance, first-order and total variances under uniform inputs, and their standard errors
        (:func:`_sampled_variances`)."""
        return _sampled_variances([self], self.process.centres.shape[1], self.seed)[0]


@dataclass(frozen=True)
class TransformedSurrogate:
    """``g(u) = (h(m(u)) - shift) / scale``: a Gaussian process ``m`` of a power transform of the output,
    mapped back (``h``), so that a resonance's peak is followed (see :data:`POWERS`).

    Its Sobol variances have no closed form: they are randomised quasi-Monte Carlo estimates
    (:data:`REPLICATES` scrambled Sobol' designs of Saltelli's form, about :data:`SURROGATE_RUNS`
    evaluations of the surrogate, made when first asked for), with standard errors that the controlled
    estimator adds to its error bound. The control stays unbiased: the estimate's error is the model
    rows' residual and this Monte Carlo error, both estimated.
    """

    core: _PowerProcess
    loo: float                        # leave-one-out RMS error over the values' standard deviation, output units
    shift: float = 0.0
    scale: float = 1.0

    @property
    def power(self) -> float:
        """The transform's power (0: the logarithm)."""
        return self.core.power

    @property
    def fitted_to(self) -> str:
        """What the process was fitted to: ``log y`` or ``y^p``."""
        return "log y" if self.power == 0 else f"y^{self.power:g}"

    def __call__(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """The surrogate at unit-cube points ``u`` (m, d)."""
        return (self.core(u) - self.shift) / self.scale

    def affine(self, shift: float, scale: float) -> "TransformedSurrogate":
        """The surrogate of ``(y - shift) / scale``."""
        return TransformedSurrogate(self.core, self.loo, self.shift + shift * self.scale, self.scale * scale)

    def without_posterior(self) -> "TransformedSurrogate":
        """The same surrogate without the process's regressor (its n x n factor): once the pilot is
        chosen, :meth:`error` is no longer needed."""
        core = replace(self.core, process=replace(self.core.process, regressor=None))
        return TransformedSurrogate(core, self.loo, self.shift, self.scale)

    def variances(self) -> tuple[float, NDArray[np.float64], NDArray[np.float64]]:
        """Variance under uniform inputs, and first-order and total variances per input (estimates)."""
        var, first, total = self.core.moments[0]
        c2 = self.scale ** 2
        return var / c2, first / c2, total / c2

    def error(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """Where the surrogate is least certain: its linearised posterior standard deviation at ``u``
        (m, d), in the units it maps to."""
        return self.core.error(u) / abs(self.scale)

    def variance_errors(self) -> tuple[float, NDArray[np.float64], NDArray[np.float64]]:
        """Standard errors of :meth:`variances` (the spread of the scrambles)."""
        var, first, total = self.core.moments[1]
        c2 = self.scale ** 2
        return var / c2, first / c2, total / c2


Control = GaussianSurrogate | TransformedSurrogate
"""A control variate of the inputs alone: a process of the output or of a power of it."""


def fit_control(u: NDArray[np.float64], y: NDArray[np.float64], seed: int = 0,
                drawn: NDArray[np.bool_] | None = None, features: NDArray[np.float64] | None = None,
                cache: dict[Any, Any] | None = None) -> "Control | FeatureSurrogate | None":
    """The control variate of ``y`` (n,) at unit-cube points ``u`` (n, d): the Gaussian process of the
    values (:meth:`GaussianSurrogate.fit`) or, for an output positive everywhere whose own process is
    not within :data:`GOOD_LOO`, of one of its :data:`POWERS` mapped back, whichever has the smallest
    leave-one-out error in the output's units; None when none is within :data:`MAX_LOO`. ``drawn``
    (n,): the points drawn from the input distribution, over which the leave-one-out errors are taken
    (default all; see :meth:`GaussianSurrogate.fit`). ``features`` (n, k): the model's control features
    at the same points (:meth:`ddgsa.models.base.Model.control_features`, computed in the same runs):
    the :class:`FeatureSurrogate` on them is fitted too, and whichever of the two has the smaller
    leave-one-out error is returned -- never a worse control than without features. ``cache``: see
    :meth:`FeatureSurrogate.fit` (the outputs of one pool share their features' processes)."""
    u = np.asarray(u, dtype=float)
    y = np.asarray(y, dtype=float)
    plain = _fit_plain(u, y, seed, drawn)
    if features is None or np.size(features) == 0:
        return plain
    with_features = FeatureSurrogate.fit(u, y, np.asarray(features, dtype=float).reshape(len(y), -1), seed, drawn,
                                         cache)
    if with_features is None or (plain is not None and plain.loo <= with_features.loo):
        return plain
    return with_features


def _fit_plain(u: NDArray[np.float64], y: NDArray[np.float64], seed: int,
               drawn: NDArray[np.bool_] | None, max_loo: float = MAX_LOO, exact: bool = True) -> Control | None:
    """:func:`fit_control` without features; ``exact=False``: a process of the output itself is fitted
    without its closed-form variances, keeping its regressor (that of a :class:`FeatureSurrogate`,
    whose variances are sampled)."""
    best: Control | None = GaussianSurrogate.fit(u, y, drawn=drawn, max_loo=max_loo, exact=exact)
    if not np.all(y > 0) or (best is not None and best.loo <= GOOD_LOO):
        return best
    train = _spread(len(y), MAX_TRAIN)
    mine = _drawn_among(train, drawn)
    yt = y[train]
    sd = float(yt[mine].std())
    ref = float(np.median(yt[mine]))              # the output's scale: the same transform in any unit
    candidates = []
    for power in POWERS:
        z_all = _transform(y / ref, power)
        process = GaussianSurrogate.fit(u, z_all, max_loo=np.inf, exact=False)
        if process is None:
            continue
        z = z_all[train]
        low, high = _clip_range(z, power)
        with np.errstate(all="ignore"):
            back = ref * _untransform(np.clip(process.loo_values, low, high), power)
            loo = float(np.sqrt(np.mean((yt - back)[mine] ** 2)) / sd) if sd > 0 else np.inf
        if np.isfinite(loo):
            candidates.append((loo, power, process, low, high))
    if not candidates:
        return best
    loo, power, process, low, high = min(candidates, key=lambda c: c[0])
    if loo > max_loo or (best is not None and best.loo <= loo):
        return best
    return TransformedSurrogate(_PowerProcess(process, power, ref, low, high, seed), loo)


def _loo_predictions(g: Control) -> NDArray[np.float64]:
    """Leave-one-out predictions of a control at its training points (those :func:`_spread` kept), in
    the output's units."""
    if isinstance(g, GaussianSurrogate):
        return g.loo_values
    core = g.core
    with np.errstate(all="ignore"):
        back = core.ref * _untransform(np.clip(core.process.loo_values, core.low, core.high), core.power)
    return (back - g.shift) / g.scale


@dataclass(frozen=True)
class _FeatureProcess:
    """A control ``c`` over (inputs, features scaled to [0, 1]) composed with the features' processes over
    the inputs: ``u -> c(u, phi_hat(u))``, with its Sobol variances sampled once, when first asked for."""

    inner: Control
    features: tuple[GaussianSurrogate, ...]
    seed: int

    def augmented(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """``(u, phi_hat(u))`` (m, d + k) at unit-cube points ``u`` (m, d)."""
        u = np.atleast_2d(np.asarray(u, dtype=float))
        return np.column_stack([u] + [p(u) for p in self.features])

    def __call__(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        return self.inner(self.augmented(u))

    @cached_property
    def moments(self) -> tuple[tuple[float, NDArray[np.float64], NDArray[np.float64]],
                               tuple[float, NDArray[np.float64], NDArray[np.float64]]]:
        """Variance, first-order and total variances under uniform inputs, and their standard errors
        (:func:`_sampled_variances`)."""
        return _sampled_variances([self.inner], self.features[0].centres.shape[1], self.seed, self.augmented)[0]


@dataclass(frozen=True)
class FeatureSurrogate:
    """``g(u) = (c(u, phi_hat(u)) - shift) / scale``: a control variate ``c`` (:func:`_fit_plain`: a process
    of the output or of a power of it) over the inputs *and* the model's control features, with the
    features replaced by Gaussian processes of them over the inputs (``phi_hat``), so that ``g`` stays a
    function of the inputs alone, evaluable at every Saltelli row without a model run.

    A model's feature (the rig's lowest lateral natural frequencies against the 1x order) is smooth in
    the parameters where its output is not: a resonance's peak lies on a curved ridge of the inputs and
    along one coordinate of the feature, so a process over (inputs, feature) follows what one over the
    inputs alone misses. Its Sobol variances have no closed form: they are sampled on the surrogate as a
    :class:`TransformedSurrogate`'s (:func:`_sampled_variances`), and their standard errors join the bound.
    The estimate stays unbiased: ``g`` is fitted on pilot points only.

    ``loo``: the composite's relative leave-one-out error in the output's units, to first order in the
    features' errors -- the inner control's own leave-one-out residual at the true features, less its
    change when the features are their processes' leave-one-out predictions (the error ``phi_hat`` adds).
    """

    core: _FeatureProcess
    loo: float
    shift: float = 0.0
    scale: float = 1.0

    @classmethod
    def fit(cls, u: NDArray[np.float64], y: NDArray[np.float64], phi: NDArray[np.float64], seed: int = 0,
            drawn: NDArray[np.bool_] | None = None, cache: dict[Any, Any] | None = None) -> "FeatureSurrogate | None":
        """Fit to ``y`` (n,) at unit-cube points ``u`` (n, d) with features ``phi`` (n, k) (see the class);
        None where a feature is not finite everywhere or is constant, or where the composite's
        leave-one-out error exceeds :data:`MAX_LOO`. ``cache``: a dict kept across the outputs of one pool,
        holding the features' processes by their points and values (they do not depend on ``y``: an
        escalation's outputs share them, fitted once)."""
        if not np.all(np.isfinite(phi)):
            return None
        low, high = phi.min(axis=0), phi.max(axis=0)
        if not np.all(high > low):
            return None
        unit = (phi - low) / (high - low)
        key = (u.tobytes(), unit.tobytes(), u.shape)
        if cache is None or key not in cache:
            fitted = [GaussianSurrogate.fit(u, unit[:, j], max_loo=np.inf, exact=False)
                      for j in range(phi.shape[1])]
            found = None if any(p is None for p in fitted) else tuple(replace(p, regressor=None) for p in fitted)
            if cache is not None:
                cache[key] = found
        processes = found if cache is None else cache[key]
        if processes is None:
            return None
        inner = _fit_plain(np.column_stack([u, unit]), y, seed, drawn, max_loo=np.inf, exact=False)
        if inner is None:
            return None
        train = _spread(len(y), MAX_TRAIN)
        mine = _drawn_among(train, drawn)
        at_true = np.column_stack([u[train], unit[train]])
        at_loo = np.column_stack([u[train]] + [p.loo_values for p in processes])
        with np.errstate(all="ignore"):
            gap = y[train] - _loo_predictions(inner) - (inner(at_loo) - inner(at_true))
            sd = float(y[train][mine].std())
            loo = float(np.sqrt(np.mean(gap[mine] ** 2)) / sd) if sd > 0 else np.inf
        if not loo <= MAX_LOO:
            return None
        return cls(_FeatureProcess(inner, tuple(processes), seed), loo)

    @property
    def fitted_to(self) -> str:
        """What the process was fitted to: the inner control's values, over the inputs and the features."""
        return f"{self.core.inner.fitted_to} with features"

    def __call__(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """The surrogate at unit-cube points ``u`` (m, d)."""
        return (self.core(u) - self.shift) / self.scale

    def affine(self, shift: float, scale: float) -> "FeatureSurrogate":
        """The surrogate of ``(y - shift) / scale``."""
        return FeatureSurrogate(self.core, self.loo, self.shift + shift * self.scale, self.scale * scale)

    def without_posterior(self) -> "FeatureSurrogate":
        """The same surrogate without the inner process's regressor (its n x n factor)."""
        inner = self.core.inner
        inner = inner.without_posterior() if isinstance(inner, TransformedSurrogate) else replace(inner, regressor=None)
        return FeatureSurrogate(replace(self.core, inner=inner), self.loo, self.shift, self.scale)

    def error(self, u: NDArray[np.float64]) -> NDArray[np.float64]:
        """Where the surrogate is least certain: the inner process's linearised posterior standard
        deviation at ``(u, phi_hat(u))`` (m, d), in the units it maps to."""
        v = self.core.augmented(u)
        inner = self.core.inner
        if isinstance(inner, TransformedSurrogate):
            return inner.error(v) / abs(self.scale)
        gp, sd = inner.regressor
        return sd * gp.predict(v, return_std=True)[1] / abs(self.scale)

    def variances(self) -> tuple[float, NDArray[np.float64], NDArray[np.float64]]:
        """Variance under uniform inputs, and first-order and total variances per input (estimates)."""
        var, first, total = self.core.moments[0]
        c2 = self.scale ** 2
        return var / c2, first / c2, total / c2

    def variance_errors(self) -> tuple[float, NDArray[np.float64], NDArray[np.float64]]:
        """Standard errors of :meth:`variances` (the spread of the scrambles)."""
        var, first, total = self.core.moments[1]
        c2 = self.scale ** 2
        return var / c2, first / c2, total / c2


JITTER = 1e-10
"""Added to the kernel matrix's diagonal in the likelihood, as scikit-learn's regressor does (its ``alpha``)."""


def _max_likelihood(theta0: NDArray[np.float64], bounds: NDArray[np.float64], u: NDArray[np.float64],
                    z: NDArray[np.float64]) -> NDArray[np.float64]:
    """Log-hyperparameters ``log (s^2, length_1..d, noise)`` of the kernel ``s^2 RBF(length) + noise`` that
    maximise the marginal likelihood of ``z`` (n,) at ``u`` (n, d): scikit-learn's optimisation (L-BFGS-B
    from ``theta0`` within ``bounds``, its objective and the regressor's ``alpha`` jitter) with the gradient as
    matrix products (:func:`_neg_log_likelihood`) instead of its (n, n, d) kernel gradient. Usually the same end
    point after the rounding :meth:`GaussianSurrogate.fit` applies; where the likelihood is flat the optimiser may stop
    elsewhere at an equal likelihood (2 of 20 random problems: a log length 0.5 apart, likelihoods within 2e-4;
    ``tests/gsa/test_control.py``), a control as good, never a biased estimate. 5-7 times
    faster at d = 27 (the escalation of a 27-input study spent most of its time there)."""
    from scipy.optimize import minimize

    res = minimize(_neg_log_likelihood, theta0, args=(u, z), method="L-BFGS-B", jac=True, bounds=bounds)
    return np.asarray(res.x, dtype=float)


def _neg_log_likelihood(theta: NDArray[np.float64], u: NDArray[np.float64],
                        z: NDArray[np.float64]) -> tuple[float, NDArray[np.float64]]:
    """Minus the log marginal likelihood of ``z`` (n,) at ``u`` (n, d) under the kernel
    ``s^2 exp(-sum_l (u_l - u'_l)^2 / (2 length_l^2)) + noise`` and its gradient in
    ``theta = log (s^2, length_1..d, noise)``; ``(inf, 0)`` where the kernel matrix is not positive definite
    (scikit-learn's convention). With ``W = a a^T - K^-1`` (``a = K^-1 z``) the gradient's entries are
    ``tr(W dK/dtheta) / 2``; for a length, ``dK/dlog length_l = K_s o D_l / length_l^2`` (``D_l`` the squared
    differences of input ``l``), whose trace against ``W`` is ``sum_ij A_ij (u_il - u_jl)^2`` with
    ``A = W o K_s``: ``2 (u_l^2 . A 1 - u_l . A u_l)``, the inputs centred first."""
    from scipy.linalg import cho_solve, cholesky
    from scipy.spatial.distance import pdist, squareform

    n = len(z)
    s2, length, noise = np.exp(theta[0]), np.exp(theta[1:-1]), np.exp(theta[-1])
    ks = squareform(s2 * np.exp(-0.5 * pdist(u / length, metric="sqeuclidean")))
    np.fill_diagonal(ks, s2)
    k = ks.copy()
    k[np.diag_indices(n)] += noise + JITTER
    try:
        chol = cholesky(k, lower=True, check_finite=False)
    except np.linalg.LinAlgError:
        return math.inf, np.zeros_like(theta)
    a = cho_solve((chol, True), z, check_finite=False)
    lml = -0.5 * float(z @ a) - float(np.log(np.diag(chol)).sum()) - n / 2 * math.log(2 * math.pi)
    w = np.outer(a, a) - cho_solve((chol, True), np.eye(n), check_finite=False)
    wk = w * ks
    uc = u - u.mean(axis=0)
    by_length = (uc ** 2).T @ wk.sum(axis=1) - np.einsum("il,il->l", uc, wk @ uc)
    grad = np.concatenate([[0.5 * wk.sum()], by_length / length ** 2, [0.5 * noise * np.trace(w)]])
    return -lml, -grad


def _transform(y: NDArray[np.float64], power: float) -> NDArray[np.float64]:
    return np.log(y) if power == 0 else y ** power


def _untransform(z: NDArray[np.float64], power: float) -> NDArray[np.float64]:
    return np.exp(z) if power == 0 else z ** (1.0 / power)


def _clip_range(z: NDArray[np.float64], power: float) -> tuple[float, float]:
    """Where the transformed predictions are kept: the training range widened by half of it, and
    positive for a negative power (where the transform is defined)."""
    lo, hi = float(z.min()), float(z.max())
    pad = 0.5 * (hi - lo)
    return (lo - pad, hi + pad) if power == 0 else (max(lo - pad, 0.5 * lo), hi + pad)


Moments = tuple[tuple[float, NDArray[np.float64], NDArray[np.float64]],
                tuple[float, NDArray[np.float64], NDArray[np.float64]]]
"""Variance, first-order and total variances (d,) of a surrogate, and their standard errors."""


def _sampled_variances(gs: Sequence[Callable[[NDArray[np.float64]], NDArray[np.float64]]], d: int, seed: int,
                       lift: Callable[[NDArray[np.float64]], NDArray[np.float64]] | None = None,
                       runs: int | None = None) -> list[Moments]:
    """Variance and first-order and total variances of each ``g`` of ``gs`` under uniform inputs, and their
    standard errors: the mean and spread of :data:`REPLICATES` scrambled Sobol' Saltelli designs (Saltelli
    2010's first-order, Jansen's total estimator) of about ``runs`` surrogate evaluations in all, on values
    less a constant. ``lift``: a map of the sampled points (m, d) that every ``g`` takes instead of the points
    (the features' processes of :class:`FeatureSurrogate` s sharing them: evaluated once a sample for all of
    ``gs``). ``runs``: default :data:`SURROGATE_RUNS`; a larger one extends each replicate's Sobol' sequence
    (its first points are the smaller design's); the points are evaluated in chunks of :data:`CHUNK_VALUES`
    coordinates."""
    from scipy.stats import qmc

    lift = lift if lift is not None else (lambda u: u)
    runs = SURROGATE_RUNS if runs is None else runs
    base = 1 << max(4, int(np.floor(np.log2(runs / (REPLICATES * (d + 2))))))
    var, first, total = (np.empty((len(gs), REPLICATES)), np.empty((len(gs), REPLICATES, d)),
                         np.empty((len(gs), REPLICATES, d)))
    # scrambles of their own (not the Saltelli design's, which SALib draws from default_rng(seed)), so
    # this estimate and the model rows' are independent, as the bound's quadrature sum assumes
    *streams, own = np.random.SeedSequence([seed, 0x5A17E11]).spawn(REPLICATES + 1)
    # one constant off every value, drawn apart from the replicates: the estimators do not move with
    # a shift, their variance does (f_B (f_ABi - f_A) grows with the mean)
    start = lift(qmc.Sobol(d, scramble=True, seed=np.random.default_rng(own)).random(256))
    centres = [float(np.median(g(start))) for g in gs]
    rows = max(1, CHUNK_VALUES // (d * d))
    for r in range(REPLICATES):
        ab = qmc.Sobol(2 * d, scramble=True, seed=np.random.default_rng(streams[r])).random(base)
        blocks = np.empty((len(gs), base, d + 2))
        for lo in range(0, base, rows):
            a, b = ab[lo:lo + rows, :d], ab[lo:lo + rows, d:]
            mixed = np.repeat(a[:, None, :], d, axis=1)                  # AB_i: A with column i from B
            mixed[:, np.arange(d), np.arange(d)] = b
            at = [lift(a), lift(mixed.reshape(-1, d)), lift(b)]
            for j, g in enumerate(gs):
                blocks[j, lo:lo + len(a)] = np.column_stack([g(at[0]), g(at[1]).reshape(len(a), d), g(at[2])])
        for j in range(len(gs)):
            var[j, r], first[j, r], total[j, r] = _saltelli_variances(blocks[j] - centres[j])
    se = np.sqrt(1.0 / REPLICATES)
    return [((float(v.mean()), f.mean(axis=0), t.mean(axis=0)),
             (float(v.std(ddof=1) * se), f.std(axis=0, ddof=1) * se, t.std(axis=0, ddof=1) * se))
            for v, f, t in zip(var, first, total)]


def prime_moments(controls: Iterable[Any]) -> None:
    """Sample the variances of the :class:`FeatureSurrogate` s among ``controls`` that share their features'
    processes (an escalation's outputs: :meth:`FeatureSurrogate.fit`'s ``cache``) in one pass a group, the
    features' processes evaluated once a sample for all of them instead of once an output (two features:
    about a third of the cost for many outputs); each keeps the moments it would have sampled alone
    (the same points, seed and arithmetic). Others are left to sample when first asked."""
    groups: dict[tuple[int, int], list[_FeatureProcess]] = {}
    for g in controls:
        core = getattr(g, "core", None)
        if isinstance(core, _FeatureProcess) and "moments" not in core.__dict__:
            groups.setdefault((id(core.features), core.seed), []).append(core)
    for cores in groups.values():
        unique = list({id(c): c for c in cores}.values())
        if len(unique) >= 2:
            _resample(unique, SURROGATE_RUNS)


def refine_moments(controls: Iterable[Any], target: float, conf_level: float = 0.95) -> None:
    """Sample the variances of the controls whose sampled error adds more than ``target`` to an index's bound
    (a first-order or total index, or a difference of two totals) again, on 4 times the surrogate evaluations
    each round, up to :data:`MAX_SURROGATE_RUNS` (where the target is out of reach, the cap ends it). The
    stopping rule reads the same 8-replicate standard errors the bound then uses.

    A controlled estimate's bound adds, in quadrature, the model rows' error and the Monte Carlo error of
    the surrogate's own variances (:func:`controlled_saltelli`'s ``exact_error``). Where the control follows
    the output closely the first is small at any base, and the second -- independent of the model runs --
    sets the bound: on the test rig's steady scene (27 inputs, a control with features, leave-one-out 0.01) it
    was 0.0108 of 0.0113 and 0.0189 of 0.0192 of the two leading total indices' errors at N = 256, and the
    bounds did not move from N = 1 024 to 2 048. Surrogate evaluations, not model runs, shrink it: the margin
    ``t sqrt(se_T^2 + (S_T se_V)^2) / V`` (at ``conf_level``, Student's t over the :data:`REPLICATES`) falls as
    ``runs^-1/2``. The estimate stays unbiased (the same surrogate, only its moments known better)."""
    from scipy.stats import t

    q = t.ppf(0.5 + conf_level / 2.0, REPLICATES - 1)
    cores = list({id(c): c for g in controls
                  if isinstance(c := getattr(g, "core", None), (_PowerProcess, _FeatureProcess))}.values())

    def margin(core: Any) -> float:
        """The largest margin the sampled moments add to a first-order or total index or to a difference of
        two total indices (:func:`controlled_saltelli`'s ``m1``, ``mt`` and, its two largest errors added, ``md``)."""
        (var, first, total), (var_se, first_se, total_se) = core.moments
        if not var > 0:
            return 0.0
        m1 = q * np.hypot(first_se, first / var * var_se) / var
        mt = q * np.hypot(total_se, total / var * var_se) / var
        md = q * np.sort(total_se)[-2:].sum() / var
        return float(max(m1.max(), mt.max(), md))

    def runs_of(core: Any) -> int:
        return int(core.__dict__.get("moment_runs", SURROGATE_RUNS))

    while True:
        loose = [c for c in cores if margin(c) > target and runs_of(c) < MAX_SURROGATE_RUNS]
        if not loose:
            return
        feature: dict[tuple[int, int, int], list[_FeatureProcess]] = {}
        for c in loose:
            runs = min(MAX_SURROGATE_RUNS, 4 * runs_of(c))
            if isinstance(c, _FeatureProcess):
                feature.setdefault((id(c.features), c.seed, runs), []).append(c)
            else:
                _resample([c], runs)
        for (_, _, runs), group in feature.items():
            _resample(group, runs)


def _resample(cores: list[Any], runs: int) -> None:
    """Sample the variances of ``cores`` (:class:`_PowerProcess` es, or :class:`_FeatureProcess` es sharing
    their features' processes) on about ``runs`` surrogate evaluations each, into their cached moments."""
    first = cores[0]
    if isinstance(first, _FeatureProcess):
        moments = _sampled_variances([c.inner for c in cores], first.features[0].centres.shape[1], first.seed,
                                     first.augmented, runs=runs)
    else:
        moments = [_sampled_variances([c], c.process.centres.shape[1], c.seed, runs=runs)[0] for c in cores]
    for core, m in zip(cores, moments):
        core.__dict__["moments"] = m            # the cached property's slot (the dataclass is frozen)
        core.__dict__["moment_runs"] = runs


def _exact_variances(c: NDArray[np.float64], a: NDArray[np.float64], length: NDArray[np.float64]
                     ) -> tuple[float, NDArray[np.float64], NDArray[np.float64]] | None:
    """Variance, first-order and total variances (d,) of ``sum_j a_j prod_l k_l(u_l, c_jl)`` under
    uniform inputs (see the module); None when the quadratic forms' round-off could exceed
    :data:`MAX_ROUNDOFF` of the variance."""
    d = c.shape[1]
    one = [_single(c[:, l], length[l]) for l in range(d)]                  # I_l: (n,)
    two = [_pair(c[:, l], length[l]) for l in range(d)]                    # J_l: (n, n)
    mean = float(a @ np.prod(one, axis=0))
    whole = np.prod(two, axis=0)
    var = float(a @ whole @ a) - mean ** 2
    size = float(np.abs(a) @ whole @ np.abs(a))
    if not var > 0 or np.finfo(float).eps * size > MAX_ROUNDOFF * var:
        return None
    first, total = np.empty(d), np.empty(d)
    for i in range(d):
        rest = a * np.prod([one[l] for l in range(d) if l != i], axis=0)
        first[i] = rest @ two[i] @ rest - mean ** 2
    for i, others in _all_but_one(two):
        ai = a * one[i]
        total[i] = var - (ai @ others @ ai - mean ** 2)
    return var, first, total


def _all_but_one(factors: list[NDArray[np.float64]], lo: int = 0, hi: int | None = None,
                 acc: NDArray[np.float64] | None = None) -> Iterator[tuple[int, NDArray[np.float64]]]:
    """``(i, prod_{l != i} factors[l])`` for every ``i`` in ``range(lo, hi)``, times ``acc``: halving the range,
    each half's product multiplied into the other's, ``d log2 d`` products of the (n, n) factors instead of the
    ``d^2`` of one product per ``i``, holding ``log2 d`` of them at once."""
    hi = len(factors) if hi is None else hi
    if hi - lo == 1:
        yield lo, np.ones_like(factors[lo]) if acc is None else acc
        return
    mid = (lo + hi) // 2
    for a, b, c, e in ((lo, mid, mid, hi), (mid, hi, lo, mid)):
        part = np.prod(factors[c:e], axis=0)
        yield from _all_but_one(factors, a, b, part if acc is None else acc * part)


def _drawn_among(train: NDArray[np.int64], drawn: NDArray[np.bool_] | None) -> NDArray[np.bool_]:
    """Which of the training points ``train`` (indices) are drawn points, over which leave-one-out
    errors are taken; all of them without ``drawn`` or with fewer than two drawn."""
    mine = np.ones(len(train), dtype=bool) if drawn is None else np.asarray(drawn, dtype=bool)[train]
    return mine if mine.sum() >= 2 else np.ones(len(train), dtype=bool)


def _spread(n: int, most: int) -> NDArray[np.int64]:
    """At most ``most`` indices evenly spread over ``range(n)`` (all of them when ``n <= most``)."""
    return np.arange(n) if n <= most else np.unique(np.linspace(0, n - 1, most).round().astype(np.int64))


def _single(c: NDArray[np.float64], ell: float) -> NDArray[np.float64]:
    """``int_0^1 exp(-(u - c)^2 / (2 ell^2)) du`` for each ``c``."""
    s = np.sqrt(2.0) * ell
    return ell * np.sqrt(np.pi / 2.0) * (erf((1.0 - c) / s) + erf(c / s))


def _pair(c: NDArray[np.float64], ell: float) -> NDArray[np.float64]:
    """``int_0^1 k(u, c_j) k(u, c_k) du`` for every pair: ``exp(-(c_j - c_k)^2 / (4 ell^2))`` times a
    Gaussian of width ``ell / sqrt 2`` about the pair's midpoint integrated over [0, 1]."""
    mid = 0.5 * (c[:, None] + c[None, :])
    gap = c[:, None] - c[None, :]
    return np.exp(-gap ** 2 / (4.0 * ell ** 2)) * (ell * np.sqrt(np.pi) / 2.0) * (erf((1.0 - mid) / ell) + erf(mid / ell))


def controlled_level(st: NDArray[np.float64], loo: float) -> NDArray[np.float64]:
    """The ``ST`` that sets a controlled row's error in Saltelli's cost rule: ``min(ST, 2 loo^2)``
    (see the module)."""
    return np.minimum(np.asarray(st, dtype=float), 2.0 * float(loo) ** 2)


@dataclass(frozen=True)
class Controlled:
    """Controlled Saltelli estimates of one output (arrays (d,)) and their error estimates."""

    S1: NDArray[np.float64]
    ST: NDArray[np.float64]
    S1_conf: NDArray[np.float64]      # bootstrap half-width
    ST_conf: NDArray[np.float64]
    S1_error: NDArray[np.float64]     # the bootstrap half-width or twice the half-sample difference
    ST_error: NDArray[np.float64]
    variance: float
    ST_diff_error: NDArray[np.float64]
    """(d, d): the same rule's error estimate of each difference ``ST_i - ST_j`` (0 on the diagonal)."""


def _saltelli_variances(blocks: NDArray[np.float64]) -> tuple[float, NDArray[np.float64], NDArray[np.float64]]:
    """Variance, first-order (Saltelli 2010) and total (Jansen) variances (d,) of one function from its
    Saltelli blocks (N, d + 2): A, AB_1..AB_d, B -- the one place these estimators are written."""
    fa, fb, fab = blocks[:, 0], blocks[:, -1], blocks[:, 1:-1]
    return (float(np.var(np.concatenate([fa, fb]))), np.mean(fb[:, None] * (fab - fa[:, None]), axis=0),
            0.5 * np.mean((fa[:, None] - fab) ** 2, axis=0))


def _estimates(f: NDArray[np.float64], g: NDArray[np.float64], exact: tuple[float, NDArray[np.float64],
               NDArray[np.float64]], rows: NDArray[np.int64]) -> tuple[NDArray[np.float64], ...]:
    """S1, ST and the variance from the Saltelli blocks ``rows`` of ``f`` and ``g`` (each (N, d + 2):
    A, AB_1..AB_d, B): ``g``'s ``exact`` variances plus the difference of the two functions' estimates."""
    (var_f, first_f, total_f), (var_g, first_g, total_g) = _saltelli_variances(f[rows]), _saltelli_variances(g[rows])
    var = exact[0] + var_f - var_g
    first = exact[1] + first_f - first_g
    total = exact[2] + total_f - total_g
    return first / var, total / var, np.asarray(var)


def controlled_saltelli(f: NDArray[np.float64], g: NDArray[np.float64],
                        exact: tuple[float, NDArray[np.float64], NDArray[np.float64]], *, resamples: int = 200,
                        conf_level: float = 0.95, seed: int = 0, convergence_factor: float = 2.0,
                        exact_error: tuple[float, NDArray[np.float64], NDArray[np.float64]] | None = None
                        ) -> Controlled:
    """Controlled estimates of one output from its Saltelli blocks.

    Parameters
    ----------
    f, g : arrays (N, d + 2)
        The output and the surrogate at the design's rows, SALib's order per base point (``A``,
        ``AB_1`` .. ``AB_d``, ``B``), in the same units.
    exact : (float, array (d,), array (d,))
        The surrogate's variance, first-order and total variances under the input distribution
        (:meth:`GaussianSurrogate.variances`); zeros with ``g = 0`` give SALib's estimates.
    resamples, conf_level, seed
        Bootstrap over the ``N`` base points (SALib's ``num_resamples`` and ``conf_level``).
    convergence_factor : float
        Times the difference between the estimates from the first ``N / 2`` base points (they form a
        Saltelli design of their own) and from all; the error estimate is the larger of that and the
        bootstrap half-width.
    exact_error : (float, array (d,), array (d,)), optional
        Standard errors of ``exact`` where it is itself an estimate
        (:meth:`TransformedSurrogate.variance_errors`): added, at the confidence level (Student's t
        over the :data:`REPLICATES`), in quadrature to every half-width and error estimate.
    """
    from scipy.stats import norm, t

    f, g = np.asarray(f, dtype=float), np.asarray(g, dtype=float)
    n = len(f)
    every = np.arange(n)
    s1, st, var = _estimates(f, g, exact, every)
    rng = np.random.default_rng(seed)
    boot = [_estimates(f, g, exact, rng.integers(0, n, n)) for _ in range(resamples)]
    z = norm.ppf(0.5 + conf_level / 2.0)
    c1 = z * np.std([b[0] for b in boot], axis=0, ddof=1)
    ct = z * np.std([b[1] for b in boot], axis=0, ddof=1)
    e1, et = c1.copy(), ct.copy()
    # the differences ST_i - ST_j by the same rule: their bootstrap replicates, and the half sample's difference
    boot_t = np.array([b[1] for b in boot])
    ed = z * np.std(boot_t[:, :, None] - boot_t[:, None, :], axis=0, ddof=1)
    if n >= 4:
        h1, ht, _ = _estimates(f, g, exact, every[:n // 2])
        e1 = np.fmax(e1, convergence_factor * np.abs(s1 - h1))
        et = np.fmax(et, convergence_factor * np.abs(st - ht))
        dev = st - ht
        ed = np.fmax(ed, convergence_factor * np.abs(dev[:, None] - dev[None, :]))
    if exact_error is not None:
        var_se, first_se, total_se = exact_error
        q = t.ppf(0.5 + conf_level / 2.0, REPLICATES - 1)
        m1 = q * np.hypot(first_se, s1 * var_se) / var
        mt = q * np.hypot(total_se, st * var_se) / var
        # the process's total variances may err together or apart: their errors add; the variance's is shared
        md = q * np.hypot(total_se[:, None] + total_se[None, :], (st[:, None] - st[None, :]) * var_se) / var
        c1, ct, e1, et, ed = np.hypot(c1, m1), np.hypot(ct, mt), np.hypot(e1, m1), np.hypot(et, mt), np.hypot(ed, md)
    return Controlled(s1, st, c1, ct, e1, et, float(var), ed)
