"""Start-up and coast-down of the ``linear`` fidelity: the rig as a speed sweep (:mod:`ddgsa.mbs.sweep`).

The rig without its motor, load and eccentric mass, its coupling at its mean stiffness, is linear
about its static sag and axisymmetric: in the non-rotating bending coordinates its matrices
depend on the spin only through the gyroscopic term and a small spin softening. It is
linearised twice, at rest and spinning at the supply's synchronous speed (the fastest a scene
reaches), and run as the linear parameter-varying system of :func:`ddgsa.mbs.sweep.integrate`
with four nonlinear inputs evaluated at every iteration as the ``kloss`` rig's elements do:

* the ``kloss`` motor torque (:func:`~ddgsa.models.hss_rig.drive.kloss_torque_at`) at the motor
  rotor's spin, on its angle;
* the load torque law (:func:`~ddgsa.mbs.elements.power_torque`) at the disk's spin;
* the eccentric mass's centrifugal force ``m_u e W^2`` at the disk, along the disk's actual angle
  (its tangential part left out, as :class:`~ddgsa.mbs.elements.EccentricMass` does);
* the coupling's turning anisotropy ``dK(theta)`` (:func:`~ddgsa.models.hss_rig.faults.anisotropy`,
  the steady path's formulation) on the coupling's stretch along the sweep (:class:`_CouplingInput`):
  the 2x the gravity sag's lift of the overhang makes, and the anisotropy acting on the vibration.

A run starts from the sag of the rig with its anisotropic coupling standing at hub angle 0 (as
the nonlinear rig does); a coast-down from the periodic orbit at the steady speed
(:func:`ddgsa.mbs.sweep.steady_orbit`: the shafts wound up by the steady torque, the unbalance
orbit and the anisotropy's harmonics, the motor's and load's slopes damping the spin). Against
the nonlinear ``kloss`` rig by generalised-alpha the outputs agree to the tolerances
``tests/models/test_hss_rig_transient.py`` states. A misalignment would enter through the
stretch as well, but is refused in transients until it is checked against the nonlinear rig.
"""

from __future__ import annotations

import functools
import math
from collections.abc import Mapping
from dataclasses import dataclass

import numpy as np
from numba import njit
from numpy.typing import NDArray

from ddgsa.mbs import nonrotating
from ddgsa.mbs.elements import power_torque
from ddgsa.mbs.machines import induction_torque
from ddgsa.mbs.sweep import (Inputs, SweepModel, full_state, integrate, lateral_frequencies, marker_rows, reduce,
                             steady_orbit, sweep_model)
from ddgsa.models.hss_rig.drive import Drive, kloss_torque_at
from ddgsa.models.hss_rig.faults import anisotropy_constants, anisotropy_matrix, coupling_stretch
from ddgsa.models.hss_rig.rig import Rig, ShaftBasis, build, load_constants, load_law, tangent_columns

Array = NDArray[np.float64]
SLOPE_STEP = 1e-6
"""Relative speed step of the torque laws' slopes at the coast-down's operating point [-]."""


def synchronous_speed(drive: Drive) -> float:
    """The supply's synchronous speed [rad/s]: the sweep's reference spin (the fastest a scene reaches)."""
    return 2 * math.pi * drive.motor.supply_frequency / drive.motor.pole_pairs


def bare_rig(p: Mapping[str, float], synchronous: float, basis: ShaftBasis = ShaftBasis()) -> Rig:
    """The rig without motor, load and eccentric mass, with the coupling's mean stiffness, spinning at
    ``synchronous`` [rad/s] (:func:`structure`'s)."""
    return build({**p, "eccentric_mass": 0.0, "load_torque": 0.0, "coupling_asymmetry": 0.0},
                 lambda marker: ([], []), spin=synchronous, basis=basis)


def structure(p: Mapping[str, float], q0: Array, synchronous: float, basis: ShaftBasis = ShaftBasis(),
              tangents: bool = False, bare: Rig | None = None) -> tuple[Rig, SweepModel]:
    """The rig without motor, load and eccentric mass, with the coupling's mean stiffness
    (``coupling_asymmetry`` 0), and its sweep model about the sag ``q0`` (the positions of
    :meth:`HssRig.initial_state`) with reference spin ``synchronous`` [rad/s]. ``tangents``: both
    linearisations take :func:`~ddgsa.models.hss_rig.rig.tangent_columns` from the kernel's tangents (the
    block path's, as the steady one's; half the residual calls), and both their whole damping matrix without
    differences (``damping_tangents``: the tangents, the bodies' exact rate slopes and the map's rate terms).
    ``bare``: :func:`bare_rig`, built already."""
    bare = bare_rig(p, synchronous, basis) if bare is None else bare
    system = bare.system
    columns = tangent_columns(system) if tangents else ()
    rest = nonrotating.linearise(system, q0, np.zeros(system.n), tangent_columns=columns, damping_tangents=tangents)
    spinning = nonrotating.linearise(system, q0, system.qd0, tangent_columns=columns, damping_tangents=tangents)
    return bare, sweep_model(rest, spinning, system.index("hss.rx"), q0 - system.q0)


