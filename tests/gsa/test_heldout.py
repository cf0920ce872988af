"""The held-out suite's closed form (``ddgsa.bench.heldout``) against an independent answer: a tensor
Gauss rule, exact here (every input function is a polynomial of degree <= 3 in its input, the
products of a block are of degree <= 3 per input, so 6 nodes integrate their squares exactly)."""

from __future__ import annotations

import numpy as np
import pytest

from ddgsa.bench.heldout import PHI, BlockSum, _input, held_out_case
from ddgsa.gsa.testfunctions import tensor_indices
from ddgsa.gsa.space import ParameterSpace


def test_the_closed_form_indices_agree_with_a_tensor_rule() -> None:
    kinds = ("uniform", "cubic", "normal", "square", "lognormal")
    space = ParameterSpace.from_dict({f"x{k + 1}": _input(kind) for k, kind in enumerate(kinds)})
    f = BlockSum(space, kinds, ((0, 2, 4), (1, 3)), np.array([1.3, 0.7]), np.array([0.5, 0.8, 0.3, 0.6, 0.4]), 4.0)
    s1, st = f.indices()
    ref_s1, ref_st = tensor_indices(f, space, 6)
    assert s1 == pytest.approx(ref_s1[0], abs=1e-10)
    assert st == pytest.approx(ref_st[0], abs=1e-10)


@pytest.mark.parametrize("kind", PHI)
def test_each_input_function_is_standardised(kind: str) -> None:
    space = ParameterSpace.from_dict({"x": _input(kind)})
    from ddgsa.gsa.quadrature import gauss_rule

    nodes, weights = gauss_rule(space.parameters[0], 12)
    phi = BlockSum(space, (kind,), ((0,),), np.ones(1), np.ones(1), 0.0).phi(nodes[:, None])[:, 0]
    assert weights @ phi == pytest.approx(0.0, abs=1e-9)
    assert weights @ phi ** 2 == pytest.approx(1.0, rel=1e-9)


def test_the_draws_hold_inert_inputs_and_exact_ties() -> None:
    draws = [held_out_case(s) for s in range(5000, 5012)]
    assert sum(int((f.c == 0).sum()) for f in draws) >= 12                  # inert inputs
    tied = 0
    for f in draws:
        st = f.indices()[1]
        live = np.sort(st[st > 0])
        tied += int(np.any(np.isclose(np.diff(live), 0.0, atol=1e-14)))
    assert tied >= 6                                                        # exact ties in half the draws
