"""The rig's start-up and coast-down for a block of points (issue 46 item 3,
``ddgsa.models.hss_rig.sweep_block``) against the per-point path (``HssRig._evaluate_one``: the full sweep
model, every column differenced, the factors renewed every step), and the kernel's reduction
(``ddgsa.mbs.sweep.reduce``) against the unreduced sweep."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from ddgsa.mbs.sweep import integrate, reduce
from ddgsa.models.base import Model
from ddgsa.models.hss_rig import sweep_block, transient
from ddgsa.models.hss_rig.model import HssRig, _rig_band

from tests.models.test_hss_rig_block import _study_points

RTOL = 5e-3
"""The block path's agreement with the per-point path where an output's declared resolution does not cover the
difference (issue 46: 1 % or the resolution). Measured on 16 points of each paper A study: the housings' RMS and 2x
orders within 1.1e-3 relative (the modes above the band, :data:`~ddgsa.models.hss_rig.sweep_block.NYQUIST_MULTIPLE`);
unreduced, every output within 6e-5."""


def _differences(model: HssRig, points: pd.DataFrame, scene: dict) -> tuple[dict[str, float], dict[str, float], list]:
    """The block path's and the per-point path's outputs on ``points``: (outputs beyond :data:`RTOL` and their
    resolution: their largest excess; every output's largest relative difference; outputs above their resolution
    at every point)."""
    params = model.resolve(points)
    sc = model._scene(scene)
    block = model._evaluate_block(params, sc)
    ref = Model._evaluate_block(model, params, sc)
    assert block.attrs["failures"] == ref.attrs["failures"]
    assert block.attrs["block_points"] == len(points) - sum(map(bool, params[["misalignment_parallel",
                                                                              "misalignment_angular"]].any(axis=1)))
    resolution = {str(o): o.resolution for o in model.outputs}
    ok = [i for i in range(len(points)) if i not in ref.attrs["failures"]]
    above = [c for c in ref.columns if np.all(np.abs(ref[c].to_numpy()[ok]) > resolution[c])]
    beyond, relative = {}, {}
    for col in ref.columns:
        a, b = ref[col].to_numpy()[ok], block[col].to_numpy()[ok]
        excess = np.abs(a - b) - np.maximum(RTOL * np.abs(a), resolution[col])
        relative[col] = float(np.max(np.abs(a - b) / np.maximum(np.abs(a), 1e-300)))
        if excess.max() > 0.0:
            beyond[col] = float(excess.max())
    return beyond, relative, above


@pytest.mark.parametrize("kind", ["startup", "coastdown"])
def test_block_sweeps_match_the_per_point_path(kind: str) -> None:
    """Three seeded points of ``paper_a_subsystem``: every output within :data:`RTOL` or its resolution, and at
    least 20 of the 49 outputs above their resolution at every point (the comparison is not carried by the
    resolutions alone)."""
    model, points, scene = _study_points("paper_a_subsystem", 3, seed=11)
    beyond, _, above = _differences(model, points, {**scene, "kind": kind})
    assert len(above) >= 20, above
    assert not beyond, f"outputs beyond {RTOL:g} and their resolution: {beyond}"


@pytest.mark.parametrize("kind", ["startup", "coastdown"])
def test_block_sweeps_carry_the_per_point_paths_control_features(kind: str) -> None:
    """The sweep features (``critical_ratio_1``, ``end_ratio_1``) of three seeded points of ``paper_a_subsystem``: the
    block path's within 1e-6 of the per-point path's (both from the unreduced sweep's linearisation; the end speed
    from the reduced and the full record). Their frequency is checked against ``modes()`` in
    ``tests/models/test_hss_rig_block.py``."""
    model, points, scene = _study_points("paper_a_subsystem", 3, seed=11)
    params, sc = model.resolve(points), model._scene({**scene, "kind": kind})
    block = model._evaluate_block(params, sc).attrs["features"]
    ref = Model._evaluate_block(model, params, sc).attrs["features"]
    assert set(block) == set(ref) == {"critical_ratio_1", "end_ratio_1"}
    for f in ref:
        np.testing.assert_allclose(block[f], ref[f], rtol=1e-6)


@pytest.mark.slow
@pytest.mark.parametrize("study", ["paper_a_subsystem", "paper_a_structural"])
@pytest.mark.parametrize("kind", ["startup", "coastdown"])
def test_block_sweeps_match_the_per_point_path_on_16_points(study: str, kind: str) -> None:
    """As the fast test, on 16 seeded points of each paper A study's space."""
    model, points, scene = _study_points(study, 16, seed=5)
    beyond, _, above = _differences(model, points, {**scene, "kind": kind})
    assert len(above) >= 20, above
    assert not beyond, f"outputs beyond {RTOL:g} and their resolution: {beyond}"


