"""What every model shares through ``ddgsa.models.base.Model`` (issue 24): one fidelity check, and
``modes``, ``campbell`` and ``build`` with one signature."""

from __future__ import annotations

import inspect

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
