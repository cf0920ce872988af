"""What every model shares through ``ddgsa.models.base.Model`` (issue 24): one fidelity check, and
``modes``, ``campbell`` and ``build`` with one signature; ``resolve`` reads points as a table, a
mapping or a 2-D array and checks each value's range with the study file's message (issue 48)."""

from __future__ import annotations

import inspect

import numpy as np
import pandas as pd
import pytest

from ddgsa import models
from ddgsa.errors import ModelError
from ddgsa.models.base import Model


@pytest.mark.parametrize("name", sorted(models.MODELS))
def test_modes_and_campbell_have_the_bases_signature(name: str) -> None:
    """The base's parameters, in its order, first (a model may add its own keywords after them:
    the geared drive's ``lss_torque``)."""
    cls = models.MODELS[name]
    for method in ("modes", "campbell", "build"):
        names = list(inspect.signature(getattr(cls, method)).parameters)
        base = [p.name for p in inspect.signature(getattr(Model, method)).parameters.values()
                if p.kind != inspect.Parameter.VAR_KEYWORD]
        assert names[:len(base)] == base, (name, method, names)


@pytest.mark.parametrize("name", ["direct_drive", "indirect_drive", "hss_rig", "generator_radial"])
def test_every_multibody_model_builds_by_one_spelling(name: str) -> None:
    """``build(params)`` on each of the four models (the rig also needs its scene); no other spelling left."""
    model = models.get(name)
    conditions = {"scene": {"kind": "steady", "speed_rpm": 1500.0, "duration": 0.5, "settle": 0.05}} if name == "hss_rig" else {}
    assert model.build(None, **conditions) is not None
    for old in ("assemble", "system", "_assemble"):
        assert not hasattr(model, old), (name, old)


def test_a_model_without_a_multibody_system_refuses_to_build() -> None:
    with pytest.raises(ModelError, match="model 'analytic' is not built from the kernel's parts"):
        models.get("analytic").build()


@pytest.mark.parametrize("name, known", [("hss_rig", "dq, kloss, linear"), ("direct_drive", "flexible, rigid, linear"),
                                         ("generator_radial", "linearised"), ("analytic", "exact")])
def test_one_fidelity_check_names_the_model_and_the_known_fidelities(name: str, known: str) -> None:
    with pytest.raises(ModelError, match=f"model '{name}': unknown fidelity 'stiff'; known: {known}$"):
        models.get(name, fidelity="stiff")


def test_a_model_without_rotor_speed_refuses_a_campbell_diagram() -> None:
    model = models.get("analytic")
    assert model.modes(rotor_speed=0.0).empty
    with pytest.raises(ModelError, match="no rotor speed to sweep"):
        model.campbell([0.0, 1.0])


@pytest.mark.parametrize("name, option, value, allowed", [
    ("direct_drive", "time_step", 0.5, r"a finite number in \(0, 0.1\] s"),
    ("direct_drive", "deflection", "peak", "one of total, frame, elastic"),
    ("indirect_drive", "housing_point", (1.0, 2.0), r"3 finite numbers in \[-inf, inf\] m"),
    ("indirect_drive", "fluctuation_scale", 0.0, r"a finite number in \(0, 1\]"),
    ("hss_rig", "noise", 1, "true or false"),
    ("generator_radial", "output_step", -1.0, r"a finite number in \(0, inf\] s"),
])
def test_a_model_built_directly_checks_its_declared_options(name: str, option: str, value: object,
                                                             allowed: str) -> None:
    """The constructor checks the declared options (one check, the same message as ``models.get``)."""
    with pytest.raises(ModelError, match=f"model '{name}': option '{option}' must be {allowed}, got"):
        models.MODELS[name](**{option: value})


def _ishigami(x: np.ndarray) -> np.ndarray:
    """Ishigami's function (a = 7, b = 0.1) written out: the independent answer for the analytic model."""
    return np.sin(x[:, 0]) + 7.0 * np.sin(x[:, 1]) ** 2 + 0.1 * x[:, 2] ** 4 * np.sin(x[:, 0])