def test_a_basis_below_the_housings_resonances_is_caught(monkeypatch: pytest.MonkeyPatch) -> None:
    """The block's band holds the housings' resonances up to the record's Nyquist frequency: reduced to the
    band the model's basis rule names for its outputs (609 Hz at 1500 rpm: 26 of 42 modes, the housings' near
    900 Hz dropped) the comparison fails, the first housing's RMS 20 % off and beyond its resolution."""
    model, points, scene = _study_points("paper_a_subsystem", 2, seed=11)
    sc = {**scene, "kind": "startup"}
    monkeypatch.setattr(sweep_block, "band_hz", lambda s: _rig_band(model, s))
    beyond, relative, _ = _differences(model, points, sc)
    assert "rms_housing_1_y" in beyond and relative["rms_housing_1_y"] > 0.1


def test_a_reduction_to_every_mode_is_the_unreduced_sweep() -> None:
    """:func:`ddgsa.mbs.sweep.reduce` with a band above every mode is a change of coordinates: the rig's
    start-up at the nominal point, its inputs' rows mapped onto the basis, gives the unreduced record within
    1e-7 of each coordinate's largest excursion or 1e-9 m or rad (the iterations' tolerance is 1e-10 m or rad;
    measured 2.4e-10 rad on the shaft's 12 rad spin angle, below 1e-10 elsewhere)."""
    model = HssRig("linear", time_step=5e-4)
    raw = model.resolve(None).iloc[0].to_dict()
    sc = model._scene({"kind": "startup", "speed_rpm": 1500.0, "duration": 0.3, "sample_rate": 2000.0})
    rig, drive, spin = model._build(raw, sc)
    q0, _ = model.initial_state(rig, raw)
    full = transient.prepare(drive, raw, q0, "startup", spin, model.basis)
    small = transient.prepare(drive, raw, q0, "startup", spin, model.basis, band_hz=1e6)
    assert small.model.basis.shape == (42, 42)
    _, z, _ = integrate(full.model, 0.3, 5e-4, full.z0, full.zd0, full.inputs)
    _, e, _ = integrate(small.model, 0.3, 5e-4, small.z0, small.zd0, small.inputs, reuse=sweep_block.REUSE)
    scale = np.abs(z).max(axis=0)
    assert np.all(np.abs(e @ small.model.basis.T - z).max(axis=0) <= np.maximum(1e-7 * scale, 1e-9))
    assert abs(z[-1, rig.system.index("hss.rx")]) > 10.0          # the shaft turned: the spin is carried
    with pytest.raises(ValueError, match="reduced already"):
        reduce(small.model, 100.0)


def test_a_point_that_fails_is_a_failure_with_its_reason(monkeypatch: pytest.MonkeyPatch) -> None:
    """A point whose sweep cannot be prepared is recorded with its reason and NaN outputs; the block's other
    points are computed."""
    model, points, scene = _study_points("paper_a_subsystem", 2, seed=11)
    params = model.resolve(points)
    prepare = transient.prepare

    def failing(drive, p, *args, **kwargs):
        if math.isclose(p["hss_diameter"], params["hss_diameter"].iloc[1]):
            raise np.linalg.LinAlgError("singular matrix")
        return prepare(drive, p, *args, **kwargs)

    monkeypatch.setattr(transient, "prepare", failing)
    out = model._evaluate_block(params, model._scene({**scene, "kind": "startup"}))
    assert out.attrs["failures"] == {1: "LinAlgError: singular matrix"}
    assert out.iloc[1].isna().all() and out.iloc[0].notna().all()


