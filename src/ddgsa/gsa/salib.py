"""Cross-check estimators from SALib: Saltelli/Jansen (``saltelli``), ``fast`` and ``rbd_fast``.

All three sample the unit hypercube with SALib and map it through each input's inverse
CDF (:meth:`ParameterSpace.ppf`): Sobol indices are invariant under such a
coordinate-wise bijection, so every distribution ddgsa supports works the same way.
Non-finite values never reach SALib (one NaN makes its Sobol indices all exactly zero,
silently): the base class refuses such outputs first. Seeds are passed as a
``numpy.random.Generator`` built from the ``seed`` option (SALib treats an integer
``seed=0`` as "no seed" in places; a Generator is never ignored).

Diagnostics: ``negative_index`` (untrusted) when an index is below zero by more than its
confidence half-width; ``wide_confidence`` (untrusted) when a confidence half-width exceeds
``conf_max``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray
from SALib.analyze import fast as fast_analyze
from SALib.analyze import rbd_fast as rbd_analyze
from SALib.analyze import sobol as sobol_analyze
from SALib.sample import fast_sampler, latin
from SALib.sample import sobol as sobol_sample

from ddgsa.errors import MethodError
from ddgsa.gsa.base import Design, GsaMethod, PartialIndices, check_fraction, check_int, register
from ddgsa.gsa.result import Diagnostic
from ddgsa.space import ParameterSpace

_COMMON = {"seed": 0, "num_resamples": 200, "conf_level": 0.95, "conf_max": 0.1}


def unit_problem(dim: int) -> dict[str, Any]:
    """A SALib problem on the ``dim``-dimensional unit hypercube."""
    return {"num_vars": dim, "names": [f"x{i}" for i in range(dim)], "bounds": [[0.0, 1.0]] * dim}


class _SalibMethod(GsaMethod):
    """Shared option checks and the per-output analysis loop."""

    def check_options(self, space: ParameterSpace, opts: dict[str, Any]) -> None:
        check_int(self.name, "seed", opts["seed"], 0)
        check_int(self.name, "num_resamples", opts["num_resamples"], 10)
        check_fraction(self.name, "conf_level", opts["conf_level"])
        check_fraction(self.name, "conf_max", opts["conf_max"], 0.0, 1e9)

    def _analyze(self, space: ParameterSpace, design: Design, y: NDArray[np.float64],
                 outputs: list[str]) -> PartialIndices:
        k, d = y.shape[1], space.dim
        S1, ST = np.full((k, d), np.nan), np.full((k, d), np.nan)
        S1c, STc = np.full((k, d), np.nan), np.full((k, d), np.nan)
        diags: list[Diagnostic] = []
        for j, out in enumerate(outputs):
            if np.var(y[:, j]) == 0.0:
                diags.append(Diagnostic("zero_variance", f"output {out!r} is constant over the sample; "
                                        "its Sobol indices are undefined", "untrusted", output=out))
                continue
            rng = np.random.default_rng(design.options["seed"])
            res = self._salib_analyze(design, y[:, j], rng)
            S1[j] = res["S1"]
            S1c[j] = res["S1_conf"]
            if "ST" in res:
                ST[j], STc[j] = res["ST"], res["ST_conf"]
        diags += _interval_diagnostics(space, outputs, S1, S1c, ST, STc, design.options["conf_max"])
        return PartialIndices(S1=S1, ST=ST, S1_conf=S1c, ST_conf=STc, diagnostics=diags)

    def _salib_analyze(self, design: Design, y: NDArray[np.float64],
                       rng: np.random.Generator) -> dict[str, Any]:
        raise NotImplementedError


@register("saltelli")
class Saltelli(_SalibMethod):
    """Saltelli sampling with Jansen/Saltelli estimators and bootstrap intervals (SALib ``sobol``).

    Options: ``n`` (base sample, a power of two, default 1024; cost ``n (d + 2)``), ``seed``,
    ``num_resamples``, ``conf_level``, ``conf_max``.
    """

    defaults = {"n": 1024, **_COMMON}

    def check_options(self, space: ParameterSpace, opts: dict[str, Any]) -> None:
        super().check_options(space, opts)
        n = check_int(self.name, "n", opts["n"], 2)
        if n & (n - 1):
            raise MethodError(f"method 'saltelli': option 'n' must be a power of two (Sobol' balance), got {n}")

    def _design(self, space: ParameterSpace, opts: dict[str, Any]) -> Design:
        u = sobol_sample.sample(unit_problem(space.dim), opts["n"], calc_second_order=False,
                                scramble=True, seed=np.random.default_rng(opts["seed"]))
        return Design(self.name, space.ppf(u), opts, {"unit": u})

    def _salib_analyze(self, design: Design, y: NDArray[np.float64],
                       rng: np.random.Generator) -> dict[str, Any]:
        o = design.options
        return sobol_analyze.analyze(unit_problem(design.points.shape[1]), y, calc_second_order=False, num_resamples=o["num_resamples"],
                                     conf_level=o["conf_level"], seed=rng)


@register("fast")
class Fast(_SalibMethod):
    """Extended FAST (SALib ``fast``): S1 and ST. Options: ``n`` per input (> 4 M^2, default 512), ``M``."""

    defaults = {"n": 512, "M": 4, **_COMMON}

    def check_options(self, space: ParameterSpace, opts: dict[str, Any]) -> None:
        super().check_options(space, opts)
        m = check_int(self.name, "M", opts["M"], 1)
        check_int(self.name, "n", opts["n"], 4 * m * m + 1)

    def _design(self, space: ParameterSpace, opts: dict[str, Any]) -> Design:
        u = fast_sampler.sample(unit_problem(space.dim), opts["n"], M=opts["M"],
                                seed=np.random.default_rng(opts["seed"]))
        return Design(self.name, space.ppf(u), opts, {"unit": u})

    def _salib_analyze(self, design: Design, y: NDArray[np.float64],
                       rng: np.random.Generator) -> dict[str, Any]:
        o = design.options
        # SALib's FAST bootstrap draws from numpy's global RandomState: seed it from our
        # generator for this call only and put the caller's global state back afterwards
        saved = np.random.get_state()
        try:
            np.random.seed(int(rng.integers(2**31)))
            return fast_analyze.analyze(unit_problem(design.points.shape[1]), y, M=o["M"],
                                        num_resamples=o["num_resamples"], conf_level=o["conf_level"],
                                        seed=None)
        finally:
            np.random.set_state(saved)


@register("rbd_fast")
class RbdFast(_SalibMethod):
    """Random-balance-design FAST (SALib ``rbd_fast``): S1 only. Options: ``n`` (default 1024), ``M``."""

    defaults = {"n": 1024, "M": 10, **_COMMON}

    def check_options(self, space: ParameterSpace, opts: dict[str, Any]) -> None:
        super().check_options(space, opts)
        m = check_int(self.name, "M", opts["M"], 1)
        check_int(self.name, "n", opts["n"], 2 * m + 1)

    def _design(self, space: ParameterSpace, opts: dict[str, Any]) -> Design:
        u = latin.sample(unit_problem(space.dim), opts["n"], seed=np.random.default_rng(opts["seed"]))
        return Design(self.name, space.ppf(u), opts, {"unit": u})

    def _salib_analyze(self, design: Design, y: NDArray[np.float64],
                       rng: np.random.Generator) -> dict[str, Any]:
        o = design.options
        u = design.meta["unit"]
        return rbd_analyze.analyze(unit_problem(u.shape[1]), u, y, M=o["M"], num_resamples=o["num_resamples"],
                                   conf_level=o["conf_level"], seed=rng)


def _interval_diagnostics(space: ParameterSpace, outputs: list[str], S1: NDArray[np.float64],
                          S1c: NDArray[np.float64], ST: NDArray[np.float64], STc: NDArray[np.float64],
                          conf_max: float) -> list[Diagnostic]:
    """Negative indices beyond their interval and intervals too wide to read."""
    diags = []
    for q, val, conf in (("S1", S1, S1c), ("ST", ST, STc)):
        for j, i in zip(*np.nonzero(np.isfinite(val))):
            out, par = outputs[j], space.names[i]
            half = conf[j, i] if np.isfinite(conf[j, i]) else 0.0
            if val[j, i] + half < 0.0:
                diags.append(Diagnostic("negative_index", f"output {out!r}: {q}[{par}] = {val[j, i]:.3g} "
                                        f"< 0 beyond its interval (+-{half:.2g}); sample too small",
                                        "untrusted", output=out, parameter=par, value=float(val[j, i])))
            if half > conf_max:
                diags.append(Diagnostic("wide_confidence", f"output {out!r}: {q}[{par}] +-{half:.2g} is wider "
                                        f"than conf_max {conf_max}; raise the sample size",
                                        "untrusted", output=out, parameter=par, value=float(half)))
    return diags