@dataclass
class Sweep:
    """One point's sweep, ready to integrate: its model (reduced or not), inputs and start."""

    bare: Rig
    model: SweepModel
    inputs: Inputs
    z0: Array
    zd0: Array
    lateral: float
    """The rig's lowest lateral natural frequency [rad/s] at the sweep's reference spin (the supply's synchronous
    speed), from the unreduced sweep model (:func:`ddgsa.mbs.sweep.lateral_frequencies`): its first lateral
    critical speed's neighbour, which the rig's sweep features compare speeds with."""


def prepare(drive: Drive, p: Mapping[str, float], q0: Array, kind: str, spin: float,
            basis: ShaftBasis = ShaftBasis(), band_hz: float | None = None, tangents: bool = False,
            bare: Rig | None = None) -> Sweep:
    """The sweep of a start-up (from rest) or coast-down (from ``spin`` [rad/s]) of the rig of parameters ``p``
    (see :func:`run`); ``band_hz`` [Hz]: on the model reduced to its modes up to that band
    (:func:`ddgsa.mbs.sweep.reduce`, the inputs' rows mapped onto its basis); ``tangents``, ``bare``: as
    :func:`structure`."""
    bare, model = structure(p, q0, synchronous_speed(drive), basis, tangents, bare)
    critical = float(lateral_frequencies(bare.system, model, synchronous_speed(drive), 1)[0])
    lin = model.lin
    if band_hz is not None:
        model = reduce(model, band_hz)
    onto = np.eye(lin.q0.size) if model.basis is None else model.basis
    motor = marker_rows(bare.system, lin, bare.markers["motor"])[3] @ onto
    disk_rows = marker_rows(bare.system, lin, bare.markers["disk"]) @ onto
    disk, lateral = disk_rows[3], disk_rows[1:3]
    me = p["eccentric_mass"] * p["eccentric_radius"]
    load = load_law(p)
    coupling = _CouplingInput(p, bare, model)
    inputs = Inputs(rig_inputs, (motor, disk, np.ascontiguousarray(lateral), float(me), drive.constants,
                                 load_constants(p), coupling.data))
    n = model.m.shape[0]
    if kind == "startup":
        z0, zd0 = np.zeros(n), np.zeros(n)
    else:
        def slope(law, w: float) -> float:
            h = SLOPE_STEP * max(1.0, abs(w))
            return (law(0.0, w + h) - law(0.0, w - h)) / (2 * h)

        motor_law = functools.partial(kloss_torque_at, drive)
        static = motor * motor_law(0.0, spin) + disk * load(0.0, spin)
        tangent = -slope(motor_law, spin) * np.outer(motor, motor) - slope(load, spin) * np.outer(disk, disk)
        once = me * spin * spin * (lateral[0] - 1j * lateral[1])
        z0, zd0 = steady_orbit(model, spin, static, once, tangent, disk, coupling if coupling.active else None)
    return Sweep(bare, model, inputs, z0, zd0, critical)


def run(drive: Drive, p: Mapping[str, float], q0: Array, kind: str, spin: float, t_end: float, dt: float,
        output_every: int, basis: ShaftBasis = ShaftBasis()) -> tuple[Array, Array, Array, float]:
    """Record ``(t, q, qd)`` of a start-up (from rest) or coast-down (from ``spin`` [rad/s]) of the
    rig of parameters ``p`` (in the coordinates of :func:`~ddgsa.models.hss_rig.rig.build`), and
    :attr:`Sweep.lateral` [rad/s].

    Parameters
    ----------
    drive : Drive
        The motor and supply of the scene.
    p : mapping
        The rig's parameters, the coupling's anisotropy and misalignment included (see the module).
    q0 : (n,)
        Positions at the static sag [m, rad] (of the rig with its anisotropic coupling standing at
        hub angle 0, as the nonlinear rig starts).
    kind : str
        ``startup`` or ``coastdown``.
    dt : float
        Generalised-alpha step [s]; ``output_every`` steps a sample.
    basis : ShaftBasis
        The high-speed shaft's modal basis.
    """
    sweep = prepare(drive, p, q0, kind, spin, basis)
    t, z, zd = integrate(sweep.model, t_end, dt, sweep.z0, sweep.zd0, sweep.inputs, output_every)
    q, qd = full_state(sweep.model, z, zd)
    return t, q, qd, sweep.lateral