def test_the_damping_is_the_kernels_exact_form() -> None:
    """The block's sweep linearises the rig with every column of ``C`` formed without differences
    (``linearise(..., damping_tangents=True)``): at rest the kernel's tangents, at the synchronous speed the
    tangents, the bodies' exact rate slopes and the map's rate terms. At a random ``paper_a_structural`` point,
    about its sag, each column within 1e-6 of its largest central difference (measured: at rest equal but for
    1e-52 in a zero column; at speed 1.5e-7 on the shaft's spin column, the differences' round-off at their 1e-6
    step, 1.5e-10 against differences at a 1e-3 step), and ``K`` the same linearisation's."""
    from ddgsa.mbs import nonrotating
    from ddgsa.models.hss_rig.rig import tangent_columns

    model, points, scene = _study_points("paper_a_structural", 1, seed=7)
    raw = model.resolve(points).to_dict("records")[0]
    sc = model._scene({**scene, "kind": "startup"})
    rig, drive, spin = model._build(raw, sc)
    q0, _ = model.initial_state(rig, raw, tangents=True)
    bare, _ = transient.structure(raw, q0, 2 * math.pi * 25.0, model.basis)
    system = bare.system
    cols = tangent_columns(system)
    for qd in (np.zeros(system.n), system.qd0):
        ref = nonrotating.linearise(system, q0, qd, tangent_columns=cols)
        fast = nonrotating.linearise(system, q0, qd, tangent_columns=cols, damping_tangents=True)
        scale = np.abs(ref.c).max(axis=0)
        floor = 1e-12 * scale.max()                      # a zero column: 1e-52 of differencing noise
        assert np.all(np.abs(fast.c - ref.c).max(axis=0) <= np.maximum(1e-6 * scale, floor))
        assert np.array_equal(fast.k, ref.k)


def test_records_too_short_fail_as_on_the_per_point_path() -> None:
    """A 0.6 s start-up turns fewer than the 8 revolutions the ball-pass bands' 0.25 orders need: every point
    is a failure with the per-point path's reason (the block's objectives retried one record at a time), none
    an exception of the whole block."""
    model, points, scene = _study_points("paper_a_subsystem", 2, seed=11)
    params = model.resolve(points)
    sc = model._scene({**scene, "kind": "startup", "duration": 0.6})
    block = model._evaluate_block(params, sc)
    ref = Model._evaluate_block(model, params, sc)
    assert set(block.attrs["failures"]) == {0, 1}
    assert block.attrs["failures"] == ref.attrs["failures"]
    assert "narrower than the Hann main lobe" in block.attrs["failures"][0]
    assert block.isna().all().all()


def test_the_sag_on_the_bare_rig_is_the_still_rigs() -> None:
    """The block's sag on the sweep's bare rig (``sweep_block._sagged``: the bare rig's tangents plus the
    coupling's anisotropy at hub angle 0, no still rig built) against the per-point path's (``initial_state``: the
    still rig built, its stiffness differenced) on 3 ``paper_a_structural`` points with their anisotropic coupling:
    within 1e-9 of the sag's largest entry (the differences' noise; measured 8e-13 to 6e-11), and within 1e-11 of the
    still rig's from the tangents (measured 2e-14 to 1.5e-13); without the anisotropy's term it would be 3e-2 off.
    A misaligned coupling, loaded at rest, takes the still rig itself."""
    model, points, scene = _study_points("paper_a_structural", 3, seed=13)
    sc = model._scene({**scene, "kind": "startup"})
    for raw in model.resolve(points).to_dict("records"):
        assert raw["coupling_asymmetry"] > 0.0
        for misaligned in (False, True):
            raw = {**raw, "misalignment_parallel": 1e-4 if misaligned else 0.0, "misalignment_angular": 0.0}
            drive, _ = model.drive(raw, sc)
            rig = transient.bare_rig(raw, transient.synchronous_speed(drive), model.basis)
            fast = sweep_block._sagged(model, rig, raw) - rig.system.q0
            tangents = model.initial_state(rig, raw, tangents=True)[0] - rig.system.q0
            if misaligned:
                assert np.array_equal(fast, tangents)
                continue
            differenced = model.initial_state(rig, raw)[0] - rig.system.q0
            scale = np.abs(differenced).max()
            assert np.abs(fast - differenced).max() <= 1e-9 * scale
            assert np.abs(fast - tangents).max() <= 1e-11 * scale