def test_resolve_takes_a_frame_a_mapping_of_numbers_or_columns_and_a_2d_array() -> None:
    """Each form of points gives the table written by hand: given values, nominal (0) for the rest,
    columns in the declared order x1, x2, x3."""
    model = models.get("analytic")
    two = np.array([[0.1, 0.2, 0.3], [-1.0, 2.0, 3.0]])
    forms = {"frame": pd.DataFrame({"x3": [0.3, 3.0], "x1": [0.1, -1.0], "x2": [0.2, 2.0]}, index=[7, 9]),
             "columns": {"x1": [0.1, -1.0], "x2": np.array([0.2, 2.0]), "x3": (0.3, 3.0)},
             "array": two}
    for form, points in forms.items():
        table = model.resolve(points)
        assert list(table.columns) == ["x1", "x2", "x3"], form
        np.testing.assert_array_equal(table.to_numpy(), two, err_msg=form)      # copies of exact decimals
    np.testing.assert_array_equal(model.resolve({"x2": 0.5}).to_numpy(), [[0.0, 0.5, 0.0]])
    np.testing.assert_array_equal(model.resolve({"x3": [1.0, 2.0]}).to_numpy(), [[0.0, 0.0, 1.0], [0.0, 0.0, 2.0]])
    np.testing.assert_array_equal(model.resolve(None).to_numpy(), [[0.0, 0.0, 0.0]])


def test_evaluate_takes_a_2d_array_in_the_declared_order() -> None:
    """``evaluate(array, scene)`` (an ``AttributeError`` before issue 48) gives Ishigami's values at
    11 m/s (the model's factor wind_speed / 11 is 1), to 1e-12 relative: the same formula in
    another order of operations differs by a few ulps."""
    from ddgsa.loads.scene import Scene

    x = np.array([[0.1, 0.2, 0.3], [-1.0, 2.0, 3.0], [3.0, -2.5, 1.5]])
    out = models.get("analytic").evaluate(x, Scene(wind_speed=11.0, turbulence_intensity=0.0, duration=1.0))
    np.testing.assert_allclose(out["y"].to_numpy(), _ishigami(x), rtol=1e-12)


@pytest.mark.parametrize("points, message", [
    (np.zeros((2, 2)), r"model 'analytic': an array of points has shape \(n_points, 3\), one column per parameter "
                       r"in the declared order \(x1, x2, x3; one point: array.reshape\(1, -1\)\); got shape \(2, 2\)"),
    (np.zeros(3), r"has shape \(n_points, 3\).*got shape \(3,\)"),
    ({"x1": [0.1, 0.2], "x2": [0.3]}, r"every parameter a 1-D column of one length; got shapes \{'x1': \(2,\), "
                                      r"'x2': \(1,\)\}"),
    ({"x1": 0.1, "x2": [0.3]}, r"one number, or every parameter a 1-D column"),
    ({"x1": "one"}, r"parameter 'x1' must be numbers \[-\], got \['one'\]"),
    ([[0.1, 0.2, 0.3]], r"points are a DataFrame, a mapping .* or a 2-D array \(n_points, 3\); got list"),
    ({"x4": 0.1}, r"model 'analytic': unknown parameter 'x4'; known: x1, x2, x3; did you mean 'x3' or 'x2' or 'x1'\?"),
    (np.array([[0.1, 4.0, 0.0]]), r"model 'analytic': parameter 'x2' = 4 leaves its allowed range "
                                  r"\[-3.14159, 3.14159\]$"),
])
def test_resolve_refuses_points_it_cannot_read_saying_what_it_takes(points: object, message: str) -> None:
    with pytest.raises(ModelError, match=message):
        models.get("analytic").resolve(points)


def test_a_value_outside_its_range_gets_the_same_message_from_the_api_and_from_a_study(tmp_path) -> None:
    """A lateral bearing stiffness typed in kN/m (5e5, meaning 5e8 N/m; the range is [1e6, 1e12] N/m)
    is refused by ``resolve`` and by a study's ``fixed`` with one message and its unit hint."""
    from ddgsa.errors import StudyError
    from ddgsa.study.spec import load_study

    problem = ("parameter 'k_front_y' = 500000 N/m leaves its allowed range [1e+06, 1e+12] N/m (hint: 500000 kN/m "
               "= 5e+08 N/m is inside it: if the number is in kN/m, write unit: kN/m)")
    with pytest.raises(ModelError) as api:
        models.get("direct_drive", fidelity="rigid").resolve({"k_front_y": 5e5})
    assert str(api.value) == f"model 'direct_drive': {problem}"
    path = tmp_path / "kn.yaml"
    path.write_text("name: kn\nmodel: {name: direct_drive, fidelity: rigid}\nparameters:\n"
                    "  k_front_z: {nominal: 1e10, spread: 0.2}\nfixed: {k_front_y: 5e5}\n"
                    "scenes: {wind_speed: 11, duration: 60}\noutputs: [damage_front]\nmethods:\n"
                    "  - {method: mdrm, points: 3}\n")
    with pytest.raises(StudyError) as study:
        load_study(path)
    assert str(study.value) == f"{path}: field 'fixed.k_front_y': {problem}"
