"""The linear fidelity's steady scene for a block of points at once (issue 46).

Per point the kernel does what only it can, on one rig a point: the rig without its turning loads
(:func:`~ddgsa.models.hss_rig.rig.build` with no eccentric mass: the per-point path's rig for the
coupling's stretch), its gravity sag standing still with its motor off (:func:`_at_rest`: the per-point
path's :func:`~ddgsa.models.hss_rig.model.still_rig` on the same System, from the kernel's tangents alone
where no element is loaded at rest), the coupling's static stretch on it by a chord iteration whose tangent
is the stiffness of the linearisation below, at the sag and speed (:func:`~ddgsa.models.hss_rig.faults.operating_stretch`:
one residual a step instead of a linearisation a step, the first step's residual the linearisation's own; the
stiffness at rest the sag was solved with is no tangent for it: with a 0.5 mm parallel misalignment its chord
settled on a stretch whose tilt about y was 0.5 % of the Newton iteration's, the housings' 2x orders 10 % low,
``test_misaligned_points_agree_with_the_per_point_path``), that rig
linearised once in non-rotating coordinates
about its sag (:func:`ddgsa.mbs.nonrotating.linearise`; about the undeformed rig the unbalance would put
no 1x torque on the shaft, whose sagged disk it turns about; it takes the columns of
:func:`~ddgsa.models.hss_rig.rig.tangent_columns` from the kernel's tangents and differences the other
half of ``K``; ``C`` whole from the kernel's exact form, ``damping_tangents``: tangents, the bodies' rate slopes and
the map's rate terms, no residual call), the inputs of one revolution taken at :data:`FORCE_SAMPLES` angles -- the motor's and the turning
loads (the unbalance, the coupling's 2x load tabulated at those angles), which are elements on the rig's
markers but not among its parts (:func:`ddgsa.mbs.nonrotating.projected_inputs`, the motor's relative to its
value in the linearisation's ``r0``, the loads absolute, in one evaluation of their markers): one rig built a point,
not two, and their tangents (``m e w^2``, 1e-6 of the bearings' stiffness) left out of the
linearisation -- and the disk probe mapped linearly onto the coordinates. Then the block goes together:
one stacked eigenvalue call (:func:`ddgsa.mbs.nonrotating.first_order_eigenvalues`) for the stability and
on-mode check (:func:`ddgsa.mbs.nonrotating.harmonic_validity`), one stacked harmonic solve
(:func:`ddgsa.mbs.nonrotating.harmonic_response`), the sensors' records synthesised from their harmonics
(:func:`ddgsa.mbs.nonrotating.synthesis`) at the record's times and, for the order domain, at the uniform shaft
angles the per-point path resamples to (:func:`ddgsa.models.signals.angle_samples`: exact where it interpolates
a cubic spline, the angle being the rigid spin; the vibration sensors, while the motor's torque and current
are resampled from their records as there), and the outputs of all records by one run of each signal
operation (:func:`~ddgsa.models.hss_rig.model.record_objectives`). The rig's control features (the 1x order
over its lowest lateral natural frequencies, :meth:`HssRig.control_features`) come from each point's
linearisation (:func:`ddgsa.mbs.nonrotating.lateral_frequencies`, on the check's eigenvalues: the shapes of
the few lowest by inverse iteration).

It holds where :meth:`HssRig._linear_run` solves in the frequency domain: the ``linear`` fidelity, a
steady scene, no supply unbalance and no defect (every input repeats once per revolution), no
measurement noise. The records of a block share their shaft angle: the rigid spin ``spin t`` (the
torsional vibration's angle modulation, below 1e-5 rad, is left out of the order domain). The anti-alias
low-pass the per-point path applies before resampling (at 51 orders, above the record's Nyquist frequency at
2 kHz) passes the block's 7 harmonics unchanged, so the order domain's records are the synthesis at any rate
(at 5 kHz, where that filter acts, every output of 4 points of each paper A study agreed with the per-point
path within 1e-3 or its resolution, as at 2 kHz). A point
whose linearisation is unstable, whose orders lie on an undamped mode, or whose coupling vibrates at 2x
beyond :data:`~ddgsa.models.hss_rig.faults.MAX_VIBRATION_RATIO` of its stretch is a failure with that
reason; the per-point path (:meth:`HssRig._evaluate_one`) is the check of the rest
(``tests/models/test_hss_rig_block.py``: every output within 1e-3 or its declared resolution on 64 points
of each paper A study, the issue asking 1 %).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ddgsa.mbs import nonrotating
from ddgsa.mbs.compiled import evaluate, pack
from ddgsa.mbs.elements import EccentricMass, Element
from ddgsa.mbs.modal import linearise_system
from ddgsa.models import signals
from ddgsa.models.hss_rig.drive import Drive, drive_for, kloss_along, kloss_parts, steady_speed
from ddgsa.models.hss_rig.faults import anisotropy_loads, check_small, operating_stretch
from ddgsa.models.hss_rig.parameters import RATED_SPEED
from ddgsa.models.hss_rig.rig import Rig, build, tangent_columns
from ddgsa.models.hss_rig.scenes import RigScene

if TYPE_CHECKING:
    from ddgsa.models.base import Model as HssRig      # the rig model; its module imports this one

Array = NDArray[np.float64]

FORCE_SAMPLES = 16
"""Samples of one revolution the block's inputs are taken at (harmonics up to 7), the coupling's 2x load
tabulated at these angles (its table read at its nodes). They hold every harmonic of the inputs: 128 samples
with the load tabulated 8x finer give the same outputs within 1e-13 (``tests/models/test_hss_rig_block.py``).
The per-point path (:func:`ddgsa.mbs.nonrotating.periodic`) reads 64 samples of that load tabulated at the
record's rate: its linear interpolation's error, 1e-6 of the forces, aliases to orders 16-22, which the
accelerometers weigh by their frequency squared (the housings' peaks move by up to 10 %, within their
resolution), and the numerically zero bearing bands (1e-12 to 1e-8) are made of it."""
CHECK_SAMPLES = 16
"""Samples of one revolution the coupling's 2x check (:func:`~ddgsa.models.hss_rig.faults.check_small`)
reads: its fit of the mean, 1x, 2x and 3x is exact on them for a periodic response."""
COORDS = ("housing_1.y", "housing_1.z", "housing_2.y", "housing_2.z", "motor.rx", "hss.rx")
"""Coordinates the sensors read directly (rates: accelerometers, motor speed; angle and speed of the shaft)."""

def holds(model: "HssRig", params: pd.DataFrame, scene: RigScene, signals: tuple[str, ...]) -> NDArray[np.bool_]:
    """Which rows of the resolved ``params`` the block path takes (see the module)."""
    if model.fidelity != "linear" or scene.kind != "steady" or signals or model.noise:
        return np.zeros(len(params), dtype=bool)
    return ((params["supply_unbalance"] == 0.0) & (params["defect_amplitude"] == 0.0)).to_numpy()


@dataclass
class _Point:
    """One point's linear rig: its matrices, input harmonics and the sensors' map onto its coordinates."""

    raw: dict[str, float]
    rig: Rig
    drive: Drive
    spin: float
    lin: nonrotating.SpinLinearisation
    f_hat: NDArray[np.complex128]
    sensors: Array
    """(8, n): rows ``COORDS`` (unit rows) and the disk's y and z [m per coordinate unit]."""
    disk0: Array
    """(2,) the disk centre's y and z [m] on the operating trajectory (z = 0)."""