@pytest.mark.parametrize("kind", ["startup", "coastdown"])
def test_the_incremental_loop_is_the_kernels(kind: str) -> None:
    """The block's integration (``integrate(..., incremental=True)``: the residual carried along the corrections,
    reordered dot products) against the kernel's loop (:mod:`ddgsa.mbs.alpha`) on the same reduced sweep, the
    rig's nominal point over 0.3 s: every coordinate and rate within 1e-9 of its largest excursion or 1e-12 (the
    iterations' tolerance is 1e-10 m or rad; measured 4e-13 to 2e-11, while the incremental loop run to a 1e-7
    tolerance is 2e-4 to 1e-2 off)."""
    model = HssRig("linear", time_step=5e-4)
    raw = model.resolve(None).iloc[0].to_dict()
    sc = model._scene({"kind": kind, "speed_rpm": 1500.0, "duration": 0.3, "sample_rate": 2000.0})
    drive, spin = model.drive(raw, sc)
    rig = transient.bare_rig(raw, transient.synchronous_speed(drive), model.basis)
    q0 = sweep_block._sagged(model, rig, raw)
    sweep = transient.prepare(drive, raw, q0, kind, spin, model.basis, band_hz=sweep_block.band_hz(sc), tangents=True,
                              bare=rig)
    args = (sweep.model, 0.3, 5e-4, sweep.z0, sweep.zd0, sweep.inputs)
    _, z, zd = integrate(*args, reuse=sweep_block.REUSE, extrapolate=True)
    _, e, ed = integrate(*args, reuse=sweep_block.REUSE, extrapolate=True, incremental=True)
    for a, b in ((z, e), (zd, ed)):
        assert np.all(np.abs(a - b).max(axis=0) <= np.maximum(1e-9 * np.abs(a).max(axis=0), 1e-12))


def test_sweep_lateral_frequencies_are_those_of_its_two_linearisations() -> None:
    """:func:`ddgsa.mbs.sweep.lateral_frequencies` of the rig's sweep model at rest and at its reference spin equal
    :func:`ddgsa.mbs.nonrotating.lateral_frequencies` of the two linearisations the model interpolates (the
    sweep's matrices are exact at both spins); between them they move monotonically."""
    from ddgsa.mbs import nonrotating
    from ddgsa.mbs.sweep import lateral_frequencies, sweep_model

    model = HssRig(fidelity="linear", time_step=5e-4)
    raw = model.resolve(pd.DataFrame({"hss_diameter": [0.026]})).to_dict("records")[0]
    sc = model._scene({"kind": "startup", "speed_rpm": 1500.0, "duration": 1.2, "sample_rate": 2000.0})
    drive, _ = model.drive(raw, sc)
    sync = transient.synchronous_speed(drive)
    rig = transient.bare_rig(raw, sync, model.basis)
    system = rig.system
    q0 = model.initial_state(rig, raw)[0]
    rest = nonrotating.linearise(system, q0, np.zeros(system.n))
    spinning = nonrotating.linearise(system, q0, system.qd0)
    sweep = sweep_model(rest, spinning, system.index("hss.rx"), q0 - system.q0)
    np.testing.assert_allclose(lateral_frequencies(system, sweep, 0.0, 2), nonrotating.lateral_frequencies(system, rest, 2),
                               rtol=1e-9)
    np.testing.assert_allclose(lateral_frequencies(system, sweep, sync, 2),
                               nonrotating.lateral_frequencies(system, spinning, 2), rtol=1e-9)
    lowest = [lateral_frequencies(system, sweep, w, 1)[0] for w in np.linspace(0.0, sync, 5)]
    assert np.all(np.diff(lowest) > 0) or np.all(np.diff(lowest) < 0)
    with pytest.raises(ValueError, match="unreduced"):
        lateral_frequencies(system, reduce(sweep, 500.0), sync, 1)
