"""The linear fidelity's start-up and coast-down for a block of points (issue 46, item 3).

Each point's speed sweep (:mod:`~ddgsa.models.hss_rig.transient`) is prepared as the per-point path prepares
it, with the steady block path's savings (:mod:`~ddgsa.models.hss_rig.steady_block`): one rig built a point
(the bare rig of the sweep, whose coordinates and sensor markers are the full rig's), the sag on the still
rig's stiffness from the kernel's tangents (``initial_state(..., tangents=True)``: every column where nothing
is loaded at rest; formed on the bare rig with the coupling's anisotropy added, :func:`_sagged`: no second
build), the sweep's two linearisations with :func:`~ddgsa.models.hss_rig.rig.tangent_columns`
from the tangents and the whole damping matrix without differences (``damping_tangents``: exact at rest and at
speed). The sweep model is reduced
to the scene's band (:func:`ddgsa.mbs.sweep.reduce`: the rigid spin and the undamped modes at rest up to
:func:`band_hz`, the inputs' rows mapped onto that basis) and integrated by the kernel's generalised-alpha
with its factors kept across steps and an extrapolating predictor (:func:`ddgsa.mbs.sweep.integrate`'s
``reuse`` and ``extrapolate``: the same states to the iteration's tolerance), its residual's linear part carried
along each step's Newton corrections as rows' dot products the compiler may reorder (``incremental``: the kernel
loop's iterates to round-off, 2.2x faster). The sensors are read from the
coordinates they need (the housings' rates differenced as the per-point records are, the disk probe through
its linear map onto the non-rotating coordinates at the sag: its marker's velocity rows) and the outputs of all
the block's records come from one call of :func:`~ddgsa.models.hss_rig.model.record_objectives` (one shaft
angle and speed per record).

It holds where :meth:`HssRig._simulate` runs the sweep: the ``linear`` fidelity, a start-up or coast-down, no
misalignment (which the per-point path refuses in transients: those points go that way and fail there with its
reason), no measurement noise, no signals. A point whose preparation or integration fails (a linear solve, the
coast-down's steady orbit, a step that does not converge or leaves the finite numbers) or whose outputs are
not finite is a failure with that reason in ``attrs["failures"]``, never a number. The per-point path is the
check (``tests/models/test_hss_rig_sweep_block.py``: every output within 5e-3 or its declared resolution on
16 points of each paper A study, measured 1.1e-3).
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from ddgsa.errors import ModelError
from ddgsa.mbs.compiled import evaluate
from ddgsa.mbs.sweep import SweepModel, integrate, marker_rows
from ddgsa.models.hss_rig.drive import Drive, kloss_along
from ddgsa.models.hss_rig import transient
from ddgsa.models.hss_rig.rig import Rig
from ddgsa.models.hss_rig.scenes import RigScene
from ddgsa.models.hss_rig.steady_block import COORDS

if TYPE_CHECKING:
    from ddgsa.models.base import Model as HssRig      # the rig model; its module imports this one

NYQUIST_MULTIPLE = 2.5
"""The band the block's sweeps keep, in multiples of the record's Nyquist frequency (:func:`band_hz`)."""
Array = NDArray[np.float64]
_ERRORS = (ArithmeticError, RuntimeError, ValueError, np.linalg.LinAlgError)
"""What a point's run may raise that makes it a failure (as :meth:`Model._evaluate_block`'s loop catches)."""
REUSE = 3
"""Newton iterations a step may take before the sweep's factors are refreshed (:func:`ddgsa.mbs.sweep.integrate`):
the rig's steps take two or three with fresh factors, and as many with factors kept across steps (7067 against
7085 iterations a 1.2 s start-up at the nominal point), which are refreshed a few times a run."""


def band_hz(scene: RigScene) -> float:
    """The band [Hz] the block's sweeps keep: :data:`NYQUIST_MULTIPLE` times the record's Nyquist frequency.

    The accelerometers' records read the housings' resonances up to the Nyquist frequency (their envelope band
    reaches 0.45 of the sample rate), above what the model's basis rule names (its sampling checks, up to
    3 x BPFI, times :data:`~ddgsa.models.base.BAND_FACTOR`: 609 Hz at 1500 rpm, 26 of the rig's 42 modes, which
    moves the first housing's RMS by 22 %), and the modes just above it still add their quasi-static part:
    measured at 2 kHz on 4 points of ``paper_a_subsystem`` against the per-point path, the housings' RMS and 2x
    orders move by 1.6 % at 1.5x the Nyquist frequency (34 modes, up to 968 Hz), 8e-4 at 2.5x (37 modes, the
    next at 2539 Hz), 6e-5 unreduced (the tangent columns' and the kept factors' share)."""
    return NYQUIST_MULTIPLE * 0.5 * scene.sample_rate


def holds(model: "HssRig", params: pd.DataFrame, scene: RigScene, signals: tuple[str, ...]) -> NDArray[np.bool_]:
    """Which rows of the resolved ``params`` the block path takes (see the module)."""
    if model.fidelity != "linear" or scene.kind == "steady" or signals or model.noise:
        return np.zeros(len(params), dtype=bool)
    return ((params["misalignment_parallel"] == 0.0) & (params["misalignment_angular"] == 0.0)).to_numpy()


def sweep_block(model: "HssRig", params: pd.DataFrame, scene: RigScene) -> pd.DataFrame:
    """Outputs of the rows of ``params`` (resolved, all :func:`holds`) in a start-up or coast-down ``scene``;
    failures with their reasons in ``attrs["failures"]`` (see the module)."""
    record_objectives = model.block_parts["record_objectives"]
    names = [str(o) for o in model.outputs]
    band = band_hz(scene)
    step, every = model.step_for(1.0 / scene.sample_rate)
    records: dict[int, tuple[Array, Array, float]] = {}
    features: dict[int, dict[str, float]] = {}
    failures: dict[int, str] = {}
    drive = None
    t = np.zeros(0)
    names_in = list(params.columns)
    for i, values in enumerate(params.to_numpy().tolist()):           # (DataFrame.to_dict: 1 ms a row)
        raw = dict(zip(names_in, values))
        try:
            drive, spin = model.drive(raw, scene)
            rig = transient.bare_rig(raw, transient.synchronous_speed(drive), model.basis)   # its coordinates
            q0 = _sagged(model, rig, raw)                                    # and sensors are the full rig's
            sweep = transient.prepare(drive, raw, q0, scene.kind, spin, model.basis, band_hz=band, tangents=True,
                                      bare=rig)
            t, z, zd = integrate(sweep.model, scene.duration, step, sweep.z0, sweep.zd0, sweep.inputs, every,
                                 reuse=REUSE, extrapolate=True, incremental=True)
            xs, angle, f_r, end_speed = _sensors(model, rig, drive, sweep.model, t, z, zd)
            records[i] = (xs, angle, f_r)
            features[i] = model.block_parts["sweep_features"](drive, sweep.lateral, end_speed)
        except _ERRORS as exc:
            failures[i] = f"{type(exc).__name__}: {exc}"
    outputs: dict[int, dict[str, float]] = {}

    def objectives_of(idx: list[int]) -> None:
        """The outputs of the points ``idx`` at once; where that fails (a record too short for a band), each on its
        own, as the per-point path, so that only the failing points are failures."""
        try:
            outputs.update(zip(idx, _objectives(record_objectives, records, idx, t, scene, drive)))
        except _ERRORS as exc:
            if len(idx) == 1:
                failures[idx[0]] = f"{type(exc).__name__}: {exc}"
            else:
                for i in idx:
                    objectives_of([i])

    if records:
        objectives_of(list(records))
    for i, out in list(outputs.items()):
        if not all(math.isfinite(v) for v in out.values()):
            del outputs[i]
            failures[i] = f"{ModelError.__name__}: sweep block: an output is not finite"
    nan = {o: math.nan for o in names}
    out = pd.DataFrame([outputs.get(i, nan) for i in range(len(params))], columns=names)
    out.attrs["failures"] = dict(sorted(failures.items()))
    names_f = [str(f) for f in model.control_features(scene)]
    if names_f:                     # the per-point path's features, NaN where a point failed
        out.attrs["features"] = {f: tuple(features[i][f] if i in outputs else math.nan for i in range(len(params)))
                                 for f in names_f}
    return out


def _sagged(model: "HssRig", rig: Rig, raw: dict[str, float]) -> Array:
    """The positions (n,) at the gravity sag of the rig of parameters ``raw`` standing still with its motor off:
    :meth:`HssRig.initial_state`'s (``tangents=True``: :func:`~ddgsa.models.hss_rig.model.still_rig`'s), solved
    on the sweep's bare ``rig`` without building the still rig.

    The still rig is the bare rig with the coupling's anisotropy standing at hub angle 0 and the load law, which
    puts no torque and no stiffness on the rig at rest. Where no element carries a load at rest (every wrench
    zero: no misalignment) and every part is compiled, the still rig's stiffness is the kernel's tangents alone,
    so it is the bare rig's tangents plus the anisotropy's ``J^T dK J`` (``J`` the coupling's relative marker
    Jacobian, hub and shaft end at one point; ``dK`` the lateral and angular pairs' ``+-asymmetry`` of
    :class:`~ddgsa.models.hss_rig.elements.MisalignedCoupling`, in the hub's frame, the global one at rest), and
    the static force is the bare rig's (measured on 4 ``paper_a_structural`` points: stiffness within 2e-17, sag
    within 4e-13 of the still rig's). Otherwise the still rig is built (:meth:`HssRig.initial_state`)."""
    system = rig.system
    rest = np.zeros(system.n)
    _, force, stiffness, _, loads, *_ = evaluate(system.fast_terms.packed, system.q0, rest, 0.0)
    if system.fast_terms.python or np.any(loads):
        return model.initial_state(rig, raw, tangents=True)[0]
    jac = (system.marker_state(rig.markers["coupling"], system.q0, rest, 0.0).jac
           - system.marker_state(rig.markers["hub"], system.q0, rest, 0.0).jac)
    a, kr, ka = raw["coupling_asymmetry"], raw["coupling_radial_stiffness"], raw["coupling_angular_stiffness"]
    dk = np.array([0.0, a * kr, -a * kr, 0.0, a * ka, -a * ka])
    return system.q0 + np.linalg.lstsq(stiffness + jac.T @ (dk[:, None] * jac), force, rcond=None)[0]


def _objectives(record_objectives, records: dict[int, tuple[Array, Array, float]], idx: list[int], t: Array,
                scene: RigScene, drive: Drive) -> list[dict[str, float]]:
    """:func:`~ddgsa.models.hss_rig.model.record_objectives` of the points ``idx``' records (sensors, angle, speed)."""
    xs, angle, f_r = (np.stack([records[i][k] for i in idx], axis=-1) for k in range(3))
    return record_objectives(t, xs.transpose(0, 2, 1), angle, f_r, scene, drive)


def _sensors(model: "HssRig", rig: Rig, drive: Drive, sweep: SweepModel, t: Array, z: Array,
             zd: Array) -> tuple[Array, Array, float, float]:
    """The sensors (n_t, len(SENSORS)), shaft angle [rad] (n_t,), mean shaft speed [Hz] and last shaft speed
    [rad/s] (the per-point path's ``speed`` at the record's end: the sweep features') of one point's record
    ``z``, ``zd`` (n_t, n_reduced) at ``t`` [s]: the per-point path's sensors (:meth:`HssRig._sensors`) read from
    the coordinates they need, the disk probe through its linear map onto the non-rotating coordinates at the
    sag (:func:`ddgsa.mbs.sweep.marker_rows`)."""
    sensors = model.block_parts["sensors"]
    system, lin, basis = rig.system, sweep.lin, sweep.basis
    rows = basis[[system.index(c) for c in COORDS]]                             # (6, n_reduced)
    y, yd = z @ rows.T, zd @ rows.T
    disk = rig.markers["disk"]
    # the disk centre's lateral velocity rows are its position's slope in the non-rotating coordinates (the
    # steady block differences the positions: the same within 2e-10 of the rows)
    slope = marker_rows(system, lin, disk)[1:3] @ basis                               # (2, n_reduced)
    centre = system.positions(disk, lin.q0[None, :], np.zeros((1, system.n)), np.full(1, lin.t0))[0, 1:]
    xs = np.empty((t.size, len(sensors)))
    xs[:, :4] = np.gradient(yd[:, :4], t, axis=0, edge_order=2)
    xs[:, 4:6] = centre + z @ slope.T
    speed = lin.qd0[system.index("hss.rx")] + yd[:, COORDS.index("hss.rx")]
    motor = lin.qd0[system.index("motor.rx")] + yd[:, COORDS.index("motor.rx")]
    xs[:, 6], xs[:, 7] = kloss_along(drive, t, motor)
    angle = lin.q0[system.index("hss.rx")] + y[:, COORDS.index("hss.rx")]
    return xs, angle, float(np.mean(speed)) / (2 * math.pi), float(speed[-1])