def _at_rest(model: "HssRig", rig: Rig, plain: dict[str, float]) -> tuple[Array, Array]:
    """The gravity sag (n,) [m, rad, coordinate units] of the loaded ``rig`` (parameters ``plain``, no turning
    loads) standing still with its motor off, and the stiffness (n, n) it is solved with: the per-point path's
    :func:`~ddgsa.models.hss_rig.model.still_rig` on this rig's own System, without a second build.

    The rig is packed without its motor (:func:`ddgsa.mbs.compiled.pack`) and taken at its undeformed state at
    rest. Where no element carries a load there (every wrench zero: no misalignment), the elements add no
    geometric terms and the stiffness is the kernel's tangents alone (:func:`~ddgsa.mbs.modal.linearise_system`
    with every column a tangent: one evaluation instead of 21 differenced columns' 42 residuals). Checked against
    the per-point path's all-differenced still rig (``tests/models/test_hss_rig_block.py``): every column within
    1e-6 of its largest entry (measured 8e-9, the differences' noise), the sag within 1e-9 of its largest entry
    (measured 6e-11). A loaded coupling (misaligned) takes :func:`still_rig` with half its columns differenced,
    as before: its preload's geometric terms, which the tangents leave out, move the shaft's sag by up to 6x."""
    still_rig, still_key = (model.block_parts[k] for k in ("still_rig", "still_key"))
    system = rig.system
    packed = pack(system, [e for e in system.elements if e.name != "motor"])
    rest = np.zeros(system.n)
    if np.any(evaluate(packed, system.q0, rest, 0.0)[4]):
        sag, k = still_rig(still_key(plain), model.basis, True)
        return sag, k
    lin = linearise_system(system, system.q0, rest, compiled=packed, static=True, tangent_columns=np.arange(system.n))
    return np.linalg.lstsq(lin.k, lin.r0, rcond=None)[0], lin.k


