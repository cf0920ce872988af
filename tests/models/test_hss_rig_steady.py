"""The linear fidelity's frequency-domain steady state (:func:`ddgsa.mbs.nonrotating.periodic`)
against its exact time-domain run (:func:`ddgsa.mbs.nonrotating.simulate`) on the rig's outputs.

Both start from the periodic state of one revolution; the time-domain run integrates the C1
cubic interpolant of the inputs exactly (interpolation error ~ (W dt)^4 / 384 < 1e-7 here) and
lets the cyclic spin angle drift with the linearisation's residual torque, the frequency-domain
one holds it; so they agree to the drift's effect on the sensors (measured <= 1.1e-4 of the
sensor's RMS on the structural sensors, 900-1500 rpm). The time-domain run's start from that state
rings in the converged basis's lightly damped higher shaft modes (0.2 % modal damping, decay time
~0.04 s at 2 kHz): after 0.05 s of settling its peaks differ by up to 1.4e-3 of the RMS, after 0.2 s
by 1.1e-4 and after 0.4 s by 5e-5 -- the frequency-domain state is the periodic one; the scene
settles 0.2 s.
"""

from __future__ import annotations

import numpy as np
import pytest

from ddgsa import models
from ddgsa.models.hss_rig.drive import drive_for
from ddgsa.models.hss_rig.model import ACCELEROMETERS, PROBES, POLE_PAIRS, objectives
from ddgsa.models.hss_rig.scenes import RigScene

SCENE = RigScene("steady", speed_rpm=1500.0, duration=0.6, sample_rate=2000.0, settle=0.2)


def _outputs(model, point: dict[str, float], harmonic: bool) -> dict[str, float]:
    p = model.effective(model.resolve(point).iloc[0].to_dict())
    rig, drive, spin = model.build(p, SCENE)
    t, q, qd = model._linear_run(rig, p, SCENE, spin, harmonic=harmonic)
    return objectives(model._sensors(rig, drive, SCENE, t, q, qd), SCENE, drive_for(p, SCENE, POLE_PAIRS))


@pytest.mark.slow  # two nonlinear time-domain rig runs (~20 s cold); the rig's paths against kloss stay in the default run
@pytest.mark.parametrize("point", [{}, {"eccentric_mass": 0.02, "support_stiffness": 5e6}])
def test_frequency_domain_steady_state_equals_the_time_domain_run(point):
    model = models.get("hss_rig", fidelity="linear")
    fast, ref = _outputs(model, point, True), _outputs(model, point, False)
    for sensor in ACCELEROMETERS + PROBES:
        scale = ref[f"rms_{sensor}"]
        for kind in ("rms", "peak", "order1x", "order2x"):
            key = f"{kind}_{sensor}"
            assert abs(fast[key] - ref[key]) <= 5e-4 * scale, (key, fast[key], ref[key])
    for key in ("current_line", "rms_motor_current", "mean_speed_rpm"):
        assert fast[key] == pytest.approx(ref[key], rel=1e-4), key
    # the motor torque barely moves at steady speed (1e-5 of its 10 N m mean): compare on that mean
    assert abs(fast["order1x_motor_torque"] - ref["order1x_motor_torque"]) <= 1e-6 * 10.0


def test_the_linear_fidelity_takes_the_frequency_domain_only_for_once_per_revolution_inputs(monkeypatch):
    from ddgsa.mbs import nonrotating

    model = models.get("hss_rig", fidelity="linear")
    used = []
    for name in ("periodic", "simulate"):
        real = getattr(nonrotating, name)
        monkeypatch.setattr(nonrotating, name, lambda *a, _n=name, _f=real, **k: used.append(_n) or _f(*a, **k))
    for point in ({}, {"supply_unbalance": 0.01}, {"defect_amplitude": 50.0}):
        model.simulate(SCENE, point)
    assert used == ["periodic", "simulate", "simulate"]


def test_the_nonlinear_rig_started_in_the_periodic_state_stays_in_it():
    """The kloss rig (generalised-alpha, 2e-4 s) started from :meth:`HssRig.periodic_state` keeps the
    frequency-domain steady state: the disk probe over 0.2 s within 1 % of the 1x amplitude (a start
    from the static sag rings at the 2 %-damped bending mode for seconds: > 50 %)."""
    from ddgsa.mbs import genalpha

    kloss, linear = models.get("hss_rig", fidelity="kloss"), models.get("hss_rig", fidelity="linear")
    point = {"coupling_asymmetry": 0.0}
    steady = linear.simulate(SCENE, point)
    p = kloss.resolve(point).iloc[0].to_dict()
    rig, drive, spin = kloss.build(p, SCENE)
    sag = kloss.initial_state(rig, p)
    amplitude = 0.5 * np.ptp(steady["disk_y"])
    for start, most in ((kloss.periodic_state(rig, *sag, spin), 0.01), (sag, None)):
        run = genalpha.simulate(rig.system, 0.2, 2e-4, q0=start[0], qd0=start[1], output_every=1)
        disk = np.array([rig.system.marker_state(rig.markers["disk"], q, qd, t).r[1]
                         for t, q, qd in zip(run.t, run.q, run.qd)])
        ref = np.interp(run.t, steady.index.to_numpy(), steady["disk_y"].to_numpy())
        error = np.abs(disk - ref).max() / amplitude
        assert error < most if most else error > 0.5, error


