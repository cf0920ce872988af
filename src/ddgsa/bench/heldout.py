"""A held-out suite for ``ddgsa bench trust --held-out``: functions drawn at random from a family with
closed-form Sobol indices, which no trust rule's constant was chosen on (issue 51.5).

Each function is a sum of independent blocks, each a product over its inputs::

    f(x) = offset + sum_b a_b prod_{i in B_b} (1 + c_i phi_i(x_i))

with ``phi_i`` a standardised (mean 0, variance 1) function of an independent input: a uniform one
(linear or cubic), a normal one (linear or its square) or a lognormal one. With ``v_i = c_i^2``:

* the variance is ``V = sum_b a_b^2 (prod_{i in B_b} (1 + v_i) - 1)``;
* the main effect of ``x_i`` in block ``b`` is ``a_b c_i phi_i``: ``S_i = a_b^2 v_i / V``;
* its total effect is ``T_i = a_b^2 v_i prod_{j in B_b, j != i} (1 + v_j) / V``.

The draws (:func:`held_out_case`) vary the dimension (4-20), the blocks (interactions), the
distributions and nonlinearity, set some ``c_i`` to zero (inert inputs), repeat some (exact ties)
and add an offset of up to ten standard deviations (M-DRM is not shift invariant), so the suite
holds the cases the issue names. ``tests/gsa/test_heldout.py`` checks the closed form against a
tensor Gauss rule on small draws.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from ddgsa.gsa.space import ParameterSpace

SEEDS = tuple(range(5000, 5012))
"""The suite's twelve draws (seeds of :func:`held_out_case`), never used to choose a constant."""

PHI = ("uniform", "cubic", "normal", "square", "lognormal")
"""The standardised input functions ``phi``."""

_LOGNORMAL_SIGMA = 0.5


@dataclass(frozen=True)
class BlockSum:
    """One drawn function: its space, blocks, coefficients and input functions."""

    space: ParameterSpace
    kinds: tuple[str, ...]
    blocks: tuple[tuple[int, ...], ...]
    a: NDArray[np.float64]
    c: NDArray[np.float64]
    offset: float

    def phi(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        """The standardised input functions at points ``x`` (n, d)."""
        out = np.empty_like(x, dtype=float)
        for i, kind in enumerate(self.kinds):
            out[:, i] = _standardised(kind, x[:, i])
        return out

    def __call__(self, x: NDArray[np.float64]) -> NDArray[np.float64]:
        z = 1.0 + self.c * self.phi(np.atleast_2d(x))
        return self.offset + sum(a * np.prod(z[:, list(b)], axis=1) for a, b in zip(self.a, self.blocks))

    def indices(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """Exact ``S1`` and ``ST`` (d,), in closed form (the module)."""
        v = self.c ** 2
        s1, st = np.zeros(len(v)), np.zeros(len(v))
        total = 0.0
        for a, b in zip(self.a, self.blocks):
            prod = np.prod(1.0 + v[list(b)])
            total += a ** 2 * (prod - 1.0)
            for i in b:
                s1[i] = a ** 2 * v[i]
                st[i] = a ** 2 * v[i] * prod / (1.0 + v[i])
        return s1 / total, st / total


def _standardised(kind: str, x: NDArray[np.float64]) -> NDArray[np.float64]:
    """``phi(x)`` with mean 0 and variance 1 under the input's distribution (:func:`_input`)."""
    if kind == "uniform":                      # U(0, 1)
        return (x - 0.5) * np.sqrt(12.0)
    if kind == "cubic":                        # U(0, 1): E x^3 = 1/4, Var x^3 = 1/7 - 1/16
        return (x ** 3 - 0.25) / np.sqrt(1.0 / 7.0 - 1.0 / 16.0)
    if kind == "normal":                       # N(0, 1)
        return x
    if kind == "square":                       # N(0, 1): E x^2 = 1, Var x^2 = 2
        return (x ** 2 - 1.0) / np.sqrt(2.0)
    s2 = _LOGNORMAL_SIGMA ** 2                 # lognormal(0, sigma): mean exp(s2/2), var (e^s2 - 1) e^s2
    return (x - np.exp(s2 / 2.0)) / np.sqrt((np.exp(s2) - 1.0) * np.exp(s2))


def _input(kind: str) -> dict[str, float | str]:
    if kind in ("uniform", "cubic"):
        return {"dist": "uniform", "low": 0.0, "high": 1.0}
    if kind in ("normal", "square"):
        return {"dist": "normal", "mean": 0.0, "std": 1.0}
    return {"dist": "lognormal", "mu": 0.0, "sigma": _LOGNORMAL_SIGMA}


def held_out_case(seed: int) -> BlockSum:
    """One function of the family (the module), drawn with ``seed``.

    Examples
    --------
    >>> f = held_out_case(5000)
    >>> s1, st = f.indices()
    >>> bool(np.all(st >= s1 - 1e-15)), round(float(s1.sum()), 6) <= 1.0
    (True, True)
    """
    rng = np.random.default_rng(seed)
    d = int(rng.integers(4, 21))
    kinds = tuple(str(k) for k in rng.choice(PHI, size=d))
    order = rng.permutation(d)
    cuts = np.sort(rng.choice(np.arange(1, d), size=int(rng.integers(0, min(4, d - 1) + 1)), replace=False))
    blocks = tuple(tuple(int(i) for i in sorted(part)) for part in np.split(order, cuts))
    c = rng.uniform(0.1, 0.9, size=d)
    inert = rng.random(d) < 0.3
    c[inert] = 0.0
    shared = [b for b in blocks if np.count_nonzero(~inert[list(b)]) >= 2]
    if shared:                                  # an exact tie: two live inputs of one block with equal c
        b = shared[int(rng.integers(len(shared)))]
        i, j = rng.choice([k for k in b if not inert[k]], size=2, replace=False)
        c[j] = c[i]
    a = rng.uniform(0.3, 2.0, size=len(blocks))
    probe = BlockSum(ParameterSpace.from_dict({f"x{k + 1}": _input(kinds[k]) for k in range(d)}),
                     kinds, blocks, a, c, 0.0)
    sd = float(np.sqrt(sum(ab ** 2 * (np.prod(1.0 + c[list(b)] ** 2) - 1.0) for ab, b in zip(a, blocks))))
    offset = float(rng.choice([0.0, 1.0, 10.0])) * sd
    return BlockSum(probe.space, kinds, blocks, a, c, offset)