def _linearised(model: "HssRig", raw: dict[str, float], scene: RigScene) -> _Point:
    """The kernel's part of one point (see the module)."""
    pole_pairs = model.block_parts["pole_pairs"]
    drive = drive_for(raw, scene, pole_pairs)
    spin = steady_speed(drive, raw["load_torque"], raw["load_speed_exponent"], RATED_SPEED)
    # the rig without its turning loads (the per-point path's rig for the coupling's stretch): they are
    # inputs, projected along the trajectory below; their tangents (m e w^2 against the bearings' 5e7 N/m) are not kept
    plain = {**model.effective(raw), "eccentric_mass": 0.0}
    rig = build(plain, kloss_parts(drive), spin=spin, basis=model.basis)
    system = rig.system
    sag = _at_rest(model, rig, plain)[0]
    q0, qd0 = system.q0.copy(), system.qd0.copy()
    q0 += sag
    lin = nonrotating.linearise(system, q0, qd0, tangent_columns=tangent_columns(system), damping_tangents=True)
    if raw["coupling_asymmetry"] > 0.0:       # a chord on this linearisation's stiffness, from its residual
        stretch = operating_stretch(rig, q0, qd0, tangent=lin.k, start=lin)
    period = 2 * math.pi / spin
    loads: list[Element] = [EccentricMass(rig.markers["disk"], raw["eccentric_mass"], raw["eccentric_radius"])]
    if raw["coupling_asymmetry"] > 0.0:       # tabulated at the input angles themselves: read at its nodes
        loads += anisotropy_loads(raw, stretch, spin, period, period / FORCE_SAMPLES)(rig.markers)
    tp = lin.t0 + period * np.arange(FORCE_SAMPLES) / FORCE_SAMPLES
    motor = [e for e in system.elements if e.name == "motor"]
    relative = [True] * len(motor) + [False] * len(loads)
    forces = nonrotating.projected_inputs(system, lin, tp, motor + loads, relative) + lin.r0
    f_hat = nonrotating.input_harmonics(forces)
    # the disk probe: its marker's position Jacobian (the first rows of its velocity Jacobian: the kernel's
    # coordinates are positions, their rates the velocities) through the map's T = dq/dz at the operating point
    disk = system.states_of([rig.markers["disk"]], lin.q0, lin.qd0, lin.t0)[0]
    n = system.n
    rows = np.zeros((len(COORDS), n))
    rows[np.arange(len(COORDS)), [system.index(c) for c in COORDS]] = 1.0
    slope = disk.jac[1:3] @ lin.projection(lin.t0)
    return _Point(raw, rig, drive, spin, lin, f_hat, np.vstack([rows, slope]), disk.r[1:].copy())