def test_campbell_whirl_agrees_with_the_gyroscopic_split():
    """The disk-tilt pair splits with speed (gyroscopic): the branch whose frequency rises must
    orbit forward, the falling one backward (whirl read from the non-rotating mode shapes)."""
    model = models.get("hss_rig", fidelity="linear")
    spin = 3000.0 * np.pi / 30.0
    frame = model.campbell([0.0, spin], orders=(1.0, 2.0)).to_frame()
    still, fast = frame[frame["speed_rad_s"] == 0.0], frame[frame["speed_rad_s"] == spin]
    assert still["frequency_hz"].max() < 150.0 and (still["whirl"] != "forward").all()
    tilt = fast[fast["frequency_hz"].between(80.0, 160.0) & fast["whirl"].isin(["forward", "backward"])]
    low, high = tilt.nsmallest(1, "frequency_hz").iloc[0], tilt.nlargest(1, "frequency_hz").iloc[0]
    base = still[still["frequency_hz"].between(115.0, 130.0)]["frequency_hz"]      # the pair at standstill
    assert low["whirl"] == "backward" and low["frequency_hz"] < base.min()
    assert high["whirl"] == "forward" and high["frequency_hz"] > base.max()


def test_compiled_spin_linearisation_is_the_python_one_within_its_own_step_noise():
    """The compiled central differences (:func:`ddgsa.mbs.nonrotating._hybrid_jacobian`) against the
    same differences through ``system.terms`` (``compiled=False``), on the spinning rig about its sag.

    ``K`` agrees to round-off; ``C`` (velocity steps of 1e-9 against residuals of ~100 N) carries the
    differences' round-off noise, which differs between the two summation orders: the compiled ``C``
    must lie closer to the Python one than the Python one at twice the step lies to itself, i.e.
    within the reference's own finite-difference noise (the outputs that read it, the motor torque's
    1e-6 ripple above all, move by as much when the reference's step changes; docs/hss_rig.md, Cost).
    """
    from ddgsa.mbs import nonrotating

    model = models.get("hss_rig", fidelity="linear")
    p = model.effective(model.resolve({"eccentric_mass": 0.01}).iloc[0].to_dict())
    rig, _, _ = model.build(p, SCENE)
    q0, qd0 = model.initial_state(rig, p)
    fast = nonrotating.linearise(rig.system, q0, qd0)
    ref = nonrotating.linearise(rig.system, q0, qd0, compiled=False)
    ref2 = nonrotating.linearise(rig.system, q0, qd0, compiled=False, rel_step=2e-6)
    assert np.linalg.norm(fast.k - ref.k) <= 1e-12 * np.linalg.norm(ref.k)
    assert np.array_equal(fast.m, ref.m) and np.array_equal(fast.r0, ref.r0)
    noise = np.linalg.norm(ref2.c - ref.c)
    assert 0.0 < np.linalg.norm(fast.c - ref.c) < noise < 1e-6 * np.linalg.norm(ref.c)


def test_static_linearisation_of_the_rig_at_rest_is_the_full_ones_stiffness():
    """``linearise_system(static=True)`` (the sag's: ``K`` alone, the packed part through
    ``central_jacobian``) against the full compiled linearisation (``K`` and ``C`` in one compiled
    loop) and the Python one through ``System.terms``, on the rig at rest: the same ``K`` to
    round-off, ``C`` left at zero, the same ``r0``."""
    from ddgsa.mbs import linearise_system
    from ddgsa.models.hss_rig.rig import build

    model = models.get("hss_rig", fidelity="linear")
    p = model.resolve({"eccentric_mass": 0.0}).iloc[0].to_dict()
    system = build(p, lambda marker: ([], []), spin=0.0, basis=model.basis).system
    packed = system.fast_terms.packed
    static = linearise_system(system, compiled=packed, static=True)
    full = linearise_system(system, compiled=packed)
    python = linearise_system(system)
    for ref in (full, python):
        assert np.linalg.norm(static.k - ref.k) <= 1e-12 * np.linalg.norm(ref.k)
        np.testing.assert_allclose(static.r0, ref.r0, rtol=1e-12, atol=1e-12 * np.abs(ref.r0).max())
    assert not np.any(static.c) and np.any(full.c)


def test_motor_torque_ripple_is_not_round_off() -> None:
    """The steady linear rig's smallest outputs (2f torque ripple 2e-7 N m, current sideband, RMS motor
    torque, 900 rpm) move by less than 5e-6 relative when every parameter is nudged by 4 ulp, a change
    no physics sees: the non-rotating linearisation differences the rates with a 1e-6 step
    (:data:`ddgsa.mbs.nonrotating.VELOCITY_SCALE`; measured <= 8.6e-7), where a 1e-9 step moved them by
    up to 5.6e-5 (its round-off)."""
    import warnings

    import pandas as pd

    scene = RigScene("steady", speed_rpm=900.0, duration=0.7, sample_rate=2000.0, settle=0.05)
    model = models.get("hss_rig", fidelity="linear")
    nom = model.nominal
    eps = 4 * np.finfo(float).eps
    points = pd.DataFrame([nom, {k: v * (1 + eps) for k, v in nom.items()}, {k: v * (1 - eps) for k, v in nom.items()}])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = model.evaluate(points, scene)[["torque_2f", "current_sideband_2s", "rms_motor_torque"]]
    assert float((out.iloc[1:] / out.iloc[0] - 1).abs().max().max()) < 5e-6