@njit(cache=True, inline="always")
def rig_inputs(t, z, zd, data, f):  # pragma: no cover (compiled)
    """The sweep's four nonlinear inputs (see the module) added to ``f``: ``data`` is ``(motor row,
    disk row, lateral rows (2, n), m_u e [kg m], Drive.constants, load_constants, coupling data)``."""
    motor, disk, lateral, me, drive, law, coupling = data
    wm, wd, th = 0.0, 0.0, 0.0
    for i in range(z.size):
        wm += motor[i] * zd[i]
        wd += disk[i] * zd[i]
        th += disk[i] * z[i]                         # the mass starts along +y, as in the rig
    tm, tl = induction_torque(drive, t, wm), power_torque(law, wd)
    fy, fz = me * wd * wd * math.cos(th), me * wd * wd * math.sin(th)
    for i in range(z.size):
        f[i] += motor[i] * tm + disk[i] * tl + fy * lateral[0, i] + fz * lateral[1, i]
    coupling_force(z, coupling, f)


@njit(cache=True, inline="always")
def coupling_force(z, coupling, f):  # pragma: no cover (compiled)
    """:class:`_CouplingInput`'s force added to ``f``: ``-rows^T dK(theta) (s_sag + J z)`` with
    ``theta = angle @ z``; ``coupling`` is its :attr:`_CouplingInput.data`."""
    active, stiffness, rows, jac, sag, angle = coupling
    if not active:
        return
    theta = 0.0
    for i in range(z.size):
        theta += angle[i] * z[i]
    stretch = sag.copy()                             # s_sag + J z, in loops (no BLAS call an iteration)
    for k in range(6):
        for i in range(z.size):
            stretch[k] += jac[k, i] * z[i]
    dk = anisotropy_matrix(stiffness, theta)
    wrench = np.zeros(6)
    for k in range(6):
        for j in range(6):
            wrench[k] += dk[k, j] * stretch[j]
    for i in range(z.size):
        acc = 0.0
        for k in range(6):
            acc += rows[k, i] * wrench[k]
        f[i] -= acc


@njit(cache=True)
def coupling_forces(zs, coupling, out):  # pragma: no cover (compiled)
    """:func:`coupling_force` at each row of ``zs`` (m, n), added to the rows of ``out`` (m, n)."""
    for k in range(zs.shape[0]):
        coupling_force(zs[k], coupling, out[k])


class _CouplingInput:
    """The coupling's turning anisotropy as a nonlinear input of the sweep: ``f(z)`` (n,).

    The coupling's force on the hub is ``K(theta) s`` with ``K(theta) = K_mean + dK(theta)``
    (:func:`~ddgsa.models.hss_rig.faults.anisotropy`, ``theta`` the hub's spin angle) and ``s``
    its stretch (misalignment included); the sweep model holds ``K_mean s``. The input is the rest,
    ``+-dK(theta) s`` on the hub and the shaft end, with ``s = s_sag + J z`` the stretch at the sag
    (:func:`~ddgsa.models.hss_rig.faults.coupling_stretch`) plus its linear change with the
    state, so it carries the static stretch along the sweep (the gravity sag's lift of the
    overhang, the twist the torque winds up, the vibration) and the parametric term the steady
    path drops.

    ``J`` is the marker rows' difference (velocity rows) without its columns on the spin angles:
    a spinning hub or shaft tilted by the sag has an angular velocity across the spin axis (the
    tilt times the spin), which integrated over the hundreds of radians a sweep turns would read
    as a growing angular stretch (0.3 rad after 1 s at the nominal point, which put the housings'
    2x 2.5x off), while turning both ends together leaves the stretch unchanged. The force keeps
    the full rows (virtual work).
    """

    def __init__(self, p: Mapping[str, float], bare: Rig, model: SweepModel) -> None:
        self.p, lin = p, model.lin
        onto = np.eye(lin.q0.size) if model.basis is None else model.basis
        hub = marker_rows(bare.system, lin, bare.markers["hub"])
        rows = marker_rows(bare.system, lin, bare.markers["coupling"]) - hub         # d(stretch rate) / dq'
        rates = model.rates if model.basis is None else model.basis @ model.rates       # the spin angles
        self.rows = rows @ onto                                                       # d(stretch rate) / dz'
        self.jac = np.where(rates != 0.0, 0.0, rows) @ onto                           # d(stretch) / dz
        hub = hub @ onto
        self.sag = coupling_stretch(bare, lin.q0)
        self.angle = hub[3]                  # the hub's spin angle (0 at the sag, as the rig's hub frame)
        self.active = bool(p["coupling_asymmetry"] > 0.0)

    @functools.cached_property
    def data(self) -> tuple:
        """``(active, (a k_r, a k_a), rows (6, n), J (6, n), s_sag (6,), angle row (n,))``: what the
        compiled :func:`coupling_force` reads."""
        return (self.active, anisotropy_constants(self.p), np.ascontiguousarray(self.rows),
                np.ascontiguousarray(self.jac), np.asarray(self.sag, dtype=float), np.asarray(self.angle, dtype=float))

    def __call__(self, z: Array) -> Array | float:
        """The forces ``f(z)`` (m, n) [N, N m] at the states ``z`` (m, n) (0.0 when the coupling is axisymmetric)."""
        if not self.active:
            return 0.0
        z = np.ascontiguousarray(z, dtype=float)
        f = np.zeros_like(z)
        coupling_forces(z, self.data, f)
        return f