def steady_block(model: "HssRig", params: pd.DataFrame, scene: RigScene) -> pd.DataFrame:
    """Outputs of the rows of ``params`` (resolved, all :func:`holds`) in a steady ``scene``; failures with their
    reasons in ``attrs["failures"]`` (see the module)."""
    failures: dict[int, str] = {}
    points: dict[int, _Point] = {}
    for i, raw in enumerate(params.to_dict("records")):
        try:
            points[i] = _linearised(model, raw, scene)
        except (ArithmeticError, RuntimeError, ValueError, np.linalg.LinAlgError) as exc:
            failures[i] = f"{type(exc).__name__}: {exc}"
    outputs: dict[int, dict[str, float]] = {}
    by_spin: dict[float, list[int]] = {}
    for i, pt in points.items():
        by_spin.setdefault(pt.spin, []).append(i)
    eigenvalues: dict[int, NDArray[np.complex128]] = {}
    for spin, idx in by_spin.items():
        done, bad, lam = _solve_group(model, [points[i] for i in idx], scene, spin)
        outputs.update({idx[j]: out for j, out in done.items()})
        failures.update({idx[j]: why for j, why in bad.items()})
        eigenvalues.update(zip(idx, lam))
    names = [str(o) for o in model.outputs]
    nan = {o: math.nan for o in names}
    out = pd.DataFrame([outputs.get(i, nan) for i in range(len(params))], columns=names)
    out.attrs["failures"] = failures
    features = [str(f) for f in model.control_features(scene)]
    if not features:
        return out
    values = np.full((len(params), len(features)), math.nan)
    for i in outputs:                     # the control features of each point's own linearisation
        pt = points[i]
        values[i] = pt.spin / nonrotating.lateral_frequencies(pt.rig.system, pt.lin, len(features), eigenvalues[i])
    out.attrs["features"] = {f: tuple(values[:, j].tolist()) for j, f in enumerate(features)}
    return out


