"""The block contract of ``Model.evaluate`` (issue 46 item 1): ``evaluate`` resolves the points and
hands them to ``Model._evaluate_block`` as one block; its default loops over the points."""

from __future__ import annotations

from typing import Any

import numpy as np
import pandas as pd
import pytest

from ddgsa.models.base import Model, ModelParameter


class _Toy(Model):
    """``y = a b`` per point; a point with ``a < 0`` fails (a ValueError, as a failed simulation)."""

    name = "toy_block"
    parameters = (ModelParameter("a", 1.0, "-", "first factor", -1.0, 2.0),
                  ModelParameter("b", 3.0, "-", "second factor", 0.0, 5.0))
    outputs = ("y", "a_squared")

    def _evaluate_one(self, params: dict[str, float], scene: Any) -> dict[str, float]:
        if params["a"] < 0.0:
            raise ValueError(f"negative a = {params['a']}")
        return {"y": params["a"] * params["b"], "a_squared": params["a"] ** 2}

    def simulate(self, scene: Any, params: Any = None) -> pd.DataFrame:
        raise NotImplementedError

    def modes(self, params: Any = None, rotor_speed: float = 0.0) -> pd.DataFrame:
        return pd.DataFrame()


class _ToyBlock(_Toy):
    """The same outputs computed for a whole block at once; counts the blocks it is handed."""

    def __init__(self) -> None:
        self.blocks: list[int] = []

    def _evaluate_block(self, params: pd.DataFrame, scene: Any, signals: tuple[str, ...] = ()) -> pd.DataFrame:
        self.blocks.append(len(params))
        a, b = params["a"].to_numpy(), params["b"].to_numpy()
        bad = a < 0.0
        out = pd.DataFrame({"y": np.where(bad, np.nan, a * b), "a_squared": np.where(bad, np.nan, a * a)})
        out.attrs["failures"] = {int(i): f"ValueError: negative a = {a[i]}" for i in np.flatnonzero(bad)}
        return out


POINTS = pd.DataFrame({"a": [0.5, -0.5, 1.5, 2.0], "b": [1.0, 2.0, 4.0, 0.0]})


def test_the_default_block_loops_over_the_points_and_records_failures() -> None:
    out = _Toy().evaluate(POINTS, None)
    assert list(out.columns) == ["y", "a_squared"] and len(out) == 4
    np.testing.assert_array_equal(out["y"].to_numpy(), [0.5, np.nan, 6.0, 0.0])
    assert out.attrs["failures"] == {1: "ValueError: negative a = -0.5"}


def test_a_batching_model_gets_the_resolved_block_in_one_call() -> None:
    """Missing columns come nominal (``b`` = 3), the block arrives whole, and its outputs and failures
    equal the per-point loop's."""
    model = _ToyBlock()
    out = model.evaluate(POINTS[["a"]], None)
    assert model.blocks == [4]
    ref = _Toy().evaluate(POINTS[["a"]], None)
    pd.testing.assert_frame_equal(out, ref)
    assert out.attrs["failures"] == ref.attrs["failures"] == {1: "ValueError: negative a = -0.5"}
    np.testing.assert_array_equal(out["y"].to_numpy(), [1.5, np.nan, 4.5, 6.0])


def test_the_block_is_checked_before_it_is_evaluated() -> None:
    """``resolve`` still refuses a point outside a parameter's range, before the block runs."""
    model = _ToyBlock()
    with pytest.raises(ValueError, match="parameter 'b' = 9 leaves its allowed range"):
        model.evaluate(pd.DataFrame({"b": [9.0]}), None)
    assert model.blocks == []


class _ToyFeatures(_Toy):
    """The toy with a control feature, ``a + b``, computed in the same run (issue 46 item 8)."""

    name = "toy_features"

    def control_features(self, scene: Any) -> tuple[Any, ...]:
        from ddgsa.models.base import ModelOutput

        return (ModelOutput("a_plus_b", "-", "a + b"),)

    def _evaluate_one(self, params: dict[str, float], scene: Any) -> dict[str, float]:
        return {**super()._evaluate_one(params, scene), "a_plus_b": params["a"] + params["b"]}


def test_a_model_without_features_returns_none_and_the_runner_stores_its_outputs_alone() -> None:
    """The default declares no control feature: ``evaluate`` carries no ``features`` and the stored
    outcomes hold the outputs only, as before features existed."""
    from ddgsa.runner import evaluate_batch_in

    toy = _Toy()
    assert toy.control_features(None) == ()
    out = toy.evaluate(POINTS, None)
    assert "features" not in out.attrs
    got = evaluate_batch_in(lambda p, s: toy.evaluate(p, s), {}, POINTS.to_dict("records"))
    assert [None if o.outputs is None else set(o.outputs) for o in got] == [{"y", "a_squared"}, None] + [{"y", "a_squared"}] * 2

    def no_features(p: pd.DataFrame, s: Any) -> pd.DataFrame:       # an empty mapping: the same
        out = toy.evaluate(p, s)
        out.attrs["features"] = {}
        return out

    assert [o.outputs for o in evaluate_batch_in(no_features, {}, POINTS.to_dict("records"))] == [o.outputs for o in got]


def test_declared_features_come_with_the_runs_and_are_stored_beside_the_outputs() -> None:
    """A model's features are returned in ``attrs["features"]`` (NaN where a point failed; the outputs'
    columns unchanged) and the runner stores them with each run's outputs, where the confirmation reads them."""
    from ddgsa.runner import evaluate_batch_in

    toy = _ToyFeatures()
    out = toy.evaluate(POINTS, None)
    assert list(out.columns) == ["y", "a_squared"]
    np.testing.assert_array_equal(out.attrs["features"]["a_plus_b"], [1.5, np.nan, 5.5, 2.0])
    both = pd.concat([out, out], ignore_index=True)          # frames with features still concatenate
    assert len(both) == 8
    got = evaluate_batch_in(lambda p, s: toy.evaluate(p, s), {}, POINTS.to_dict("records"))
    assert got[1].outputs is None
    assert [o.outputs["a_plus_b"] for o in got if o.outputs is not None] == [1.5, 5.5, 2.0]
    assert got[2].outputs["y"] == 6.0