def _solve_group(model: "HssRig", pts: list[_Point], scene: RigScene,
                 spin: float) -> tuple[dict[int, dict[str, float]], dict[int, str], NDArray[np.complex128]]:
    """Outputs (by position in ``pts``) and failures of points sharing their ``spin`` [rad/s], and the
    eigenvalues (P, 2n) of their first-order systems (the validity's, reused by the control features)."""
    record_objectives = model.block_parts["record_objectives"]
    m, c, k = (np.stack([getattr(pt.lin, a) for pt in pts]) for a in ("m", "c", "k"))
    f_hat = np.stack([pt.f_hat for pt in pts])
    lam = nonrotating.first_order_eigenvalues(m, c, k)
    why = nonrotating.harmonic_validity(m, c, k, spin, f_hat.shape[1] - 1, scene.duration, lam)
    z0, z_hat = nonrotating.harmonic_response(m, c, k, f_hat, spin)
    bad: dict[int, str] = {}
    period = 2 * math.pi / spin
    t_check = period * np.arange(CHECK_SAMPLES) / CHECK_SAMPLES
    for j, pt in enumerate(pts):
        if why[j] is None and pt.raw["coupling_asymmetry"] > 0.0:
            z, zd = nonrotating.synthesis(t_check, spin, z_hat[j])
            q = nonrotating.full_states(pt.lin, pt.lin.t0 + t_check, z0[j] + z, zd)[0]
            try:
                check_small(pt.rig, q, pt.lin.t0 + t_check, spin)
            except ValueError as exc:
                why[j] = f"{type(exc).__name__}: {exc}"
        if why[j] is not None:
            bad[j] = why[j]
    ok = [j for j in range(len(pts)) if j not in bad]
    if not ok:
        return {}, bad, lam
    t0 = pts[0].lin.t0
    dt = 1.0 / scene.sample_rate
    times = t0 + dt * np.arange(int(round(scene.duration / dt)) + 1)
    keep = times >= scene.settle - 1e-12
    g = np.stack([pts[j].sensors for j in ok])                                   # (P, 8, n)
    y_hat = np.einsum("psn,pjn->pjs", g, z_hat[ok])
    y, yd = nonrotating.synthesis(times - t0, spin, y_hat)                       # (P, n_t, 8)
    # the accelerometers as the per-point path takes them: second-order differences of the housings' rates
    acc = np.gradient(yd[:, :, :4], times, axis=1, edge_order=2)[:, keep]       # (the rates' constant part drops)
    kept = [pts[j] for j in ok]
    xs = _sensor_records(kept, z0[ok], times[keep], y[:, keep], yd[:, keep], acc)           # (P, n_t, 8)
    angle = pts[0].lin.q0[pts[0].rig.system.index("hss.rx")] + spin * (times[keep] - t0)
    # the order domain: the vibration sensors at uniform shaft angles are their harmonics there (the angle is
    # the rigid spin), the accelerometers' central differences of the rates, exact on a harmonic, as the factor
    # i sin(j W dt) / dt on its rate's harmonic (the time records' interior samples to round-off); the motor's
    # torque and current (nonlinear in the speed, the current at the supply's frequency) resampled from their
    # records as the per-point path does: a third of the cost of the motor's law at the angles
    per_rev = model.block_parts["samples_per_rev"]
    phi = signals.angle_samples(angle, per_rev)
    t_phi = times[keep][0] + phi / spin - t0
    jw = spin * np.arange(1, y_hat.shape[1] + 1)[:, None]
    xa = np.empty((len(ok), phi.size, xs.shape[2]))
    xa[:, :, :4] = nonrotating.synthesis(t_phi, spin, -jw * np.sin(jw * dt) / dt * y_hat[:, :, :4])[0]
    xa[:, :, 4:6] = _disk(kept, z0[ok], nonrotating.synthesis(t_phi, spin, y_hat[:, :, 6:])[0])
    motor = xs[:, :, 6:].transpose(1, 0, 2).reshape(len(angle), -1)
    xa[:, :, 6:] = signals.resample_to_angle(times[keep], motor, angle, per_rev)[1].reshape(
        phi.size, len(ok), 2).transpose(1, 0, 2)
    outs = record_objectives(times[keep], xs.transpose(1, 0, 2), angle, spin / (2 * math.pi), scene, pts[ok[0]].drive,
                             xa.transpose(1, 0, 2))
    return dict(zip(ok, outs)), bad, lam


def _sensor_records(pts: list[_Point], z0: Array, times: Array, y: Array, yd: Array, acc: Array) -> Array:
    """The sensors' records (P, n_t, 8) in :data:`~ddgsa.models.hss_rig.model.SENSORS` order at ``times`` [s]
    of points ``pts`` from their static parts ``z0`` (P, n), the periodic parts of the sensed coordinates and
    the disk's position ``y`` and their rates ``yd`` (P, n_t, 8) (:data:`COORDS`, then the disk's y and z), and
    the accelerometers ``acc`` (P, n_t, 4)."""
    motor = COORDS.index("motor.rx")
    xs = np.empty(y.shape)
    xs[:, :, :4] = acc
    xs[:, :, 4:6] = _disk(pts, z0, y[:, :, 6:])
    for r, pt in enumerate(pts):
        speed = pt.lin.qd0[pt.rig.system.index("motor.rx")] + yd[r, :, motor]
        xs[r, :, 6], xs[r, :, 7] = kloss_along(pt.drive, times, speed)
    return xs


def _disk(pts: list[_Point], z0: Array, y: Array) -> Array:
    """The disk probe's y and z (P, n_t, 2) [m] of points ``pts`` from their static parts ``z0`` (P, n) and
    the periodic parts ``y`` (P, n_t, 2) of its position."""
    return np.stack([pt.disk0 + pt.sensors[6:] @ z for pt, z in zip(pts, z0)])[:, None, :] + y
